//! How a `DataError` is displayed: `file:line: message`, or `file: message` for the whole file.

use crate::common::{parse_err, table_text};
use spectral_quadrature_spectra::{DataError, Spacing};

#[test]
fn display_is_file_colon_line_colon_message() {
    let text = table_text(&["400,1,2,3", "401,1,abc,3"]);
    let e = parse_err("data/some file.csv", &text, Some(3), Spacing::Even);
    let shown = e.to_string();
    assert_eq!(shown, format!("data/some file.csv:3: {}", e.message));
    assert!(shown.starts_with("data/some file.csv:3: "), "{shown}");
    assert!(shown.contains("abc"), "{shown}");
}

#[test]
fn display_of_a_constructed_error() {
    let e = DataError {
        file: "x.csv".to_string(),
        line: 12,
        message: "bad thing".to_string(),
    };
    assert_eq!(e.to_string(), "x.csv:12: bad thing");
    // Line 0 concerns the whole file and is not shown as a line number.
    let whole = DataError {
        file: "x.csv".to_string(),
        line: 0,
        message: "empty file".to_string(),
    };
    assert_eq!(whole.to_string(), "x.csv: empty file");
    // It is a std error, usable with `?` into Box<dyn Error>.
    let boxed: Box<dyn std::error::Error> = Box::new(e);
    assert_eq!(boxed.to_string(), "x.csv:12: bad thing");
}
