//! Scene files: arbitrary bytes → text (converted with `String::from_utf8_lossy`, so every
//! input is parsed; invalid UTF-8 becomes U+FFFD, which also exercises multi-byte characters
//! next to the spans that error lines are computed from) → `Scene::parse("fuzz.toml", text,
//! data_dir)`. The derivation is never run on the parsed scene (it takes seconds); observers
//! other than the default are read from the runtime crate's `data/`, as a build would.
//!
//! Checked: no panic, hang or unbounded memory, whatever the text. An error names the file
//! (`file == "fuzz.toml"`, its `Display` starts with `fuzz.toml:`, and with `fuzz.toml:<line>: `
//! when it has a line) and its line, when non-zero, is a line of the text (1..=lines, one more
//! for a position at the very end). An accepted scene:
//! - is not the default scene and names the file;
//! - reads data from `data_dir`; its settings are the observer's defaults
//!   (`Settings::for_observer`) except `range_nm` and `step_nm`;
//! - has a finite `range_nm` with lo < hi, and a finite, positive `step_nm`;
//! - names at least one set or has a `[plan]`; every set's line is a line of the text;
//! - uses each display once, every one a standard display (primaries, white point, doc as the
//!   default scene's) with a transfer function that is sRGB, linear or a finite positive γ;
//! - has a plan, if any, with a finite positive budget, a line of the text, and either an
//!   emission file or both reflectances and illuminants (not both kinds).
//!
//! A dictionary of the scene keys and names helps reach accepted scenes quickly:
//! `cargo +nightly fuzz run scene -- -dict=fuzz/fuzz_targets/scene.dict`.
#![no_main]

use spectral_quadrature_spectra::builtin_lights;
use std::path::Path;
use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use spectral_quadrature_generator::display::{DisplaySpec, Transfer};
use spectral_quadrature_generator::scene::Scene;
use spectral_quadrature_generator::{Error, ObserverId, Settings};

const FILE: &str = "fuzz.toml";

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let data_dir = Path::new(common::DATA_DIR);
    match Scene::parse(FILE, &text, data_dir) {
        Err(e) => check_error(&e, &text),
        Ok(scene) => check_scene(&scene, &text, data_dir),
    }
});

/// The largest line number a position in `text` can have: its lines, plus one for the end of
/// a text that ends with a newline (and line 1 of an empty text).
fn max_line(text: &str) -> usize {
    text.lines().count() + 1
}

fn check_line(what: &str, line: usize, text: &str) {
    assert!(
        (1..=max_line(text)).contains(&line),
        "{what}: line {line} is not a line of the text ({} lines): {text:?}",
        text.lines().count()
    );
}

fn check_error(e: &Error, text: &str) {
    let shown = e.to_string();
    let Some((file, line)) = e.location() else {
        panic!("a scene error names no file: {e:?}");
    };
    let line = line as usize;
    assert_eq!(file, FILE, "the error names another file: {shown}");
    assert!(
        shown.starts_with(&format!("{FILE}:")),
        "the error does not start with the file: {shown:?}"
    );
    if line != 0 {
        check_line(&format!("error {shown:?}"), line, text);
        assert!(
            shown.starts_with(&format!("{FILE}:{}: ", line)),
            "the error does not start with file:line: {shown:?}"
        );
    } else {
        assert!(
            shown.starts_with(&format!("{FILE}: ")),
            "the error does not start with \"file: \": {shown:?}"
        );
    }
}

/// Whether `name` can be a set or light name in generated code, as the scene parser's error
/// states the rule (upper snake case: A-Z, 0-9, _; a letter first), written here independently
/// of the parser's own check.
fn is_const_name(name: &str) -> bool {
    let mut chars = name.chars();
    chars.next().is_some_and(|c| c.is_ascii_uppercase())
        && chars.all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_')
}

/// Each observer's default settings (reading `data_dir`), once per process.
fn observer_defaults(data_dir: &Path) -> &'static [Settings] {
    static DEFAULTS: OnceLock<Vec<Settings>> = OnceLock::new();
    DEFAULTS.get_or_init(|| {
        ObserverId::ALL
            .iter()
            .map(|&o| {
                Settings::for_observer(o, data_dir)
                    .unwrap_or_else(|e| panic!("the default settings of {}: {e}", o.name()))
            })
            .collect()
    })
}

fn check_scene(scene: &Scene, text: &str, data_dir: &Path) {
    let ctx = || format!("accepted scene {scene:?} from {text:?}");
    assert_eq!(scene.file, FILE, "{}", ctx());
    assert!(
        !scene.is_default,
        "a parsed scene is the default: {}",
        ctx()
    );

    // Settings: the observer's defaults, with the scene's range and step.
    let s = &scene.settings;
    let k = ObserverId::ALL
        .iter()
        .position(|&o| o == s.observer)
        .expect("an observer of ObserverId::ALL");
    let expect = Settings {
        range_nm: s.range_nm,
        step_nm: s.step_nm,
        ..observer_defaults(data_dir)[k].clone()
    };
    assert_eq!(
        *s,
        expect,
        "settings other than range and step differ from the observer's defaults: {}",
        ctx()
    );
    let [lo, hi] = s.range_nm;
    assert!(
        lo.is_finite() && hi.is_finite() && lo < hi,
        "range_nm = [{lo}, {hi}] accepted: {}",
        ctx()
    );
    assert!(
        s.step_nm.is_finite() && s.step_nm > 0.0,
        "step_nm = {} accepted: {}",
        s.step_nm,
        ctx()
    );

    // Something to bake.
    let own = &scene.user;
    assert!(
        !scene.sets.is_empty()
            || scene.plan.is_some()
            || !own.fixed.is_empty()
            || !own.sensors.is_empty(),
        "neither sets, a plan, fixed nor sensor sets: {}",
        ctx()
    );
    // The scene's own inputs: const names, each once, lines inside the text, and every light
    // they use declared or built in.
    let mut names: Vec<&str> = Vec::new();
    for (name, line) in own
        .lights
        .iter()
        .map(|l| (&l.name, l.line))
        .chain(own.fixed.iter().map(|f| (&f.name, f.line)))
        .chain(own.sensors.iter().map(|s| (&s.name, s.line)))
    {
        assert!(is_const_name(name), "name {name:?} accepted: {}", ctx());
        assert!(!names.contains(&name.as_str()), "{name} twice: {}", ctx());
        names.push(name);
        check_line(&format!("{name}"), line, text);
    }
    let builtin = builtin_lights();
    for light in own
        .fixed
        .iter()
        .map(|f| &f.light)
        .chain(own.sensors.iter().map(|s| &s.light))
        .flatten()
    {
        assert!(
            builtin.contains(&light.as_str()) || own.lights.iter().any(|l| &l.name == light),
            "unknown light {light:?} accepted: {}",
            ctx()
        );
    }
    for (name, line) in &scene.sets {
        check_line(&format!("set {name:?}"), *line, text);
    }

    // Displays: standard ones (the default scene has every one), each once, with a valid
    // transfer function.
    let standard = Scene::default_scene(data_dir).displays;
    for (i, d) in scene.displays.iter().enumerate() {
        assert!(
            !scene.displays[..i].iter().any(|o| o.name == d.name),
            "display {} listed twice: {}",
            d.name,
            ctx()
        );
        let base = standard
            .iter()
            .find(|b| b.name == d.name)
            .unwrap_or_else(|| panic!("display {} is not a standard one: {}", d.name, ctx()));
        let same_but_transfer = DisplaySpec {
            transfer: base.transfer.clone(),
            ..d.clone()
        };
        assert_eq!(
            &same_but_transfer,
            base,
            "display {} differs from the standard one in more than its transfer: {}",
            d.name,
            ctx()
        );
        match d.transfer {
            Transfer::Srgb | Transfer::Linear => {}
            Transfer::Gamma(g) => assert!(
                g.is_finite() && g > 0.0,
                "display {} has gamma {g}: {}",
                d.name,
                ctx()
            ),
        }
    }

    if let Some(p) = &scene.plan {
        assert!(
            p.max_delta_e00.is_finite() && p.max_delta_e00 > 0.0,
            "plan budget {} accepted: {}",
            p.max_delta_e00,
            ctx()
        );
        check_line("[plan]", p.line, text);
        let surfaces = p.emission.is_none() && p.reflectances.is_some() && p.illuminants.is_some();
        let lights = p.emission.is_some() && p.reflectances.is_none() && p.illuminants.is_none();
        assert!(
            surfaces || lights,
            "plan needs either emission or reflectances and illuminants: {}",
            ctx()
        );
    }
}
