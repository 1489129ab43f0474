//! Scenes: the build bakes only what a scene names, and mistakes name file, line and choices.

/// The data files the derivation reads (the runtime crate's `data/`).
const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../data");

use crate::scene::Scene;
use crate::{derive, Derivation};
use std::sync::OnceLock;

fn default_derivation() -> &'static Derivation {
    static D: OnceLock<Derivation> = OnceLock::new();
    D.get_or_init(|| derive(&crate::Settings::new(DATA_DIR)).unwrap())
}

fn generate(file: &str, text: &str) -> Result<String, crate::Error> {
    let scene = Scene::parse(file, text, std::path::Path::new(DATA_DIR))?;
    let d = derive(&scene.settings).unwrap();
    let resolved = scene.resolve(&d)?;
    Ok(crate::tests::tables_rs(&d, &[], &resolved).unwrap())
}

/// The number of constants `ALL_TABLES` lists in a generated source (one `size_of` each).
fn baked_constants(source: &str) -> usize {
    let start = source.find("pub static ALL_TABLES").unwrap();
    source[start..].matches("size_of::<").count()
}

#[test]
fn a_minimal_scene_bakes_only_its_set_and_display() {
    let text = "sets = [\"TABLE2_ROW2\"]\ndisplays = [\"SRGB\"]\n";
    let src = generate("minimal.toml", text).unwrap();
    for present in [
        "pub const TABLE2_ROW2: WavelengthSet<4>",
        "pub const SRGB: Display",
        "pub const TABLE2_ROW2_SRGB: FoldedSet<4>",
        "pub const XYZ_TO_AC1C2",
        "pub const AC1C2_TO_XYZ",
        "pub const UNIT_SPECTRUM_Y",
    ] {
        assert!(src.contains(present), "missing {present}");
    }
    for absent in [
        "TABLE2_ROW1",
        "DISPLAY_P3",
        "REC2020",
        "MEYER_1987",
        "A_RULES",
        "C1_RULES",
        "RULES:",
        "MAX_ORDER",
        "SENSITIVITIES",
        "GRID_NM",
        "pub mod rules",
        "A_3",
        "UNIFORM_",
    ] {
        assert!(
            !src.contains(absent),
            "{absent} should not be baked:\n{src}"
        );
    }
    // The default scene bakes everything; the minimal one a few of its constants (11 of 143:
    // the opponent space's six, its set, display, display list, folded and integer set).
    let d = default_derivation();
    let full = crate::tests::tables_rs(
        d,
        &[],
        &Scene::default_scene(std::path::Path::new(DATA_DIR))
            .resolve(d)
            .unwrap(),
    )
    .unwrap();
    assert!(
        baked_constants(&src) * 10 < baked_constants(&full),
        "{} vs {}",
        baked_constants(&src),
        baked_constants(&full)
    );
    assert!(
        src.len() * 10 < full.len(),
        "source {} vs {}",
        src.len(),
        full.len()
    );
}

#[test]
fn extras_transfer_and_named_rules_are_honoured() {
    let text = "sets = [\"AC1C2_3_2_2\", \"A_4\"]\ndisplays = [\"DISPLAY_P3\"]\n[transfer]\nDISPLAY_P3 = \"gamma 2.2\"\n[extras]\nrules = true\n";
    let src = generate("panel.toml", text).unwrap();
    assert!(
        src.contains("pub const AC1C2_3_2_2: WavelengthSet<7>"),
        "{src}"
    );
    assert!(src.contains("pub mod rules") && src.contains("pub const A_4: WavelengthSet<4>"));
    assert!(src.contains("        TransferFunction::Gamma(2.2),\n    ));"));
    assert!(src.contains("pub const A_RULES") && !src.contains("SENSITIVITIES"));
    assert!(src.contains("pub const AC1C2_3_2_2_DISPLAY_P3: FoldedSet<7>"));
    // A per-channel rule is not folded: alone it gives no colour.
    assert!(!src.contains("A_4_DISPLAY_P3"));
}

/// A scene's error with the file and line it names: every scene error names one.
struct Located {
    file: String,
    line: u64,
    error: crate::Error,
}

impl std::fmt::Display for Located {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.error.fmt(f)
    }
}

fn error(text: &str) -> Located {
    let error = generate("scene.toml", text).unwrap_err();
    let (file, line) = error
        .location()
        .unwrap_or_else(|| panic!("the error names no file: {error:?}"));
    Located {
        file: file.into(),
        line,
        error,
    }
}

#[test]
fn mistakes_name_the_file_the_line_and_the_choices() {
    // Unknown set: line 2, with the valid forms and the defined rules.
    let e = error("displays = [\"SRGB\"]\nsets = [\"TABLE3_ROW1\"]\n");
    assert_eq!((e.file.as_str(), e.line), ("scene.toml", 2), "{e}");
    assert!(
        e.to_string().contains("TABLE2_ROW1") && e.to_string().contains("AC1C2_<a>_<c1>_<c2>"),
        "{e}"
    );
    assert!(e.to_string().starts_with("scene.toml:2:"), "{e}");
    // An undefined order says why.
    let e = error("sets = [\n  \"TABLE2_ROW2\",\n  \"AC1C2_3_3_1\",\n]\n");
    assert_eq!(e.line, 3, "{e}");
    assert!(
        e.to_string().contains("C1 order 3 is undefined (outside"),
        "{e}"
    );
    let e = error("sets = [\"C2_4\"]\n");
    assert!(
        e.to_string().contains("C2 order 4 is undefined (complex"),
        "{e}"
    );
    // A shared set out of range lists the shared-set forms and lights, not the rules.
    let e = error("sets = [\"KQ_C_40\"]\n");
    assert_eq!(e.line, 1, "{e}");
    let shown = e.to_string();
    assert!(
        shown.contains("shared sets have 3 to 32 wavelengths"),
        "{e}"
    );
    assert!(
        shown.contains("KQ_<light>_<n>") && shown.contains("F11"),
        "{e}"
    );
    assert!(
        !shown.contains("defined rules") && !shown.contains("C2_15"),
        "{e}"
    );
    // An unknown light: the built-in lights listed once, by the error (not again by the hint).
    let e = error("sets = [\"KQ_NOPE_6\"]\n");
    assert!(
        e.to_string().contains("NOPE is not a built-in illuminant"),
        "{e}"
    );
    assert!(e.to_string().contains(": A, C, D50"), "{e}");
    assert_eq!(e.to_string().matches("LED_B3").count(), 1, "{e}");
    assert!(!e.to_string().contains("defined rules"), "{e}");
    // Unknown display.
    let e = error("sets = [\"TABLE2_ROW2\"]\ndisplays = [\"SRGB\", \"CRT\"]\n");
    assert_eq!(e.line, 2);
    assert!(
        e.to_string().contains("unknown display \"CRT\"") && e.to_string().contains("DISPLAY_P3"),
        "{e}"
    );
    // Unknown key: the toml error lists the valid keys.
    let e = error("sets = [\"TABLE2_ROW2\"]\n\ncolour = true\n");
    assert_eq!(e.line, 3, "{e}");
    assert!(
        e.to_string().contains("colour") && e.to_string().contains("displays"),
        "{e}"
    );
    // Unknown observer and transfer function.
    let e = error("observer = \"cie1931\"\nsets = [\"TABLE2_ROW2\"]\n");
    assert_eq!(e.line, 1);
    assert!(e.to_string().contains("cie1931_2deg"), "{e}");
    let e =
        error("sets = [\"TABLE2_ROW2\"]\ndisplays = [\"SRGB\"]\n[transfer]\nSRGB = \"gamma -1\"\n");
    assert_eq!(e.line, 4);
    assert!(e.to_string().contains("gamma <γ>"), "{e}");
    // No sets at all.
    assert!(error("displays = [\"SRGB\"]\n")
        .to_string()
        .contains("names no sets"));
    // Orders beyond the derivation's maximum.
    let e = error("sets = [\"A_40\"]\n");
    assert!(e.to_string().contains("1..=16"), "{e}");
}

#[test]
fn bad_budgets_are_refused_with_their_line() {
    for (value, word) in [
        ("0.0", "bad budget"),
        ("-1.0", "bad budget"),
        ("nan", "bad budget"),
        ("inf", "bad budget"),
    ] {
        let text = format!("displays = [\"SRGB\"]\n[plan]\nmax_delta_e00 = {value}\nreflectances = \"a.csv\"\nilluminants = \"b.csv\"\n");
        let e = error(&text);
        assert_eq!(e.line, 3, "{value}: {e}");
        assert!(e.to_string().contains(word), "{e}");
    }
    let e = error("[plan]\nmax_delta_e00 = 1.0\nmetric = \"median\"\nreflectances = \"a.csv\"\nilluminants = \"b.csv\"\n");
    assert_eq!(e.line, 3);
    assert!(e.to_string().contains("mean, max"), "{e}");
    let e = error("[plan]\nmax_delta_e00 = 1.0\nreflectances = \"a.csv\"\n");
    assert!(
        e.to_string().contains("needs reflectances and illuminants"),
        "{e}"
    );
    // A missing spectra file is named.
    let e = error(
        "[plan]\nmax_delta_e00 = 1.0\nreflectances = \"no-such.csv\"\nilluminants = \"b.csv\"\n",
    );
    assert!(e.to_string().contains("no-such.csv"), "{e}");
}

#[test]
fn every_scene_in_examples_parses_and_resolves() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/scenes");
    let mut n = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let text = std::fs::read_to_string(&path).unwrap();
            generate(&path.display().to_string(), &text).unwrap_or_else(|e| panic!("{e}"));
            n += 1;
        }
    }
    assert!(n >= 3, "{n} scenes");
}

#[test]
fn a_scenes_light_group_is_baked_for_each_display_and_its_mistakes_name_their_line() {
    // The default scene's group (D65, A, F11, LED_B2 at 8, cached), under another name, with
    // its lights in the scene's order.
    let source = generate(
        "scene.toml",
        "displays = [\"SRGB\", \"REC2020\"]\n[groups.ROOM]\nlights = [\"D65\", \"A\", \"F11\", \"LED_B2\"]\nwavelengths = 8\n",
    )
    .unwrap();
    for display in ["SRGB", "REC2020"] {
        assert!(
            source.contains(&format!("pub const ROOM_{display}: LightGroupSet<8, 4> =")),
            "{display}"
        );
    }
    assert!(source.contains("        [\"D65\", \"A\", \"F11\", \"LED_B2\"],\n"));
    assert!(source.contains("pub const NAMES: [&str; 2] = [\"ROOM_SRGB\", \"ROOM_REC2020\"];"));
    let group = |body: &str| format!("displays = [\"SRGB\"]\n[groups.ROOM]\n{body}");
    for (body, line, message) in [
        (
            "lights = [\"D65\"]\nwavelengths = 8\n",
            3,
            "a group has two or more, or one with training = \"bounces\"",
        ),
        (
            "lights = [\"D65\", \"NOPE\"]\nwavelengths = 8\n",
            3,
            "unknown light \"NOPE\"",
        ),
        (
            "lights = [\"D65\", \"D65\"]\nwavelengths = 8\n",
            3,
            "D65 is named twice",
        ),
        (
            "lights = [\"D65\", \"A\"]\nwavelengths = 40\n",
            4,
            "a light group has 3 to 16",
        ),
        (
            "lights = [\"D65\", \"A\"]\nwavelengths = 8\nobjective = \"median\"\n",
            5,
            "valid: \"mean\", \"worst\"",
        ),
        ("lights = [\"D65\", \"A\"]\n", 2, "wavelengths"),
        (
            "lights = [\"D65\", \"A\"]\nwavelengths = 8\ntraining = \"twice\"\n",
            5,
            "valid: \"reflectances\", \"bounces\"",
        ),
    ] {
        let e = error(&group(body));
        assert_eq!(
            (e.file.as_str(), e.line),
            ("scene.toml", line),
            "{body}: {e}"
        );
        assert!(e.to_string().contains(message), "{body}: {e}");
    }
    // A group's name is a scene's own name: not twice, not a catalogue form.
    let e = error("displays = [\"SRGB\"]\n[lights]\nROOM = \"x.csv\"\n[groups.ROOM]\nlights = [\"D65\", \"A\"]\nwavelengths = 8\n");
    assert!(e.to_string().contains("declared twice"), "{e}");
    let e = error(
        "displays = [\"SRGB\"]\n[groups.KQ_ROOM]\nlights = [\"D65\", \"A\"]\nwavelengths = 8\n",
    );
    assert!(e.to_string().contains("catalogue form"), "{e}");
}

#[test]
fn a_group_fitted_for_bounced_light_is_searched_and_baked_as_such() {
    // Not in the node cache (the default fit is on reflectances as they are): searched here, on
    // the crate's reflectances and their bounce forms.
    let source = generate(
        "scene.toml",
        "displays = [\"SRGB\"]\n[groups.BOUNCED]\nlights = [\"D65\", \"A\"]\nwavelengths = 4\ntraining = \"bounces\"\n",
    )
    .unwrap();
    assert!(source.contains("pub const BOUNCED_SRGB: LightGroupSet<4, 2> ="));
    // One light fitted for bounced light is a set of its own (one light fitted on reflectances
    // as they are is its folded set, refused above).
    let source = generate(
        "scene.toml",
        "displays = [\"SRGB\"]\n[groups.C_BOUNCED]\nlights = [\"C\"]\nwavelengths = 4\ntraining = \"bounces\"\n",
    )
    .unwrap();
    assert!(source.contains("pub const C_BOUNCED_SRGB: LightGroupSet<4, 1> ="));
    // The doc comment, its lines joined.
    assert!(source
        .replace("\n    /// ", " ")
        .contains("on the crate's reflectances and their bounce forms"));
}
