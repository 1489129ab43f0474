//! Reading spectral tables: CSV with one header row, wavelength in nm in the first column.
//!
//! Every malformed input is an error that names the file and the line; nothing is skipped.

use std::borrow::ToOwned;
use std::string::{String, ToString};
use std::vec::Vec;

use super::error::DataError;

/// How the wavelength column must be spaced.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Spacing {
    /// Strictly increasing with one constant step (observer tables).
    Even,
    /// Strictly increasing, any steps (user spectra, resampled later).
    Any,
}

/// A parsed table: wavelengths and one row of values per wavelength.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// The label errors name (a path or an embedded file's name).
    pub file: String,
    /// Column names after the wavelength column.
    pub columns: Vec<String>,
    /// Wavelengths in nm, strictly increasing.
    pub wavelengths: Vec<f64>,
    /// `values[i][j]`: column `j` at `wavelengths[i]`.
    pub values: Vec<Vec<f64>>,
    /// 1-based line number of each data row, for later error messages.
    pub lines: Vec<u64>,
}

impl Table {
    /// The constant step in nm (meaningful for [`Spacing::Even`] tables with two or more rows).
    pub fn step(&self) -> f64 {
        if self.wavelengths.len() < 2 {
            return 0.0;
        }
        self.wavelengths[1] - self.wavelengths[0]
    }

    fn error(&self, line: u64, message: impl Into<String>) -> DataError {
        DataError {
            file: self.file.clone(),
            line,
            message: message.into(),
        }
    }
}

/// Parses CSV text: a header row, then rows of numbers; the first column is the wavelength in
/// nm. `columns`, when given, is the required number of value columns after the wavelength.
///
/// Errors (each naming `file` and the line): an empty file, a header without value columns, a
/// row with missing or extra fields, a field that is not a number or is not finite, wavelengths
/// that are not strictly increasing, and (with [`Spacing::Even`]) uneven steps.
pub fn parse_table(
    file: &str,
    text: &str,
    columns: Option<usize>,
    spacing: Spacing,
) -> Result<Table, DataError> {
    let err = |line: u64, message: String| DataError {
        file: file.to_owned(),
        line,
        message,
    };
    // The csv crate skips blank lines and miscounts lines after "\r\n" (rust-csv#395): check
    // line structure here so that nothing is skipped and every line number is right.
    let normalized;
    let text = if text.contains('\r') {
        normalized = text.replace("\r\n", "\n");
        if let Some(at) = normalized.find('\r') {
            let line = normalized[..at].matches('\n').count() as u64 + 1;
            return Err(err(
                line,
                "bare carriage return (use \\n or \\r\\n line endings)".to_owned(),
            ));
        }
        normalized.as_str()
    } else {
        text
    };
    let lines: Vec<&str> = text.lines().collect();
    let last_content = lines.iter().rposition(|l| !l.trim().is_empty());
    if let Some(last) = last_content {
        if let Some(blank) = lines[..last].iter().position(|l| l.trim().is_empty()) {
            let what = if blank < lines.iter().position(|l| !l.trim().is_empty()).unwrap_or(0) {
                "empty line before the header"
            } else {
                "empty line inside the table"
            };
            return Err(err(blank as u64 + 1, what.to_owned()));
        }
    }
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let mut records = reader.records();
    let header = match records.next() {
        None => return Err(err(0, "empty file: expected a header row".to_owned())),
        Some(Err(e)) => return Err(err(line_of(&e), e.to_string())),
        Some(Ok(h)) => h,
    };
    let header_line = header.position().map_or(1, |p| p.line());
    if header.len() < 2 {
        return Err(err(
            header_line,
            "header needs a wavelength column and at least one value column".to_owned(),
        ));
    }
    let width = header.len() - 1;
    if let Some(expected) = columns {
        if width != expected {
            return Err(err(
                header_line,
                std::format!("header has {width} value columns, expected {expected}"),
            ));
        }
    }
    let columns: Vec<String> = header.iter().skip(1).map(ToString::to_string).collect();
    let mut table = Table {
        file: file.to_owned(),
        columns,
        wavelengths: Vec::new(),
        values: Vec::new(),
        lines: Vec::new(),
    };
    for record in records {
        let record = record.map_err(|e| err(line_of(&e), e.to_string()))?;
        let line = record.position().map_or(0, |p| p.line());
        if record.len() != width + 1 {
            let which = if record.len() < width + 1 {
                "missing"
            } else {
                "extra"
            };
            return Err(err(
                line,
                std::format!(
                    "{which} columns: {} fields, the header has {}",
                    record.len(),
                    width + 1
                ),
            ));
        }
        let mut row = Vec::with_capacity(width);
        for (i, field) in record.iter().enumerate() {
            let name = if i == 0 {
                "wavelength"
            } else {
                &table.columns[i - 1]
            };
            let value: f64 = field.parse().map_err(|_| {
                err(
                    line,
                    std::format!("column {} ({name}): {field:?} is not a number", i + 1),
                )
            })?;
            if !value.is_finite() {
                return Err(err(
                    line,
                    std::format!("column {} ({name}): {field:?} is not finite", i + 1),
                ));
            }
            row.push(value);
        }
        let wavelength = row.remove(0);
        if let Some(&previous) = table.wavelengths.last() {
            if wavelength <= previous {
                return Err(err(
                    line,
                    std::format!(
                        "wavelength {wavelength} nm is not greater than the previous row's {previous} nm"
                    ),
                ));
            }
            if spacing == Spacing::Even && table.wavelengths.len() >= 2 {
                let step = table.step();
                let this_step = wavelength - previous;
                // Published tables list wavelengths to a few decimals: 1e-6 nm is far below that.
                if (this_step - step).abs() > 1e-6 {
                    return Err(err(
                        line,
                        std::format!(
                            "uneven wavelength step: {this_step} nm after {previous} nm, the table's step is {step} nm"
                        ),
                    ));
                }
            }
        }
        table.wavelengths.push(wavelength);
        table.values.push(row);
        table.lines.push(line);
    }
    if table.wavelengths.is_empty() {
        return Err(table.error(header_line, "no data rows after the header"));
    }
    Ok(table)
}

/// Reads and parses a file from disk; the error names the path.
pub fn read_table(
    path: &std::path::Path,
    columns: Option<usize>,
    spacing: Spacing,
) -> Result<Table, DataError> {
    let (label, text) = read_text(path)?;
    parse_table(&label, &text, columns, spacing)
}

/// Reads a file's text; the error names the path.
pub(crate) fn read_text(path: &std::path::Path) -> Result<(String, String), DataError> {
    let label = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| DataError {
        file: label.clone(),
        line: 0,
        message: std::format!("cannot read: {e}"),
    })?;
    Ok((label, text))
}

fn line_of(e: &csv::Error) -> u64 {
    e.position().map_or(0, |p| p.line())
}
