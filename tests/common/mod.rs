//! Helpers shared by the integration tests: a module each test file includes with `mod common;`,
//! not a test target of its own.

use std::fmt::Debug;

use proptest::strategy::Strategy;
use proptest::test_runner::{Config, TestCaseResult, TestRunner};

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
