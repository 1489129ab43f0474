//! Negative values: rounding noise read as 0 and reported once, anything more negative an error
//! naming line and column, unless the reader is asked to clamp.

use crate::common::{assert_error, parse_err, spectra_text, table_text};
use spectral_quadrature_spectra::{parse_table, parse_table_with, Negatives, Spacing, Spectra};

#[test]
fn rounding_noise_is_read_as_zero_and_reported_once_with_the_first_place() {
    let text = table_text(&[
        "400,0.5,0.25,1",
        "405,0.5,-7e-18,0.5",
        "410,-2.2e-16,0.5,-1e-17",
    ]);
    let t = parse_table("noise.csv", &text, Some(3), Spacing::Even).unwrap();
    assert_eq!(t.values[1], [0.5, 0.0, 0.5]);
    assert_eq!(t.values[2], [0.0, 0.5, 0.0]);
    let z = t.zeroed.expect("the zeroed values are reported");
    assert_eq!(
        (z.file.as_str(), z.count, z.beyond_tolerance),
        ("noise.csv", 3, 0)
    );
    assert_eq!((z.first.line, z.first.column), (3, 3));
    assert_eq!((z.first.name.as_str(), z.first.value), ("y_bar", -7e-18));
    assert_eq!((z.most_negative.line, z.most_negative.column), (4, 2));
    assert_eq!(z.most_negative.value, -2.2e-16);
    assert_eq!(z.largest, 1.0);
    let shown = z.to_string();
    assert!(
        shown.starts_with(
            "noise.csv:3: column 3 (y_bar): 3 negative values read as 0, the first here (-7e-18)"
        ),
        "{shown}"
    );
    assert!(shown.contains("rounding noise"), "{shown}");
    assert!(
        shown.contains("-2.2e-16 at line 4, column 2 (x_bar)"),
        "{shown}"
    );
}

#[test]
fn a_table_without_negative_values_reports_nothing() {
    // -0 is not below zero.
    let text = table_text(&["400,0,0.5,1", "405,-0,0.5,0.5"]);
    let t = parse_table("clean.csv", &text, Some(3), Spacing::Even).unwrap();
    assert_eq!(t.zeroed, None);
}

#[test]
fn negative_beyond_the_tolerance_is_an_error_naming_line_and_column() {
    let text = table_text(&["400,0.5,0.25,1", "405,0.5,-7e-18,0.5", "410,0.1,0.5,-0.001"]);
    let e = parse_err("neg.csv", &text, Some(3), Spacing::Even);
    assert_error(
        &e,
        "neg.csv",
        4,
        &["column 4 (z_bar)", "-0.001 is negative", "1e-6", "clamp"],
    );
    assert!(
        e.to_string().starts_with("neg.csv:4: column 4 (z_bar): "),
        "{e}"
    );
}

#[test]
fn the_first_value_beyond_the_tolerance_in_file_order_is_the_error() {
    let text = table_text(&["400,0.5,0.25,-0.5", "405,-0.5,0.5,0.5", "410,1,1,1"]);
    let e = parse_err("two.csv", &text, Some(3), Spacing::Even);
    assert_error(&e, "two.csv", 2, &["column 4 (z_bar)", "-0.5"]);
}

#[test]
fn the_tolerance_scales_with_the_files_largest_value() {
    // Largest 2: the floor is -2e-6 exactly (1e-6 times a power of two), and it is inclusive.
    let at_floor = spectra_text("wavelength_nm,s", &["400,2", "500,-2e-6", "600,1"]);
    let t = parse_table("floor.csv", &at_floor, None, Spacing::Any).unwrap();
    assert_eq!(t.values[1], [0.0]);
    let below = spectra_text("wavelength_nm,s", &["400,2", "500,-2.0000001e-6", "600,1"]);
    let e = parse_err("below.csv", &below, None, Spacing::Any);
    assert_error(
        &e,
        "below.csv",
        3,
        &["column 2 (s)", "-2e-6", "largest value, 2"],
    );
    // The same value is noise in a file whose values are in the thousands (a light's power),
    // and an error in one whose largest value is 1e-3.
    let large = spectra_text("wavelength_nm,s", &["400,3000", "500,-1e-3"]);
    assert!(parse_table("w.csv", &large, None, Spacing::Any)
        .unwrap()
        .zeroed
        .is_some());
    let small = spectra_text("wavelength_nm,s", &["400,1e-3", "500,-1e-8"]);
    parse_err("mw.csv", &small, None, Spacing::Any);
}

#[test]
fn a_file_without_a_positive_value_has_no_tolerance() {
    for rows in [["400,0", "500,-1e-300"], ["400,-1e-300", "500,-2e-300"]] {
        let text = spectra_text("wavelength_nm,s", &rows);
        let e = parse_err("dark.csv", &text, None, Spacing::Any);
        assert!(e.message.contains("no positive value"), "{e}");
    }
}

#[test]
fn subnormal_and_tiny_negatives_are_noise_huge_ones_are_errors() {
    let text = spectra_text("wavelength_nm,s", &["400,1", "500,-5e-324", "600,-1e-300"]);
    let t = parse_table("tiny.csv", &text, None, Spacing::Any).unwrap();
    assert_eq!(t.values, [[1.0], [0.0], [0.0]]);
    assert_eq!(t.zeroed.unwrap().count, 2);
    let text = spectra_text("wavelength_nm,s", &["400,1", "500,-1.7e308"]);
    let e = parse_err("huge.csv", &text, None, Spacing::Any);
    assert_error(&e, "huge.csv", 3, &["-1.7e308"]);
}

#[test]
fn clamp_reads_every_negative_as_zero_and_counts_those_beyond_the_tolerance() {
    let text = spectra_text(
        "wavelength_nm,a,b",
        &["400,1,-1e-9", "500,-0.25,0.5", "600,0.5,-0.5"],
    );
    let t = parse_table_with("clamp.csv", &text, None, Spacing::Any, Negatives::Clamp).unwrap();
    assert_eq!(t.values, [[1.0, 0.0], [0.0, 0.5], [0.5, 0.0]]);
    let z = t.zeroed.unwrap();
    assert_eq!((z.count, z.beyond_tolerance), (3, 2));
    assert_eq!((z.first.line, z.first.column, z.first.value), (2, 3, -1e-9));
    assert_eq!((z.most_negative.line, z.most_negative.column), (4, 3));
    let shown = z.to_string();
    assert!(
        shown.starts_with("clamp.csv:2: column 3 (b): 3 negative values read as 0"),
        "{shown}"
    );
    assert!(shown.contains("2 values beyond the tolerance"), "{shown}");
    assert!(shown.contains("clamped as asked"), "{shown}");
    // Without the opt-in the same file is refused at its first value beyond the tolerance.
    let e = parse_err("clamp.csv", &text, None, Spacing::Any);
    assert_error(&e, "clamp.csv", 3, &["column 2 (a)", "-0.25"]);
}

#[test]
fn spectra_readers_share_the_rule_and_the_clamp() {
    let text = spectra_text("wavelength_nm,s", &["380,1", "500,-3e-17", "780,-0.5"]);
    let e = Spectra::parse("s.csv", &text).unwrap_err();
    assert_error(&e, "s.csv", 4, &["column 2 (s)", "-0.5"]);
    let s = Spectra::parse_with("s.csv", &text, Negatives::Clamp).unwrap();
    let z = s.zeroed().unwrap();
    assert_eq!((z.count, z.beyond_tolerance, z.first.line), (2, 1, 3));
    let c = s.curve(0, [380.0, 770.0]).unwrap();
    assert_eq!(c.values, [1.0, 0.0, 0.0]);
}
