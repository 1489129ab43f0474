//! Helpers the test modules share: observer-shaped and one-column tables, and the checks of a
//! `DataError`.

use spectral_quadrature_spectra::{parse_table, DataError, Spacing};

/// The header of an observer-shaped table: the wavelength, then three value columns.
pub const HEADER: &str = "wavelength_nm,x_bar,y_bar,z_bar";

/// An observer-shaped table: `HEADER` then the given rows, one per line.
pub fn table_text(rows: &[&str]) -> String {
    let mut text = String::from(HEADER);
    text.push('\n');
    for row in rows {
        text.push_str(row);
        text.push('\n');
    }
    text
}

/// Parses `text` as an observer-shaped table that must fail; returns the error.
pub fn parse_err(label: &str, text: &str, columns: Option<usize>, spacing: Spacing) -> DataError {
    match parse_table(label, text, columns, spacing) {
        Ok(t) => panic!(
            "{label}: expected an error, parsed {} rows",
            t.wavelengths.len()
        ),
        Err(e) => e,
    }
}

/// Asserts that `e` names `file`, `line`, and that its message contains every keyword
/// (case-insensitive).
pub fn assert_error(e: &DataError, file: &str, line: u64, keywords: &[&str]) {
    assert_eq!(e.file, file, "wrong file in {e:?}");
    assert_eq!(e.line, line, "wrong line in {e:?}");
    let message = e.message.to_lowercase();
    for k in keywords {
        assert!(
            message.contains(&k.to_lowercase()),
            "message of {e:?} lacks {k:?}"
        );
    }
}

/// A one-column spectra table (`wavelength_nm,s`), rows `nm,value`.
pub fn spectra_text(header: &str, rows: &[&str]) -> String {
    let mut text = format!("{header}\n");
    for row in rows {
        text.push_str(row);
        text.push('\n');
    }
    text
}
