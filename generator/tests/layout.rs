//! The generated `tables.rs` of the default scene and of every example scene is laid out as
//! rustfmt lays it out: at most 100 columns, and unchanged by `rustfmt --check --edition 2021`
//! where rustfmt is installed (the runtime's `tests/codegen.rs` checks the tables it baked).

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The runtime crate (its `data/` and `examples/scenes/`).
fn crate_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// `(name, tables.rs)` for the default scene and each example scene.
fn every_scene() -> Vec<(String, String)> {
    let mut scenes: Vec<PathBuf> = std::fs::read_dir(crate_dir().join("examples/scenes"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    scenes.sort();
    assert!(scenes.len() >= 5, "{scenes:?}");
    let mut out = vec![(
        "default".to_string(),
        spectral_quadrature_generator::generate(&crate_dir(), None)
            .unwrap()
            .tables_rs,
    )];
    for path in scenes {
        let tables = spectral_quadrature_generator::generate(&crate_dir(), Some(path.as_os_str()))
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
            .tables_rs;
        out.push((path.display().to_string(), tables));
    }
    out
}

#[test]
fn every_scenes_tables_fit_in_100_columns() {
    for (scene, tables) in every_scene() {
        // The longest lines of the one-line layout ran to thousands of columns.
        for (i, line) in tables.lines().enumerate() {
            let columns = line.chars().count();
            assert!(
                columns <= 100,
                "{scene}: tables.rs:{}: {columns} columns",
                i + 1
            );
        }
    }
}

/// A scene of long names and many of each thing: user sets, lights and a sensor whose names
/// push chains, struct literals and items past their one-line widths, a one-wavelength set,
/// every display with three transfer functions, and both extras. `dir` holds the scene file.
fn scene_of_long_names(dir: &Path) -> String {
    let data = crate_dir().join("data");
    let data = data.display();
    let text = format!(
        r#"displays = ["DISPLAY_P3", "REC2020", "MEYER_1987", "SRGB"]
sets = ["KQ_A_LONG_LIGHT_NAME_FOR_CHAINS_8", "AC1C2_8_6_7", "UNIFORM_64", "INTERP_A_7", "A_1", "C2_1"]
[transfer]
SRGB = "gamma 2.2"
REC2020 = "linear"
DISPLAY_P3 = "gamma 1.8"
[extras]
sensitivities = true
rules = true
[lights]
A_LONG_LIGHT_NAME_FOR_CHAINS = "{data}/illuminant_LED_B3.csv"
[sensors.VERY_LONG_SENSOR_NAME_THAT_GOES_ON_AND_ON]
file = "{data}/sensor_as7341_gaussian.csv"
[fixed.ONE]
wavelengths_nm = [555.0]
[fixed.MANY_WAVELENGTHS_FOR_A_FIXED_SET_WITH_A_LONG_NAME]
wavelengths_nm = [400, 420, 440, 460, 480, 500, 520, 540, 560, 580, 600, 620, 640, 660, 680, 700]
light = "F11"
"#
    );
    let file = dir.join("long_names.toml");
    std::fs::write(&file, text).unwrap();
    spectral_quadrature_generator::generate(&crate_dir(), Some(file.as_os_str()))
        .unwrap()
        .tables_rs
}

#[test]
fn rustfmt_leaves_every_scenes_tables_as_they_are() {
    let missing = |why: &str| {
        // Where `.ci/run` found rustfmt (SPECTRAL_QUADRATURE_REQUIRE names it), it must run.
        let required = std::env::var("SPECTRAL_QUADRATURE_REQUIRE")
            .is_ok_and(|list| list.split(',').any(|c| c.trim() == "rustfmt"));
        assert!(
            !required,
            "rustfmt is not available ({why}), but SPECTRAL_QUADRATURE_REQUIRE says this machine has it"
        );
        let note = format!(
            "note: rustfmt is not available ({why}): the scenes' tables checked for 100 columns only\n"
        );
        // Past the test harness's capture, so that the output says what was not checked.
        std::io::stderr().write_all(note.as_bytes()).ok();
    };
    match Command::new("rustfmt").arg("--version").output() {
        Err(e) => return missing(&e.to_string()),
        Ok(out) if !out.status.success() => {
            return missing(String::from_utf8_lossy(&out.stderr).trim());
        }
        Ok(_) => {}
    }
    let dir = std::env::temp_dir().join(format!("sq-layout-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // An empty configuration: rustfmt's defaults, whatever a parent directory or the user's
    // configuration holds.
    let config = dir.join("rustfmt.toml");
    std::fs::write(&config, "").unwrap();
    let mut scenes = every_scene();
    // Its doc links to sets of long names are single words longer than a line: only rustfmt's
    // verdict is asked of it.
    scenes.push(("long names".into(), scene_of_long_names(&dir)));
    let mut failures = Vec::new();
    for (k, (scene, tables)) in scenes.into_iter().enumerate() {
        let file = dir.join(format!("tables_{k}.rs"));
        std::fs::write(&file, &tables).unwrap();
        let out = Command::new("rustfmt")
            .args(["--check", "--edition", "2021", "--config-path"])
            .arg(&config)
            .arg(&file)
            .output()
            .expect("rustfmt runs");
        if !out.status.success() {
            failures.push(format!(
                "{scene}:\n{}{}",
                String::from_utf8_lossy(&out.stdout),
                String::from_utf8_lossy(&out.stderr)
            ));
        }
    }
    std::fs::remove_dir_all(&dir).ok();
    assert!(
        failures.is_empty(),
        "rustfmt --check wants changes:\n{}",
        failures.join("\n")
    );
}
