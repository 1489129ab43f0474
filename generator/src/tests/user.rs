//! Sets for what the user has: a light by file, fixed wavelengths, a sensor. Judged on the
//! ColorChecker (never in training), mean ΔE00 against the full 1 nm integration.

use std::path::Path;
use std::sync::OnceLock;

use crate::user::{fixed_set, least_squares, sensor_set, Sensor, UserLight};
use crate::{derive, Derivation, Error, Settings};
use spectral_quadrature_spectra::{
    builtin_illuminant, surfaces_under_lights, Curve, EvalSet, Reference, Spectra, Stimulus,
};

const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../data");
const SENSOR_FILE: &str = "sensor_as7341_gaussian.csv";

fn d() -> &'static Derivation {
    static D: OnceLock<Derivation> = OnceLock::new();
    D.get_or_init(|| derive(&Settings::new(DATA_DIR)).unwrap())
}

fn light(name: &str) -> Curve {
    builtin_illuminant(Path::new(DATA_DIR), name, d().settings.range_nm).unwrap()
}

fn colorchecker_under(l: &Curve) -> Vec<Stimulus> {
    let cc = Spectra::builtin(
        Path::new(DATA_DIR),
        "data/reflectance_colorchecker_ohta.csv",
    )
    .and_then(|s| s.curves(d().settings.range_nm))
    .unwrap();
    surfaces_under_lights(&cc, std::slice::from_ref(l))
}

fn mean_de00(set: &EvalSet, stimuli: &[Stimulus]) -> f64 {
    let full = d()
        .observer
        .full_integration(d().settings.range_nm, 1.0)
        .unwrap();
    Reference::new(full, stimuli)
        .errors(set, stimuli)
        .mean_de00()
}

fn sensor() -> Sensor {
    let path = Path::new(DATA_DIR).join(SENSOR_FILE);
    Sensor::read(&path, SENSOR_FILE, d().settings.range_nm).unwrap()
}

/// A scratch directory for scene files, unique per test.
fn scratch(test: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("sq-user-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Parses and resolves a scene written to `dir/scene.toml`.
fn scene(dir: &Path, text: &str) -> Result<crate::scene::Resolved, Error> {
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let label = path.display().to_string();
    crate::scene::Scene::parse(&label, text, Path::new(DATA_DIR))?.resolve(d())
}

#[test]
fn fixed_bin_centres_beat_bin_sums_under_every_light() {
    // The bin centres of UNIFORM_<n> with the best weights for them (the light folded in) are
    // at least as good as the bin sums on the same wavelengths, under every light, and better
    // at N = 8 under C. Measured: N=8 under C, 1.248 against 1.343; the largest margin is
    // under F11 (1.095 against 5.075 at N = 8).
    for n in [4usize, 8, 16] {
        let uniform = d().observer.uniform_set(d().settings.range_nm, n);
        for name in ["C", "D65", "A", "F11"] {
            let l = light(name);
            let stimuli = colorchecker_under(&l);
            let bins = mean_de00(&uniform, &stimuli);
            let folded = fixed_set(d(), "FIXED", &uniform.wavelengths_nm, Some(&l)).unwrap();
            let radiance = fixed_set(d(), "FIXED", &uniform.wavelengths_nm, None).unwrap();
            let (f, r) = (
                mean_de00(&folded.eval, &stimuli),
                mean_de00(&radiance.eval, &stimuli),
            );
            eprintln!(
                "N={n} {name}: bin sums {bins:.3}, fixed radiance {r:.3}, fixed folded {f:.3}"
            );
            assert_eq!(folded.wavelengths_nm, uniform.wavelengths_nm);
            assert!(f <= bins, "N={n} under {name}: fixed {f} > bin sums {bins}");
            if n == 8 && name == "C" {
                assert!(f < bins, "N=8 under C: fixed {f} is not better than {bins}");
            }
        }
    }
}

#[test]
fn the_example_sensor_under_c_is_within_a_quarter_of_a_delta_e() {
    let s = sensor();
    assert_eq!(s.channels.len(), 8);
    assert_eq!(
        s.peaks_nm(d().settings.range_nm),
        [415.0, 445.0, 480.0, 515.0, 555.0, 590.0, 630.0, 680.0]
    );
    let c = light("C");
    let stimuli = colorchecker_under(&c);
    let fitted = sensor_set(d(), "AS7341", "AS7341", &s, Some(&c)).unwrap();
    let tcs = Spectra::builtin(Path::new(DATA_DIR), crate::shared::TRAINING_FILE)
        .and_then(|s| s.curves(d().settings.range_nm))
        .unwrap();
    let ls = least_squares(d(), "LS", &s, &c, &tcs).unwrap().unwrap();
    let (prior, plain) = (mean_de00(&fitted.eval, &stimuli), mean_de00(&ls, &stimuli));
    eprintln!(
        "sensor under C on the ColorChecker: prior {prior:.3}, least squares on the TCS {plain:.3}"
    );
    // The target, and the prior is no worse than the plain fit (measured: 0.100, 0.193).
    assert!(prior <= 0.25, "{prior}");
    assert!(
        prior <= plain,
        "prior {prior} worse than least squares {plain}"
    );
    // The white is exact: a reflectance of 1 under C reads back as C's own XYZ.
    let white = |set: &EvalSet| set.xyz(|nm| c.at(nm));
    let full = d()
        .observer
        .full_integration(d().settings.range_nm, 1.0)
        .unwrap();
    let (w, exact) = (white(&fitted.eval), white(&full));
    for k in 0..3 {
        // The constraint holds to the LU solve's rounding (measured 1e-15 relative); the grid
        // sums of the channel rows in f64 add a few ε · 400.
        assert!(
            (w[k] - exact[k]).abs() <= 1e-9 * exact[k],
            "{w:?} vs {exact:?}"
        );
    }
}

#[test]
fn a_light_by_file_gives_the_built_in_lights_set_to_the_last_digit() {
    let text = std::fs::read_to_string(Path::new(DATA_DIR).join("illuminant_F11.csv")).unwrap();
    let user = UserLight::parse("MY_F11", "copy.csv", &text, d().settings.range_nm).unwrap();
    let mine = crate::catalog::resolve_with(d(), "KQ_MY_F11_6", &[user]).unwrap();
    let builtin = crate::catalog::resolve(d(), "KQ_F11_6").unwrap();
    assert_eq!(mine.wavelengths_nm, builtin.wavelengths_nm);
    assert_eq!(mine.weights, builtin.weights, "bit for bit");
    assert_eq!(mine.light.as_deref(), Some("MY_F11"));
}

#[test]
fn a_scene_bakes_its_lights_fixed_wavelengths_and_sensors() {
    let dir = scratch("scene");
    std::fs::copy(
        Path::new(DATA_DIR).join("illuminant_LED_B3.csv"),
        dir.join("shop.csv"),
    )
    .unwrap();
    std::fs::copy(
        Path::new(DATA_DIR).join(SENSOR_FILE),
        dir.join("sensor.csv"),
    )
    .unwrap();
    let r = scene(
        &dir,
        "displays = [\"SRGB\"]\nsets = [\"KQ_SHOP_4\"]\n[lights]\nSHOP = \"shop.csv\"\n[fixed.HERO]\nwavelengths_nm = [450, 550, 600.5, 650]\nlight = \"SHOP\"\n[sensors.CHIP]\nfile = \"sensor.csv\"\n",
    )
    .unwrap();
    let names: Vec<(&str, Option<&str>, Option<&str>)> = r
        .colour_sets
        .iter()
        .map(|s| (s.name.as_str(), s.light.as_deref(), s.sensor.as_deref()))
        .collect();
    assert_eq!(
        names,
        [
            ("KQ_SHOP_4", Some("SHOP"), None),
            ("HERO", Some("SHOP"), None),
            ("CHIP", None, Some("CHIP"))
        ]
    );
    assert_eq!(
        r.colour_sets[1].wavelengths_nm,
        [450.0, 550.0, 600.5, 650.0]
    );
    let src = crate::tests::tables_rs(d(), &[], &r).unwrap();
    assert!(src.contains("pub const CHIP: WavelengthSet<8>"), "{src}");
    // The struct literal laid out as rustfmt would, one field a line.
    let flat: String = src.split_whitespace().collect();
    assert!(flat.contains("Samples::Readings{sensor:\"CHIP\",light:None,},"));
    assert!(src.contains("pub const HERO_SRGB: FoldedSet<4>"));
    assert!(src.contains("Samples::Reflectance { light: \"SHOP\" }"));
}

/// The scene's error, with the line it names and its text.
fn scene_error(test: &str, text: &str, files: &[(&str, &str)]) -> (u64, String) {
    let dir = scratch(test);
    for (name, body) in files {
        std::fs::write(dir.join(name), body).unwrap();
    }
    let e = scene(&dir, text).unwrap_err();
    let (file, line) = e.location().expect("a scene error names the scene");
    assert!(file.ends_with("scene.toml"), "{e}");
    (line, e.to_string())
}

#[test]
fn mistakes_in_the_users_inputs_name_the_file_and_line() {
    // A sensor file that does not cover the range: the scene's line, then the file's line.
    let short: String = std::iter::once("wavelength_nm,a,b".to_string())
        .chain((400..=700).map(|nm| format!("{nm},1,0.5")))
        .collect::<Vec<_>>()
        .join("\n");
    let (line, msg) = scene_error(
        "short",
        "displays = [\"SRGB\"]\n[sensors.CHIP]\nfile = \"s.csv\"\n",
        &[("s.csv", &short)],
    );
    assert_eq!(line, 2, "{msg}");
    assert!(msg.contains("s.csv:2: the data cover 400-700 nm"), "{msg}");
    // A channel that reads nothing.
    let zero: String = std::iter::once("wavelength_nm,a,dead".to_string())
        .chain((380..=780).map(|nm| format!("{nm},1,0")))
        .collect::<Vec<_>>()
        .join("\n");
    let (line, msg) = scene_error(
        "zero",
        "displays = [\"SRGB\"]\n\n[sensors.CHIP]\nfile = \"s.csv\"\n",
        &[("s.csv", &zero)],
    );
    assert_eq!(line, 3, "{msg}");
    assert!(msg.contains("channel 2 (dead, column 3) is zero"), "{msg}");
    // Duplicate names across the tables.
    let (line, msg) = scene_error(
        "dup",
        "[lights]\nX = \"a.csv\"\n[fixed.X]\nwavelengths_nm = [500]\n",
        &[],
    );
    assert_eq!(line, 3, "{msg}");
    assert!(msg.contains("X is declared twice"), "{msg}");
    // A fixed wavelength outside the range.
    let (line, msg) = scene_error(
        "outside",
        "[fixed.HERO]\nwavelengths_nm = [450, 800]\n",
        &[],
    );
    assert_eq!(line, 1, "{msg}");
    assert!(
        msg.contains("HERO: wavelength 800 nm is outside the range 380-770 nm"),
        "{msg}"
    );
    // Wavelengths out of order, an unknown light, a bad name, a catalogue name.
    let (_, msg) = scene_error("order", "[fixed.HERO]\nwavelengths_nm = [550, 450]\n", &[]);
    assert!(msg.contains("strictly increasing"), "{msg}");
    let (line, msg) = scene_error(
        "light",
        "[fixed.HERO]\nwavelengths_nm = [450]\nlight = \"SUN\"\n",
        &[],
    );
    assert_eq!(line, 3, "{msg}");
    assert!(
        msg.contains("unknown light \"SUN\"") && msg.contains("F11"),
        "{msg}"
    );
    let (_, msg) = scene_error("case", "[fixed.hero]\nwavelengths_nm = [450]\n", &[]);
    assert!(msg.contains("not upper snake case"), "{msg}");
    let (_, msg) = scene_error("form", "[fixed.KQ_9]\nwavelengths_nm = [450]\n", &[]);
    assert!(msg.contains("may not start with KQ_"), "{msg}");
    // A light file with two spectra, and one missing.
    let (line, msg) = scene_error(
        "two",
        "sets = [\"KQ_SHOP_4\"]\n[lights]\nSHOP = \"l.csv\"\n",
        &[("l.csv", "wavelength_nm,a,b\n380,1,1\n780,1,1\n")],
    );
    assert_eq!(line, 3, "{msg}");
    assert!(
        msg.contains("l.csv:1: a light file has one spectrum"),
        "{msg}"
    );
    let (_, msg) = scene_error(
        "missing",
        "sets = [\"KQ_SHOP_4\"]\n[lights]\nSHOP = \"none.csv\"\n",
        &[],
    );
    assert!(
        msg.contains("none.csv") && msg.contains("cannot read"),
        "{msg}"
    );
    // A misspelt light in a set name: the built-in lights and the scene's own, each once.
    let (line, msg) = scene_error(
        "misspelt",
        "sets = [\"KQ_WARMLED_6\"]\n[lights]\nWARM_LED = \"l.csv\"\n",
        &[("l.csv", "wavelength_nm,power\n380,1\n780,1\n")],
    );
    assert_eq!(line, 1, "{msg}");
    assert!(
        msg.contains("WARMLED is neither a built-in illuminant")
            && msg.contains("nor a light of the scene's [lights] (WARM_LED)"),
        "{msg}"
    );
    assert_eq!(msg.matches("LED_B3").count(), 1, "{msg}");
    assert_eq!(msg.matches("KQ_WARMLED_6").count(), 1, "{msg}");
    // A light named like a built-in one.
    let (_, msg) = scene_error(
        "builtin",
        "[lights]\nF11 = \"l.csv\"\n[fixed.H]\nwavelengths_nm = [450]\n",
        &[],
    );
    assert!(msg.contains("built-in illuminant's name"), "{msg}");
}

/// `text` with the value at (1-based `line`, `column`) replaced by `value`.
fn with_value(text: &str, line: usize, column: usize, value: &str) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let mut fields: Vec<&str> = lines[line - 1].split(',').collect();
    fields[column - 1] = value;
    lines[line - 1] = fields.join(",");
    lines.join("\n") + "\n"
}

#[test]
fn negative_values_in_a_scenes_files_follow_the_readers_rule() {
    let dir = scratch("negatives");
    let led = std::fs::read_to_string(Path::new(DATA_DIR).join("illuminant_LED_B3.csv")).unwrap();
    let chip = std::fs::read_to_string(Path::new(DATA_DIR).join(SENSOR_FILE)).unwrap();
    // Rounding noise in the light (line 2, 380 nm, where it is 0) and in the sensor's fourth
    // channel (line 3, 381 nm, column 5): read as 0, one warning per file through the build.
    std::fs::write(dir.join("shop.csv"), with_value(&led, 2, 2, "-3e-17")).unwrap();
    std::fs::write(dir.join("chip.csv"), with_value(&chip, 3, 5, "-7e-18")).unwrap();
    let text = "displays = [\"SRGB\"]\n[lights]\nSHOP = \"shop.csv\"\n[fixed.HERO]\nwavelengths_nm = [450, 550, 650]\nlight = \"SHOP\"\n[sensors.CHIP]\nfile = \"chip.csv\"\n";
    let scene_path = dir.join("scene.toml");
    std::fs::write(&scene_path, text).unwrap();
    let crate_dir = Path::new(DATA_DIR).parent().unwrap();
    let out = crate::generate(crate_dir, Some(scene_path.as_os_str())).unwrap();
    assert_eq!(out.warnings.len(), 2, "{:?}", out.warnings);
    assert!(
        out.warnings[0].ends_with("shop.csv:2: column 2 (relative_power): 1 negative value read as 0, the first here (-3e-17); all within the tolerance (1e-6 × the file's largest value 18.87), as rounding noise"),
        "{}",
        out.warnings[0]
    );
    assert!(
        out.warnings[1].contains("chip.csv:3: column 5 (F4_515): 1 negative value read as 0"),
        "{}",
        out.warnings[1]
    );
    // A real negative in the light: the scene's line, then the file's line and column.
    std::fs::write(dir.join("shop.csv"), with_value(&led, 30, 2, "-0.2")).unwrap();
    let e = scene(&dir, text).unwrap_err();
    assert_eq!(e.location().map(|(_, line)| line), Some(3), "{e}");
    let msg = e.to_string();
    assert!(
        msg.contains("shop.csv:30: column 2 (relative_power): -0.2 is negative"),
        "{msg}"
    );
    assert!(msg.contains("clamp_negatives = true"), "{msg}");
    // The scene opts in: read as 0, and still said.
    let r = scene(&dir, &format!("clamp_negatives = true\n{text}")).unwrap();
    assert_eq!(r.warnings.len(), 2, "{:?}", r.warnings);
    let light = &r.warnings[0];
    assert_eq!((light.count, light.beyond_tolerance), (1, 1));
    assert_eq!((light.first.line, light.first.column), (30, 2));
    assert!(light.to_string().contains("clamped as asked"), "{light}");
    // The light as a set sees 0 there: the clamped file gives the set of the file with a 0.
    std::fs::write(dir.join("shop.csv"), with_value(&led, 30, 2, "0")).unwrap();
    let zero = scene(&dir, text).unwrap();
    assert_eq!(
        zero.warnings.len(),
        1,
        "only the sensor's noise: {:?}",
        zero.warnings
    );
    assert_eq!(r.colour_sets, zero.colour_sets);
}

#[test]
fn the_planner_considers_folded_fixed_and_sensor_sets() {
    // ColorChecker under C (a file whose light is named C), a budget no catalogue set of up to 8
    // wavelengths meets: the planner picks among the folded shared sets and the scene's own.
    let dir = scratch("plan");
    let c = std::fs::read_to_string(Path::new(DATA_DIR).join("illuminant_C.csv")).unwrap();
    let c = c.replacen("relative_power", "C", 1);
    assert!(c.starts_with("wavelength_nm,C\n"), "{}", &c[..40]);
    std::fs::write(dir.join("c.csv"), c).unwrap();
    std::fs::copy(
        Path::new(DATA_DIR).join(SENSOR_FILE),
        dir.join("sensor.csv"),
    )
    .unwrap();
    std::fs::copy(
        Path::new(DATA_DIR).join("reflectance_colorchecker_ohta.csv"),
        dir.join("cc.csv"),
    )
    .unwrap();
    let r = scene(
        &dir,
        "displays = [\"SRGB\"]\n[plan]\nmax_delta_e00 = 0.15\nreflectances = \"cc.csv\"\nilluminants = \"c.csv\"\n[sensors.CHIP]\nfile = \"sensor.csv\"\nlight = \"C\"\n",
    )
    .unwrap();
    let planned = r.planned.expect("a plan");
    eprintln!("{planned}");
    let chosen = planned.split(' ').next().unwrap();
    assert!(
        chosen.starts_with("KQ_C_") || chosen == "CHIP",
        "chose {chosen}: {planned}"
    );
    // The chosen set is baked once, the sensor set always.
    let names: Vec<&str> = r.colour_sets.iter().map(|s| s.name.as_str()).collect();
    assert!(
        names.contains(&"CHIP") && names.contains(&chosen),
        "{names:?}"
    );
    assert_eq!(names.iter().filter(|n| **n == chosen).count(), 1);
}
