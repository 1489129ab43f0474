//! Malformed tables: each is an error naming the label, the exact line and what is wrong; and
//! the well-formed ones that must parse (whitespace, CRLF, trailing newlines, even spacing).

use crate::common::{assert_error, parse_err, table_text, HEADER};
use spectral_quadrature_spectra::{parse_table, Spacing};

#[test]
fn well_formed_table_parses_with_line_numbers() {
    let text = table_text(&["400,0.1,0.2,0.3", "405,0.4,0.5,0.6", "410,0.7,0.8,0.9"]);
    let t = parse_table("ok.csv", &text, Some(3), Spacing::Even).unwrap();
    assert_eq!(t.file, "ok.csv");
    assert_eq!(t.columns, ["x_bar", "y_bar", "z_bar"]);
    assert_eq!(t.wavelengths, [400.0, 405.0, 410.0]);
    assert_eq!(t.values[1], [0.4, 0.5, 0.6]);
    assert_eq!(t.lines, [2, 3, 4]);
    assert_eq!(t.step(), 5.0);
}

#[test]
fn whitespace_around_fields_is_trimmed() {
    let text = "wavelength_nm , a\n 400 , 1.5 \n401,\t2\n";
    let t = parse_table("spaces.csv", text, None, Spacing::Even).unwrap();
    assert_eq!(t.columns, ["a"]);
    assert_eq!(t.wavelengths, [400.0, 401.0]);
    assert_eq!(t.values, [vec![1.5], vec![2.0]]);
    assert_eq!(t.lines, [2, 3]);
}

#[test]
fn crlf_file_is_accepted() {
    let text = "wavelength_nm,a\r\n400,1.5\r\n401,2\r\n";
    let t = parse_table("crlf.csv", text, None, Spacing::Even).unwrap();
    assert_eq!(t.columns, ["a"]);
    assert_eq!(t.wavelengths, [400.0, 401.0]);
    assert_eq!(t.values, [vec![1.5], vec![2.0]]);
}

#[test]
fn crlf_file_reports_the_right_lines() {
    let text = "wavelength_nm,a\r\n400,1\r\n401,2\r\n";
    let t = parse_table("crlf.csv", text, None, Spacing::Even).unwrap();
    assert_eq!(t.lines, [2, 3]);
    // A bad row of a CRLF file is reported on its own line.
    let bad = "wavelength_nm,a\r\n400,1\r\n401,x\r\n";
    let e = parse_err("crlf.csv", bad, None, Spacing::Even);
    assert_error(&e, "crlf.csv", 3, &["not a number"]);
}

#[test]
fn single_row_table_parses() {
    let t = parse_table(
        "one.csv",
        &table_text(&["500,1,2,3"]),
        Some(3),
        Spacing::Even,
    )
    .unwrap();
    assert_eq!(t.wavelengths, [500.0]);
    assert_eq!(t.step(), 0.0);
}

#[test]
fn missing_column_is_reported_on_its_line() {
    let text = table_text(&["400,1,2,3", "401,1,2,3", "402,1,2"]);
    let e = parse_err("missing.csv", &text, Some(3), Spacing::Even);
    assert_error(&e, "missing.csv", 4, &["missing"]);
}

#[test]
fn extra_column_is_reported_on_its_line() {
    let text = table_text(&["400,1,2,3", "401,1,2,3,4", "402,1,2,3"]);
    let e = parse_err("extra.csv", &text, Some(3), Spacing::Even);
    assert_error(&e, "extra.csv", 3, &["extra"]);
}

#[test]
fn trailing_comma_is_an_extra_column() {
    let text = table_text(&["400,1,2,3,"]);
    let e = parse_err("trailing.csv", &text, Some(3), Spacing::Any);
    assert_error(&e, "trailing.csv", 2, &["extra"]);
}

#[test]
fn value_that_is_not_a_number_is_reported() {
    let text = table_text(&["400,1,2,3", "401,1,abc,3"]);
    let e = parse_err("abc.csv", &text, Some(3), Spacing::Even);
    assert_error(&e, "abc.csv", 3, &["not a number", "abc", "y_bar"]);
}

#[test]
fn wavelength_that_is_not_a_number_is_reported() {
    let text = table_text(&["400,1,2,3", "401,1,2,3", "4o2,1,2,3"]);
    let e = parse_err("wl.csv", &text, Some(3), Spacing::Even);
    assert_error(&e, "wl.csv", 4, &["not a number", "wavelength"]);
}

#[test]
fn empty_field_is_not_a_number() {
    let text = table_text(&["400,1,,3"]);
    let e = parse_err("blank.csv", &text, Some(3), Spacing::Even);
    assert_error(&e, "blank.csv", 2, &["not a number"]);
}

#[test]
fn nan_is_rejected() {
    for nan in ["NaN", "nan", "-NaN"] {
        let row = format!("401,1,2,{nan}");
        let text = table_text(&["400,1,2,3", &row]);
        let e = parse_err("nan.csv", &text, Some(3), Spacing::Even);
        assert_error(&e, "nan.csv", 3, &["not finite", "z_bar"]);
    }
}

#[test]
fn infinity_is_rejected() {
    for inf in ["inf", "-inf", "Infinity", "1e999"] {
        let row = format!("401,{inf},2,3");
        let text = table_text(&["400,1,2,3", &row]);
        let e = parse_err("inf.csv", &text, Some(3), Spacing::Even);
        assert_error(&e, "inf.csv", 3, &["not finite", "x_bar"]);
    }
}

#[test]
fn infinite_wavelength_is_rejected() {
    let text = table_text(&["400,1,2,3", "inf,1,2,3"]);
    let e = parse_err("inf_wl.csv", &text, Some(3), Spacing::Any);
    assert_error(&e, "inf_wl.csv", 3, &["not finite", "wavelength"]);
}

#[test]
fn repeated_wavelength_is_rejected() {
    let text = table_text(&["400,1,2,3", "401,1,2,3", "401,1,2,3"]);
    for spacing in [Spacing::Even, Spacing::Any] {
        let e = parse_err("repeat.csv", &text, Some(3), spacing);
        assert_error(&e, "repeat.csv", 4, &["not greater", "401"]);
    }
}

#[test]
fn decreasing_wavelength_is_rejected() {
    let text = table_text(&["400,1,2,3", "401,1,2,3", "402,1,2,3", "399,1,2,3"]);
    for spacing in [Spacing::Even, Spacing::Any] {
        let e = parse_err("decrease.csv", &text, Some(3), spacing);
        assert_error(&e, "decrease.csv", 5, &["not greater", "399"]);
    }
}

#[test]
fn second_row_below_first_is_rejected() {
    let text = table_text(&["400,1,2,3", "390,1,2,3"]);
    let e = parse_err("down.csv", &text, Some(3), Spacing::Even);
    assert_error(&e, "down.csv", 3, &["not greater"]);
}

#[test]
fn uneven_step_is_rejected_with_even_spacing_only() {
    let text = table_text(&[
        "400,1,2,3",
        "401,1,2,3",
        "402,1,2,3",
        "404,1,2,3",
        "405,1,2,3",
    ]);
    let e = parse_err("uneven.csv", &text, Some(3), Spacing::Even);
    assert_error(&e, "uneven.csv", 5, &["uneven"]);
    let t = parse_table("uneven.csv", &text, Some(3), Spacing::Any).unwrap();
    assert_eq!(t.wavelengths, [400.0, 401.0, 402.0, 404.0, 405.0]);
    assert_eq!(t.lines, [2, 3, 4, 5, 6]);
}

#[test]
fn uneven_step_at_the_third_row_is_rejected() {
    // The first two rows set the step; the third row breaks it.
    let text = table_text(&["400,1,2,3", "405,1,2,3", "406,1,2,3"]);
    let e = parse_err("uneven3.csv", &text, Some(3), Spacing::Even);
    assert_error(&e, "uneven3.csv", 4, &["uneven"]);
    assert!(parse_table("uneven3.csv", &text, Some(3), Spacing::Any).is_ok());
}

#[test]
fn fractional_even_steps_are_accepted() {
    // 0.1 nm steps do not add up exactly in binary; the tolerance must allow them.
    let rows: Vec<String> = (0..50)
        .map(|k| format!("{:.1},1,2,3", 400.0 + 0.1 * f64::from(k)))
        .collect();
    let rows: Vec<&str> = rows.iter().map(String::as_str).collect();
    let t = parse_table("tenth.csv", &table_text(&rows), Some(3), Spacing::Even).unwrap();
    assert_eq!(t.wavelengths.len(), 50);
}

#[test]
fn empty_file_is_a_whole_file_error() {
    for text in ["", "\n", "\n\n"] {
        let e = parse_err("empty.csv", text, Some(3), Spacing::Even);
        assert_error(&e, "empty.csv", 0, &["empty"]);
        assert_eq!(e.to_string(), format!("empty.csv: {}", e.message));
    }
}

#[test]
fn header_only_has_no_data_rows() {
    for text in [HEADER.to_string(), format!("{HEADER}\n")] {
        let e = parse_err("header.csv", &text, Some(3), Spacing::Even);
        assert_error(&e, "header.csv", 1, &["no data rows"]);
    }
}

#[test]
fn empty_line_inside_the_table_is_rejected() {
    let text = format!("{HEADER}\n400,1,2,3\n\n401,1,2,3\n");
    let e = parse_err("gap.csv", &text, Some(3), Spacing::Even);
    assert_error(&e, "gap.csv", 3, &["empty line"]);
}

#[test]
fn first_of_several_empty_lines_is_reported() {
    // Nothing is skipped: the first empty line is the error, even with a bad row after it.
    let text = format!("{HEADER}\n400,1,2,3\n\n\n401,1,2,3\n402,1,x,3\n");
    let e = parse_err("gaps.csv", &text, Some(3), Spacing::Even);
    assert_error(&e, "gaps.csv", 3, &["empty line"]);
}

#[test]
fn bare_carriage_return_is_rejected_on_its_line() {
    let text = "wavelength_nm,a\n400,1\r401,2\n";
    let e = parse_err("cr.csv", text, None, Spacing::Any);
    assert_error(&e, "cr.csv", 2, &["carriage return"]);
}

#[test]
fn whitespace_only_line_inside_the_table_is_rejected() {
    let text = format!("{HEADER}\n400,1,2,3\n   \n401,1,2,3\n");
    let e = parse_err("blankline.csv", &text, Some(3), Spacing::Even);
    assert_error(&e, "blankline.csv", 3, &["empty line"]);
}

#[test]
fn trailing_newlines_after_the_table_are_accepted() {
    // A final newline (or CRLF) is not an empty line inside the table.
    for text in [
        format!("{HEADER}\n400,1,2,3\n401,1,2,3\n"),
        format!("{HEADER}\r\n400,1,2,3\r\n401,1,2,3\r\n"),
        format!("{HEADER}\n400,1,2,3\n401,1,2,3"),
    ] {
        let t = parse_table("end.csv", &text, Some(3), Spacing::Even).unwrap();
        assert_eq!(t.wavelengths, [400.0, 401.0]);
    }
}

#[test]
fn header_with_one_column_is_rejected() {
    for columns in [None, Some(3)] {
        let e = parse_err(
            "onecol.csv",
            "wavelength_nm\n400\n401\n",
            columns,
            Spacing::Even,
        );
        assert_error(&e, "onecol.csv", 1, &["header", "value column"]);
    }
}

#[test]
fn wrong_number_of_value_columns_in_header_is_rejected() {
    let two = "wavelength_nm,x_bar,y_bar\n400,1,2\n";
    let e = parse_err("two.csv", two, Some(3), Spacing::Even);
    assert_error(&e, "two.csv", 1, &["2 value columns", "expected 3"]);
    let four = "wavelength_nm,a,b,c,d\n400,1,2,3,4\n";
    let e = parse_err("four.csv", four, Some(3), Spacing::Even);
    assert_error(&e, "four.csv", 1, &["4 value columns", "expected 3"]);
    // Without a required width, any width of at least one value column is fine.
    assert!(parse_table("two.csv", two, None, Spacing::Even).is_ok());
    assert!(parse_table("four.csv", four, None, Spacing::Even).is_ok());
}

#[test]
fn first_bad_row_is_reported_not_a_later_one() {
    let text = table_text(&["400,1,2,3", "401,abc,2,3", "402,1,2", "400,1,2,3"]);
    let e = parse_err("first.csv", &text, Some(3), Spacing::Even);
    assert_error(&e, "first.csv", 3, &["not a number"]);
}
