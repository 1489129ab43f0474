//! `tables --rust`, `--wgsl` and `--glsl` print what the runtime's build script bakes for the
//! scene named by `SPECTRAL_QUADRATURE_SCENE`, byte for byte, from any working directory.

use spectral_quadrature_tools as tools;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The `tables` program, as Cargo built it for these tests.
const TABLES: &str = env!("CARGO_BIN_EXE_tables");

fn crate_dir() -> PathBuf {
    std::fs::canonicalize(tools::CRATE_DIR).unwrap()
}

/// A scratch directory (removed when dropped), to run the program from somewhere else than the
/// workspace.
struct Scratch(PathBuf);

impl Scratch {
    fn new(tag: &str) -> Scratch {
        let dir = std::env::temp_dir().join(format!("sq-tables-{tag}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        Scratch(dir)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        std::fs::remove_dir_all(&self.0).ok();
    }
}

/// Runs `tables <flag>` in `cwd` with `SPECTRAL_QUADRATURE_SCENE` set to `scene` (or unset).
fn run(flag: &str, scene: Option<&str>, cwd: &Path) -> Output {
    let mut cmd = Command::new(TABLES);
    cmd.arg(flag).current_dir(cwd);
    match scene {
        Some(s) => cmd.env(spectral_quadrature_generator::SCENE_ENV, s),
        None => cmd.env_remove(spectral_quadrature_generator::SCENE_ENV),
    };
    cmd.output().expect("tables runs")
}

fn stdout(out: &Output) -> &str {
    assert!(
        out.status.success(),
        "exit {:?}: {}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    std::str::from_utf8(&out.stdout).unwrap()
}

#[test]
fn the_default_scene_prints_what_the_build_script_writes() {
    let expected = spectral_quadrature_generator::generate(&crate_dir(), None).unwrap();
    let here = crate_dir();
    assert_eq!(stdout(&run("--rust", None, &here)), expected.tables_rs);
    assert_eq!(stdout(&run("--wgsl", None, &here)), expected.wgsl);
    assert_eq!(stdout(&run("--glsl", None, &here)), expected.glsl);
    assert_eq!(stdout(&run("--c-header", None, &here)), expected.c_header);
    assert!(expected.tables_rs.contains("// Scene: default\n"));
}

#[test]
fn c_header_takes_the_scene_relative_to_the_working_directory() {
    let scene = "examples/scenes/sensor.toml";
    let expected =
        spectral_quadrature_generator::generate(&crate_dir(), Some(scene.as_ref())).unwrap();
    let out = Command::new(TABLES)
        .args(["--c-header", "--scene", scene])
        .current_dir(crate_dir())
        .env(
            spectral_quadrature_generator::SCENE_ENV,
            "examples/scenes/minimal.toml",
        )
        .output()
        .expect("tables runs");
    let header = stdout(&out);
    assert_eq!(header, expected.c_header);
    assert!(header.contains(" * Scene: examples/scenes/sensor.toml\n"));
    assert!(header.contains("sq_integer_as7341_srgb_encode_u8("));
}

#[test]
fn a_relative_scene_is_read_from_the_runtime_crate_wherever_it_runs() {
    // As the build script reads it: relative to the runtime crate's root, not to the working
    // directory.
    let elsewhere = Scratch::new("cwd");
    let scene = "examples/scenes/minimal.toml";
    let expected =
        spectral_quadrature_generator::generate(&crate_dir(), Some(scene.as_ref())).unwrap();
    let rust = run("--rust", Some(scene), &elsewhere.0);
    assert_eq!(stdout(&rust), expected.tables_rs);
    assert!(expected
        .tables_rs
        .contains("pub const SCENE: &str = \"examples/scenes/minimal.toml\";"));
    assert_eq!(
        stdout(&run("--wgsl", Some(scene), &elsewhere.0)),
        expected.wgsl
    );
    assert_eq!(
        stdout(&run("--glsl", Some(scene), &elsewhere.0)),
        expected.glsl
    );
    // Another scene bakes other tables.
    assert_ne!(
        expected.tables_rs,
        spectral_quadrature_generator::generate(&crate_dir(), None)
            .unwrap()
            .tables_rs
    );
}

#[test]
fn a_bad_scene_fails_naming_its_file_and_line() {
    let dir = Scratch::new("bad");
    let scene = dir.0.join("bad.toml");
    std::fs::write(&scene, "displays = [\"SRGB\"]\nsets = [\"TABLE9_ROW1\"]\n").unwrap();
    let out = run("--rust", scene.to_str(), &dir.0);
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(&format!(
            "{}:2: TABLE9_ROW1: not a set name",
            scene.display()
        )),
        "{err}"
    );
}

#[test]
fn one_output_at_a_time() {
    let out = Command::new(TABLES)
        .args(["--rust", "--wgsl"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("cannot be used with"));
}
