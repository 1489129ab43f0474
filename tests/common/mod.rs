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
