//! The crate's naming rule for enums (lib.rs, "Conventions"): every public enum's `name()` is
//! its variant's identifier in kebab-case, and its `Display` the sentence for messages; the
//! channel selectors, whose names are symbols, are the one exception.

use std::string::{String, ToString};
use std::vec::Vec;

use crate::{
    CalibrationProblem, Channel, GamutMapping, LengthOf, LightGroupProblem, Point, Rgb, RuleStatus,
};

/// Every variant of each public enum that has a `name()`. Each list is held complete by a
/// `match` without a wildcard arm (possible here, in the crate that defines the enums): a new
/// variant does not compile until it is listed.
fn gamut_mappings() -> Vec<GamutMapping> {
    let all = [GamutMapping::Clip, GamutMapping::PreserveA];
    for m in all {
        match m {
            GamutMapping::Clip | GamutMapping::PreserveA => {}
        }
    }
    all.to_vec()
}

fn rule_statuses() -> Vec<RuleStatus> {
    let all = [
        RuleStatus::Defined,
        RuleStatus::Outside,
        RuleStatus::Complex,
        RuleStatus::VanishingNorm,
    ];
    for s in all {
        match s {
            RuleStatus::Defined
            | RuleStatus::Outside
            | RuleStatus::Complex
            | RuleStatus::VanishingNorm => {}
        }
    }
    all.to_vec()
}

fn light_group_problems() -> Vec<LightGroupProblem> {
    let all = [
        LightGroupProblem::NoLights,
        LightGroupProblem::NotReflectance,
        LightGroupProblem::Wavelengths,
        LightGroupProblem::Display,
        LightGroupProblem::InvalidWeight {
            channel: Rgb::G,
            index: 3,
        },
    ];
    for p in all {
        match p {
            LightGroupProblem::NoLights
            | LightGroupProblem::NotReflectance
            | LightGroupProblem::Wavelengths
            | LightGroupProblem::Display
            | LightGroupProblem::InvalidWeight { .. } => {}
        }
    }
    all.to_vec()
}

fn calibration_problems() -> Vec<CalibrationProblem> {
    let all = [
        CalibrationProblem::NoSignal,
        CalibrationProblem::Reference,
        CalibrationProblem::OutOfRange,
    ];
    for p in all {
        match p {
            CalibrationProblem::NoSignal
            | CalibrationProblem::Reference
            | CalibrationProblem::OutOfRange => {}
        }
    }
    all.to_vec()
}

fn length_ofs() -> Vec<LengthOf> {
    let all = [
        LengthOf::Output,
        LengthOf::InputPlane,
        LengthOf::OutputPlane,
        LengthOf::Samples,
        LengthOf::RuleWavelengths,
        LengthOf::RuleWeights,
    ];
    for w in all {
        match w {
            LengthOf::Output
            | LengthOf::InputPlane
            | LengthOf::OutputPlane
            | LengthOf::Samples
            | LengthOf::RuleWavelengths
            | LengthOf::RuleWeights => {}
        }
    }
    all.to_vec()
}

/// The math crate's, re-exported by the runtime (`DisplayError::Chromaticity` names one).
fn points() -> Vec<Point> {
    let all = [Point::Red, Point::Green, Point::Blue, Point::White];
    for p in all {
        match p {
            Point::Red | Point::Green | Point::Blue | Point::White => {}
        }
    }
    all.to_vec()
}

/// Lower-case ASCII words of letters and digits joined by single hyphens.
fn is_kebab_case(s: &str) -> bool {
    !s.is_empty()
        && s.split('-').all(|w| {
            !w.is_empty()
                && w.bytes()
                    .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit())
        })
}

/// The kebab-case of an UpperCamelCase identifier: a hyphen before each upper-case letter but
/// the first, everything lower case (`PreserveA` → `preserve-a`, `OutOfRange` →
/// `out-of-range`).
fn kebab_of(identifier: &str) -> String {
    let mut out = String::new();
    for (i, ch) in identifier.chars().enumerate() {
        if ch.is_ascii_uppercase() && i > 0 {
            out.push('-');
        }
        out.push(ch.to_ascii_lowercase());
    }
    out
}

/// `name()` is the kebab-case of the variant's identifier (its `Debug` up to the fields, if
/// any), distinct within the enum; `Display` is a sentence, not the identifier.
fn check<T: core::fmt::Debug + core::fmt::Display>(
    enum_name: &str,
    all: &[T],
    name: impl Fn(&T) -> &'static str,
) {
    let mut seen = Vec::new();
    for v in all {
        let debug = std::format!("{v:?}");
        let id = debug.split([' ', '(']).next().unwrap_or_default();
        let n = name(v);
        assert!(
            is_kebab_case(n),
            "{enum_name}::{id}.name() = {n:?} is not kebab-case"
        );
        assert_eq!(n, kebab_of(id), "{enum_name}::{id}.name()");
        assert!(!seen.contains(&n), "{enum_name}: {n:?} twice");
        seen.push(n);
        let sentence = v.to_string();
        assert!(
            sentence.contains(' ') && sentence != n,
            "{enum_name}::{id}: its Display {sentence:?} is not a sentence"
        );
    }
}

#[test]
fn every_public_enum_names_its_variants_in_kebab_case() {
    assert_eq!(kebab_of("VanishingNorm"), "vanishing-norm");
    assert_eq!(kebab_of("PreserveA"), "preserve-a");
    assert!(is_kebab_case("out-of-range") && is_kebab_case("c1"));
    assert!(!is_kebab_case("PreserveA") && !is_kebab_case("a--b") && !is_kebab_case("-a"));
    check("GamutMapping", &gamut_mappings(), |v| v.name());
    check("RuleStatus", &rule_statuses(), |v| v.name());
    check("LightGroupProblem", &light_group_problems(), |v| v.name());
    check("CalibrationProblem", &calibration_problems(), |v| v.name());
    check("LengthOf", &length_ofs(), |v| v.name());
    check("Point", &points(), |v| v.name());
}

/// The stated exception: a channel selector's name is its symbol, the variant's identifier as
/// written (A, C1, C2; R, G, B), in `ALL`'s order.
#[test]
fn channel_selectors_are_named_by_their_symbols() {
    for c in Channel::ALL {
        match c {
            Channel::A | Channel::C1 | Channel::C2 => {}
        }
        assert_eq!(c.name(), std::format!("{c:?}"));
    }
    for c in Rgb::ALL {
        match c {
            Rgb::R | Rgb::G | Rgb::B => {}
        }
        assert_eq!(c.name(), std::format!("{c:?}"));
    }
    let names: Vec<&str> = Channel::ALL.iter().map(|c| c.name()).collect();
    assert_eq!(names, ["A", "C1", "C2"]);
    let names: Vec<&str> = Rgb::ALL.iter().map(|c| c.name()).collect();
    assert_eq!(names, ["R", "G", "B"]);
}
