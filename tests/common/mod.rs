//! Helpers shared by the integration tests: a module each test file includes with `mod common;`,
//! not a test target of its own.

// Each test file includes its own copy (tests/main.rs loads each file by #[path]) and uses only
// part of it.
#![allow(dead_code)]

pub mod cie015;

use std::fmt::Debug;

use proptest::strategy::Strategy;
use proptest::test_runner::{Config, TestCaseResult, TestRunner};
use spectral_quadrature::tables::folded;
use spectral_quadrature::{FoldedSet, GamutMapping};

/// Both gamut mappings.
pub const MAPPINGS: [GamutMapping; 2] = [GamutMapping::Clip, GamutMapping::PreserveA];

/// The baked sets of Table 2 row 1 folded for each display, indexed `[display]` in the order of
/// `displays::ALL`.
pub const FOLDED_ROW1: [FoldedSet<6>; 4] = [
    folded::TABLE2_ROW1_SRGB,
    folded::TABLE2_ROW1_DISPLAY_P3,
    folded::TABLE2_ROW1_REC2020,
    folded::TABLE2_ROW1_MEYER_1987,
];

/// As [`FOLDED_ROW1`], for Table 2 row 2.
pub const FOLDED_ROW2: [FoldedSet<4>; 4] = [
    folded::TABLE2_ROW2_SRGB,
    folded::TABLE2_ROW2_DISPLAY_P3,
    folded::TABLE2_ROW2_REC2020,
    folded::TABLE2_ROW2_MEYER_1987,
];

/// Runs one property for exactly `cases` cases, with no regression files, panicking with
/// proptest's (shrunk) failure under `name`.
pub fn check_property<S>(
    cases: u32,
    name: &str,
    strategy: S,
    test: impl Fn(S::Value) -> TestCaseResult,
) where
    S: Strategy,
    S::Value: Debug,
{
    let config = Config {
        failure_persistence: None,
        ..Config::with_cases(cases)
    };
    let mut runner = TestRunner::new(config);
    assert_eq!(runner.config().cases, cases);
    if let Err(e) = runner.run(&strategy, test) {
        panic!("{name}: {e}");
    }
}

/// The data files the derivation reads (the runtime crate's `data/`).
const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data");

/// The example sensor (`data/sensor_as7341_gaussian.csv`) fitted as a scene's `[sensors]` table
/// fits it, for reflectances under `light` or for radiances (`None`): `channels` holds the
/// sensor's curves, `xyz_weights` the fitted matrix from its readings to XYZ, `white_samples`
/// the golden device's readings of a perfect white (the white reference the build bakes).
pub fn example_sensor(
    d: &spectral_quadrature_generator::Derivation,
    light: Option<&str>,
) -> spectral_quadrature_generator::user::Fitted {
    let light = light.map_or(String::new(), |l| format!("light = \"{l}\"\n"));
    let text = format!(
        "displays = [\"SRGB\"]\n\n[sensors.AS7341]\nfile = \"../data/sensor_as7341_gaussian.csv\"\n{light}"
    );
    // Paths in a scene are relative to it: a scene in tests/ (the file need not exist).
    let file = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/sensor.toml");
    let scene = spectral_quadrature_generator::scene::Scene::parse(
        file,
        &text,
        std::path::Path::new(DATA_DIR),
    )
    .unwrap();
    assert_eq!(scene.settings, d.settings);
    let (_, mut fitted) = scene.resolve_user(d).unwrap();
    fitted.remove(0)
}
