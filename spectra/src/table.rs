//! Reading spectral tables: CSV with one header row, wavelength in nm in the first column.
//!
//! Every malformed input is an error that names the file and the line; nothing is skipped.
//!
//! What a reader does with negative values is [`Negatives`]'s to say.

use std::borrow::ToOwned;
use std::string::{String, ToString};
use std::vec::Vec;

use crate::DataError;

/// How far below zero a value may be, relative to the file's largest value, and still be read
/// as rounding noise: values at or above `−NEGATIVE_TOLERANCE × largest` are read as 0.
///
/// One part in a million is ten orders of magnitude above the rounding noise of a file written
/// in double precision (about 1e-16 of its largest value), and below what a measured reflectance
/// or sensitivity can be trusted to.
pub const NEGATIVE_TOLERANCE: f64 = 1e-6;

/// What a reader does with values below zero.
///
/// Spectra (reflectances, spectral power, sensitivities, colour-matching functions) are
/// non-negative, but measured files carry rounding noise: values such as −7e-18 where the
/// instrument's software subtracted two nearly equal numbers. One rule serves every reader of
/// spectra (the observer tables, the report's and the planner's files, a scene's lights,
/// sensors and plan spectra):
///
/// - a value at or above −1e-6 × the file's largest value is noise: it is read as 0, and a
///   [`ZeroedNegatives`] counts such values and names the first one's line and column, for the
///   caller to report once as a warning (the build script as `cargo:warning`, the tools on
///   standard error);
/// - a more negative value is an error naming the file, the line and the column, unless the
///   caller opts in to [`Negatives::Clamp`] (for measured data whose noise is larger): then it
///   is read as 0 too, and counted apart in the same warning.
///
/// A file whose largest value is 0 or negative has no scale: every negative value in it is
/// beyond the tolerance.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Negatives {
    /// Values within `NEGATIVE_TOLERANCE` of zero (relative to the file's largest value) are
    /// read as 0 and reported; a more negative value is an error naming file, line and column.
    #[default]
    Refuse,
    /// Every negative value is read as 0 and reported (the count beyond the tolerance apart):
    /// the opt-in for measured data whose noise exceeds the tolerance.
    Clamp,
}

/// One value of a table, where a message points to it.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct ValueAt {
    /// 1-based line of the file.
    pub line: u64,
    /// 1-based column of the file (the wavelength is column 1).
    pub column: usize,
    /// The column's name in the header.
    pub name: String,
    /// The value as read (before it was set to 0).
    pub value: f64,
}

/// The negative values a reader read as 0 in one file: what its warning says.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct ZeroedNegatives {
    /// The file's label.
    pub file: String,
    /// How many values were read as 0.
    pub count: usize,
    /// How many of them lay beyond the tolerance (only with [`Negatives::Clamp`]; otherwise 0).
    pub beyond_tolerance: usize,
    /// The first one, in file order.
    pub first: ValueAt,
    /// The most negative one (the first of equals).
    pub most_negative: ValueAt,
    /// The file's largest value, which the tolerance is relative to.
    pub largest: f64,
}

impl core::fmt::Display for ZeroedNegatives {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let (first, low) = (&self.first, &self.most_negative);
        write!(
            f,
            "{}:{}: column {} ({}): {} read as 0, the first here ({})",
            self.file,
            first.line,
            first.column,
            first.name,
            count(self.count, "negative value"),
            number(first.value)
        )?;
        if self.beyond_tolerance == 0 {
            write!(
                f,
                "; all within the tolerance ({} × the file's largest value {}), as rounding noise",
                number(NEGATIVE_TOLERANCE),
                number(self.largest)
            )?;
        } else {
            write!(
                f,
                "; {} beyond the tolerance ({} × the file's largest value {}) clamped as asked",
                count(self.beyond_tolerance, "value"),
                number(NEGATIVE_TOLERANCE),
                number(self.largest)
            )?;
        }
        if self.count > 1 {
            write!(
                f,
                "; the most negative {} at line {}, column {} ({})",
                number(low.value),
                low.line,
                low.column,
                low.name
            )?;
        }
        Ok(())
    }
}

/// `1 value`, `3 values`.
fn count(n: usize, what: &str) -> String {
    if n == 1 {
        std::format!("1 {what}")
    } else {
        std::format!("{n} {what}s")
    }
}

/// A value as a message shows it: in exponent form when very small or large, so that a
/// rounding residue reads as `-6.93889390391e-18`, not as twenty zeros.
fn number(v: f64) -> String {
    if v != 0.0 && !(1e-3..1e6).contains(&v.abs()) {
        std::format!("{v:e}")
    } else {
        std::format!("{v}")
    }
}

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
#[non_exhaustive]
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
    /// The negative values read as 0 (see [`Negatives`]), for the caller to report; `None` when
    /// the file has none.
    pub zeroed: Option<ZeroedNegatives>,
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
/// Negative values follow [`Negatives::Refuse`] (see [`parse_table_with`]).
///
/// Errors (each naming `file` and the line): an empty file, a header without value columns, a
/// row with missing or extra fields, a field that is not a number or is not finite, wavelengths
/// that are not strictly increasing, (with [`Spacing::Even`]) uneven steps, and a value below
/// zero by more than the tolerance (naming its column too).
pub fn parse_table(
    file: &str,
    text: &str,
    columns: Option<usize>,
    spacing: Spacing,
) -> Result<Table, DataError> {
    parse_table_with(file, text, columns, spacing, Negatives::Refuse)
}

/// [`parse_table`], with the rule for negative values given: values within
/// [`NEGATIVE_TOLERANCE`] of zero (relative to the file's largest value) are read as 0 and
/// counted in [`Table::zeroed`]; a more negative value is an error naming the file, its line and
/// column with [`Negatives::Refuse`], and is read as 0 and counted with [`Negatives::Clamp`].
pub fn parse_table_with(
    file: &str,
    text: &str,
    columns: Option<usize>,
    spacing: Spacing,
    negatives: Negatives,
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
        zeroed: None,
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
    zero_negatives(&mut table, negatives)?;
    Ok(table)
}

/// Applies the rule for negative values (see [`parse_table_with`]) to a parsed table: the first
/// value in file order beyond the tolerance is the error.
fn zero_negatives(table: &mut Table, negatives: Negatives) -> Result<(), DataError> {
    let values = table.values.iter().flatten();
    if !values.clone().any(|v| *v < 0.0) {
        return Ok(());
    }
    let largest = values.fold(f64::NEG_INFINITY, |m, v| m.max(*v));
    // Without a positive value there is no scale: no negative value is noise.
    let floor = -NEGATIVE_TOLERANCE * largest.max(0.0);
    let mut zeroed: Option<ZeroedNegatives> = None;
    for (row, &line) in table.values.iter_mut().zip(&table.lines) {
        for (j, v) in row.iter_mut().enumerate() {
            if *v >= 0.0 {
                continue;
            }
            let cell = ValueAt {
                line,
                column: j + 2,
                name: table.columns[j].clone(),
                value: *v,
            };
            let beyond = *v < floor;
            if beyond && negatives == Negatives::Refuse {
                let why = if largest > 0.0 {
                    std::format!(
                        "beyond the tolerance for rounding noise ({}: {} × the file's largest value, {})",
                        number(floor),
                        number(NEGATIVE_TOLERANCE),
                        number(largest)
                    )
                } else {
                    "and the file has no positive value to scale a tolerance for rounding noise"
                        .to_owned()
                };
                return Err(DataError {
                    file: table.file.clone(),
                    line,
                    message: std::format!(
                        "column {} ({}): {} is negative, {why}; spectra must be non-negative (for measured data whose noise is larger, opt in to clamping: --clamp-negatives in the report and the planner, clamp_negatives = true in a scene)",
                        cell.column,
                        cell.name,
                        number(cell.value),
                    ),
                });
            }
            *v = 0.0;
            match &mut zeroed {
                None => {
                    zeroed = Some(ZeroedNegatives {
                        file: table.file.clone(),
                        count: 1,
                        beyond_tolerance: usize::from(beyond),
                        first: cell.clone(),
                        most_negative: cell,
                        largest,
                    })
                }
                Some(z) => {
                    z.count += 1;
                    z.beyond_tolerance += usize::from(beyond);
                    if cell.value < z.most_negative.value {
                        z.most_negative = cell;
                    }
                }
            }
        }
    }
    table.zeroed = zeroed;
    Ok(())
}

/// Reads and parses a file from disk ([`parse_table`]); the error names the path.
pub fn read_table(
    path: &std::path::Path,
    columns: Option<usize>,
    spacing: Spacing,
) -> Result<Table, DataError> {
    read_table_with(path, columns, spacing, Negatives::Refuse)
}

/// [`read_table`] with the rule for negative values given ([`parse_table_with`]).
pub fn read_table_with(
    path: &std::path::Path,
    columns: Option<usize>,
    spacing: Spacing,
    negatives: Negatives,
) -> Result<Table, DataError> {
    let (label, text) = read_text(path)?;
    parse_table_with(&label, &text, columns, spacing, negatives)
}

/// Reads a file's text; the error names the path.
pub fn read_text(path: &std::path::Path) -> Result<(String, String), DataError> {
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
