//! Spectra CSV files: arbitrary bytes → text (converted with `String::from_utf8_lossy`, so
//! every input is parsed; invalid UTF-8 becomes U+FFFD) → `Spectra::parse("fuzz.csv", text)`,
//! then `curves([380.0, 770.0])`, the observer range a scene's `[plan]` reads spectra on.
//!
//! Checked: no panic, hang or unbounded memory, whatever the text. Every error (of `parse` or
//! of `curves`) names the file (`file == "fuzz.csv"`, its `Display` starts with `fuzz.csv:`,
//! and with `fuzz.csv:<line>: ` when it has a line) and its line, when non-zero, is a line of
//! the text (1..=lines, one more for a position at the very end). Parsed spectra:
//! - have at least one named spectrum (`names().len() >= 1`) and name the file;
//! - as curves over an empty range (`curves([+Inf, -Inf])`, which any data cover) give one
//!   curve per name, each with the name, as many values as wavelengths (at least one), finite
//!   strictly increasing wavelengths and finite non-negative values (`parse` rejects the rest);
//! - `curves([380.0, 770.0])` succeeds when the data reach from 380 nm or below to 770 nm or
//!   above and fails when they stop more than 1e-6 nm short at either end, and on success
//!   gives the same curves;
//! - `Curve::at` at wavelengths across 380..=770 nm (the data's nodes there included) is
//!   finite, non-negative and, being a linear interpolation, within the curve's smallest and
//!   largest value (up to a few ulps of the largest).
#![no_main]

use libfuzzer_sys::fuzz_target;
use spectral_quadrature_spectra::{Curve, DataError, Spectra};

const FILE: &str = "fuzz.csv";

/// The observer range the curves are checked on.
const RANGE_NM: [f64; 2] = [380.0, 770.0];

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let spectra = match Spectra::parse(FILE, &text) {
        Err(e) => return check_error("parse", &e, &text),
        Ok(s) => s,
    };
    let ctx = || format!("{text:?}");
    assert_eq!(spectra.file(), FILE, "{}", ctx());
    let names = spectra.names();
    assert!(!names.is_empty(), "no spectra: {}", ctx());

    // The raw data: an empty range is covered by any data.
    let all = spectra
        .curves([f64::INFINITY, f64::NEG_INFINITY])
        .unwrap_or_else(|e| panic!("curves over an empty range: {e}: {}", ctx()));
    assert_eq!(all.len(), names.len(), "one curve per spectrum: {}", ctx());
    for (curve, name) in all.iter().zip(names) {
        check_curve(curve, name, &text);
    }

    let (first, last) = (all[0].wavelengths[0], *all[0].wavelengths.last().unwrap());
    match spectra.curves(RANGE_NM) {
        Err(e) => {
            check_error("curves", &e, &text);
            assert!(
                first > RANGE_NM[0] || last < RANGE_NM[1],
                "data covering {first}-{last} nm rejected for {RANGE_NM:?}: {e}: {}",
                ctx()
            );
        }
        Ok(curves) => {
            assert!(
                first <= RANGE_NM[0] + 1e-6 && last >= RANGE_NM[1] - 1e-6,
                "data covering only {first}-{last} nm accepted for {RANGE_NM:?}: {}",
                ctx()
            );
            assert_eq!(curves, all, "curves differ with the range: {}", ctx());
            for curve in &curves {
                check_values_in_range(curve, &text);
            }
        }
    }
});

/// The largest line number a position in `text` can have: its lines, plus one for the end of
/// a text that ends with a newline (and line 1 of an empty text).
fn max_line(text: &str) -> u64 {
    text.lines().count() as u64 + 1
}

fn check_error(what: &str, e: &DataError, text: &str) {
    let shown = e.to_string();
    assert_eq!(
        e.file, FILE,
        "{what}: the error names another file: {shown}"
    );
    assert!(
        shown.starts_with(&format!("{FILE}:")),
        "{what}: the error does not start with the file: {shown:?}"
    );
    if e.line != 0 {
        assert!(
            (1..=max_line(text)).contains(&e.line),
            "{what}: error {shown:?} names line {}, the text has {} lines: {text:?}",
            e.line,
            text.lines().count()
        );
        assert!(
            shown.starts_with(&format!("{FILE}:{}: ", e.line)),
            "{what}: the error does not start with file:line: {shown:?}"
        );
    } else {
        assert!(
            shown.starts_with(&format!("{FILE}: ")),
            "{what}: the error does not start with \"file: \": {shown:?}"
        );
    }
}

fn check_curve(curve: &Curve, name: &str, text: &str) {
    assert_eq!(curve.name, name, "curve name: {text:?}");
    let (w, v) = (&curve.wavelengths, &curve.values);
    assert!(!w.is_empty(), "curve {name:?} has no data: {text:?}");
    assert_eq!(w.len(), v.len(), "curve {name:?}: {text:?}");
    assert!(
        w.iter().all(|x| x.is_finite()),
        "curve {name:?} has a wavelength that is not finite: {w:?}: {text:?}"
    );
    assert!(
        w.windows(2).all(|p| p[0] < p[1]),
        "curve {name:?}: wavelengths not strictly increasing: {w:?}: {text:?}"
    );
    assert!(
        v.iter().all(|x| x.is_finite() && *x >= 0.0),
        "curve {name:?} has a value that is negative or not finite: {v:?}: {text:?}"
    );
}

/// `Curve::at` across the range: a grid, a few odd wavelengths, and the nodes in the range.
fn check_values_in_range(curve: &Curve, text: &str) {
    let (lo, hi) = curve
        .values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    let tol = 4.0 * f64::EPSILON * hi;
    let grid = (0..=39).map(|k| RANGE_NM[0] + 10.0 * f64::from(k));
    let odd = [380.000_000_1, 455.5, 555.0, 587.3, 769.999_999_9, 770.0];
    let nodes = curve
        .wavelengths
        .iter()
        .copied()
        .filter(|w| (RANGE_NM[0]..=RANGE_NM[1]).contains(w));
    for nm in grid.chain(odd).chain(nodes) {
        let v = curve.at(nm);
        assert!(
            v.is_finite() && v >= 0.0,
            "curve {:?} at {nm} nm = {v}: {text:?}",
            curve.name
        );
        assert!(
            v >= lo - tol && v <= hi + tol,
            "curve {:?} at {nm} nm = {v:e}, outside its values {lo:e}..={hi:e}: {text:?}",
            curve.name
        );
    }
}
