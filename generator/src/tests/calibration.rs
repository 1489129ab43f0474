//! A sensor's white reference and the calibration a scene fits to a device's readings
//! (`[sensors.X] calibration = "readings.csv"`): what is baked, and every mistake named by file
//! and line.

use spectral_quadrature_spectra::builtin_illuminant;
use std::path::Path;
use std::sync::OnceLock;

use crate::calibration::{self, Readings};
use crate::{derive, Derivation, Error, Settings};

const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../data");
const EXAMPLES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples");

fn d() -> &'static Derivation {
    static D: OnceLock<Derivation> = OnceLock::new();
    D.get_or_init(|| derive(&Settings::new(DATA_DIR)).unwrap())
}

const CHANNELS: [&str; 8] = [
    "F1_415", "F2_445", "F3_480", "F4_515", "F5_555", "F6_590", "F7_630", "F8_680",
];

fn channels() -> Vec<String> {
    CHANNELS.iter().map(|c| c.to_string()).collect()
}

/// A scratch directory for scene files, unique per test.
fn scratch(test: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("sq-calibration-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A scene with the example sensor under C and `extra` lines in its table, written to `dir`
/// with `files` beside it, parsed and resolved.
fn resolve(
    dir: &Path,
    extra: &str,
    files: &[(&str, &str)],
) -> Result<crate::scene::Resolved, Error> {
    for (name, text) in files {
        std::fs::write(dir.join(name), text).unwrap();
    }
    let sensor = Path::new(DATA_DIR).join("sensor_as7341_gaussian.csv");
    let text = format!(
        "displays = [\"SRGB\"]\n[sensors.AS7341]\nfile = {:?}\nlight = \"C\"\n{extra}",
        sensor.display().to_string()
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, &text).unwrap();
    let label = path.display().to_string();
    crate::scene::Scene::parse(&label, &text, Path::new(DATA_DIR))?.resolve(d())
}

/// The error as the build script prints it.
fn message(e: &Error) -> String {
    e.to_string()
}

#[test]
fn a_sensor_bakes_its_white_and_a_calibration_its_fit() {
    let dir = scratch("bakes");
    let plain = resolve(&dir, "", &[]).unwrap();
    assert_eq!(plain.sensors.len(), 1);
    assert!(plain.sensors[0].calibration.is_none());
    let white = &plain.sensors[0].white;
    assert_eq!(white.len(), 8);
    assert!(white.iter().all(|w| *w > 0.0));
    // One white reference: the sensor set's samples of white, which scale its integer form, are
    // the same numbers as the calibration's reference.
    assert_eq!(
        plain.white_samples,
        vec![("AS7341".to_string(), white.clone())]
    );
    // The golden set reads its white as display white (Y = UNIT_SPECTRUM_Y): its weights are
    // exact on the light's white.
    let sensor = crate::user::Sensor::read(
        &Path::new(DATA_DIR).join("sensor_as7341_gaussian.csv"),
        "sensor.csv",
        d().settings.range_nm,
    )
    .unwrap();
    let c = builtin_illuminant(Path::new(DATA_DIR), "C", d().settings.range_nm).unwrap();
    let set = crate::user::sensor_set(d(), "AS7341", "AS7341", &sensor, Some(&c)).unwrap();
    let y: f64 = set.xyz_weights[1]
        .iter()
        .zip(white)
        .map(|(w, r)| w * r)
        .sum();
    // The white condition is a constraint of the fit, met to rounding (measured: 1e-15).
    assert!((y / d().unit_spectrum_y - 1.0).abs() < 1e-12, "{y}");
    let readings =
        std::fs::read_to_string(Path::new(EXAMPLES).join("sensors/as7341_device.csv")).unwrap();
    let with = resolve(
        &dir,
        "calibration = \"device.csv\"\n",
        &[("device.csv", &readings)],
    )
    .unwrap();
    let fit = with.sensors[0].calibration.as_ref().unwrap();
    // The example device's offsets are 100-1500 counts and its gains 0.9-1.1 times the
    // exposure (tests/calibration.rs in the runtime crate checks them against the device).
    assert!(
        fit.dark.iter().all(|d| (50.0..1600.0).contains(d)),
        "{:?}",
        fit.dark
    );
    assert!(
        fit.rms_residual.iter().all(|r| *r < 30.0),
        "{:?}",
        fit.rms_residual
    );
    let src = crate::tests::tables_rs(d(), &[], &with).unwrap();
    assert!(src.contains("pub mod sensors {"));
    assert!(src.contains("pub const AS7341_WHITE: [f32; 8] ="));
    assert!(src.contains("pub const AS7341_CALIBRATION: crate::Calibration<8> ="));
    assert!(src.contains("\"sensors::AS7341_CALIBRATION\""));
    assert!(src.contains("super::checked(crate::Calibration::new("));
    let plain_src = crate::tests::tables_rs(d(), &[], &plain).unwrap();
    assert!(plain_src.contains("pub const AS7341_WHITE") && !plain_src.contains("CALIBRATION"));
}

#[test]
fn the_example_scene_bakes_a_calibration_and_names_its_files() {
    let out = crate::generate(
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")),
        Some(std::ffi::OsStr::new("examples/scenes/sensor.toml")),
    )
    .unwrap();
    assert!(out.tables_rs.contains("pub const AS7341_CALIBRATION"));
    assert!(out.tables_rs.contains("pub const PLANCKIAN_LOCUS"));
    // The readings and the chart they name are inputs with their checksums, and Cargo watches
    // the readings.
    // (The header names a scene's files as the scene does, relative to the crate.)
    let header = &out.tables_rs[..3000];
    assert!(header.contains("//   examples/scenes/../sensors/as7341_device.csv\n//       sha256="));
    assert!(header.contains("//   data/reflectance_colorchecker_ohta.csv\n//       sha256="));
    assert!(out
        .rerun_if_changed
        .iter()
        .any(|p| p.ends_with("scenes/../sensors/as7341_device.csv")));
}

#[test]
fn mistakes_name_the_file_and_line() {
    let dir = scratch("mistakes");
    let header = format!("patch,{}\n", CHANNELS.join(","));
    let row = |name: &str, v: &str| format!("{name},{}\n", [v; 8].join(","));
    let good = format!(
        "# a comment\n{header}{}{}{}",
        row("\"dark skin\"", "100"),
        row("white 9.5 (.05 D)", "900"),
        row("\"neutral 5 (.70 D)\"", "400")
    );
    let cases: Vec<(String, String)> = vec![
        (
            "patch,F2_445,F1_415,F3_480,F4_515,F5_555,F6_590,F7_630,F8_680\n".into(),
            "device.csv:1: the header must name the reflectance column, then the sensor's channels in its order".into(),
        ),
        (
            format!("{header}\"dark skin\",1,2\n"),
            "device.csv:2: 3 fields; a row has the reflectance's name and 8 readings".into(),
        ),
        (
            format!("{header}{}", row("\"dark skin\"", "-1")),
            "device.csv:2: column 2 (F1_415): \"-1\" is not a finite, non-negative reading".into(),
        ),
        (
            format!("{header}{}", row("\"dark skin\"", "x")),
            "device.csv:2: column 2 (F1_415): \"x\" is not a number".into(),
        ),
        (
            format!("{header}{}\n{}", row("a", "1"), row("b", "2")),
            "device.csv:3: empty line inside the readings".into(),
        ),
        (
            format!("{header}{}", row("\"dark skin\"", "1")),
            "device.csv: 1 readings; a calibration needs at least 3".into(),
        ),
        (
            format!("{header}{}{}{}", row("\"dark skin\"", "1"), row("teal", "2"), row("orange", "3")),
            "device.csv:3: \"teal\" is not a reflectance of data/reflectance_colorchecker_ohta.csv".into(),
        ),
        (
            format!(
                "{header}{}{}{}",
                row("\"dark skin\"", "900"),
                row("white 9.5 (.05 D)", "100"),
                row("\"neutral 5 (.70 D)\"", "400")
            ),
            "channel 1: the readings do not grow with what the golden device reads".into(),
        ),
    ];
    for (text, expected) in cases {
        let e = resolve(
            &dir,
            "calibration = \"device.csv\"\n",
            &[("device.csv", &text)],
        )
        .unwrap_err();
        let m = message(&e);
        assert!(m.contains(&expected), "{m}\n  expected: {expected}");
        // Around it, the scene's line that declares the sensor.
        assert!(m.contains("scene.toml:2"), "{m}");
    }
    // The good file resolves.
    resolve(
        &dir,
        "calibration = \"device.csv\"\n",
        &[("device.csv", &good)],
    )
    .unwrap();
    // A missing file names itself.
    let m = message(&resolve(&dir, "calibration = \"missing.csv\"\n", &[]).unwrap_err());
    assert!(m.contains("missing.csv"), "{m}");
    // Scene mistakes: calibration without a light, reflectances without calibration.
    let sensor = Path::new(DATA_DIR).join("sensor_as7341_gaussian.csv");
    let text = format!(
        "[sensors.AS7341]\nfile = {:?}\ncalibration = \"device.csv\"\n",
        sensor.display().to_string()
    );
    let m = message(&crate::scene::Scene::parse("s.toml", &text, Path::new(DATA_DIR)).unwrap_err());
    assert!(
        m.starts_with(
            "s.toml:3: calibration: the readings are of reflectances under the sensor's light"
        ),
        "{m}"
    );
    let text = format!(
        "[sensors.AS7341]\nfile = {:?}\nlight = \"C\"\ncalibration_reflectances = \"chart.csv\"\n",
        sensor.display().to_string()
    );
    let m = message(&crate::scene::Scene::parse("s.toml", &text, Path::new(DATA_DIR)).unwrap_err());
    assert!(
        m.starts_with("s.toml:4: calibration_reflectances without calibration"),
        "{m}"
    );
}

/// The reflectances can come from the scene's own file.
#[test]
fn own_reflectances() {
    let dir = scratch("own");
    let chart = "wavelength_nm,grey,white\n360,0.2,0.9\n830,0.2,0.9\n";
    let readings = format!(
        "patch,{}\ngrey,{}\nwhite,{}\ngrey,{}\n",
        CHANNELS.join(","),
        ["300"; 8].join(","),
        ["1100"; 8].join(","),
        ["302"; 8].join(",")
    );
    let r = resolve(
        &dir,
        "calibration = \"device.csv\"\ncalibration_reflectances = \"chart.csv\"\n",
        &[("device.csv", &readings), ("chart.csv", chart)],
    )
    .unwrap();
    let fit = r.sensors[0].calibration.as_ref().unwrap();
    // Grey 0.2 and white 0.9 read 301 and 1100: dark = 301 − 0.2 · (1100 − 301) / 0.7.
    for k in 0..8 {
        let slope = (1100.0 - 301.0) / (0.7 * r.sensors[0].white[k]);
        let dark = 301.0 - 0.2 * r.sensors[0].white[k] * slope;
        assert!(
            (fit.dark[k] - dark).abs() < 1e-6,
            "{} vs {dark}",
            fit.dark[k]
        );
        assert!((fit.gain[k] * slope - 1.0).abs() < 1e-9);
    }
}

#[test]
fn the_fit_is_exact_on_exact_readings() {
    let golden: Vec<Vec<f64>> = (0..5)
        .map(|j| vec![j as f64, 2.0 * j as f64 + 1.0])
        .collect();
    let device: Vec<Vec<f64>> = golden
        .iter()
        .map(|g| vec![3.0 * g[0] + 10.0, 0.5 * g[1] + 7.0])
        .collect();
    let fit = calibration::fit(&golden, &device).unwrap();
    assert_eq!(fit.dark, [10.0, 7.0]);
    assert_eq!(fit.gain, [1.0 / 3.0, 2.0]);
    assert!(fit.rms_residual.iter().all(|r| *r < 1e-12));
    let flat: Vec<Vec<f64>> = (0..5).map(|_| vec![1.0]).collect();
    assert!(calibration::fit(&flat, &flat)
        .unwrap_err()
        .to_string()
        .contains("channel 1"));
    // The parser on its own.
    let r = Readings::parse("r.csv", "p,a\nx,1\ny,2\nz,3\n", &["a".into()]).unwrap();
    assert_eq!(r.patches, ["x", "y", "z"]);
    assert_eq!(r.lines, [2, 3, 4]);
    let _ = channels();
}
