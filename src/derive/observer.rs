//! CIE standard observers: colour-matching functions x̄, ȳ, z̄ read from the crate's `data/`.

use std::string::String;
use std::vec::Vec;

use super::table::{parse_table, DataError, Spacing};

/// The colour-matching functions the crate ships (all at 1 nm in `data/`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ObserverId {
    /// CIE 1931 2° (the paper's observer), 360-830 nm.
    Cie1931_2deg,
    /// CIE 1964 10°, 360-830 nm.
    Cie1964_10deg,
    /// CIE 2015 2° (CIE 170-2), 390-830 nm.
    Cie2015_2deg,
    /// CIE 2015 10° (CIE 170-2), 390-830 nm.
    Cie2015_10deg,
}

impl ObserverId {
    /// Every observer the crate ships.
    pub const ALL: [ObserverId; 4] = [
        ObserverId::Cie1931_2deg,
        ObserverId::Cie1964_10deg,
        ObserverId::Cie2015_2deg,
        ObserverId::Cie2015_10deg,
    ];

    /// The name used in settings, tables and CSV output, e.g. `cie1931_2deg`.
    pub fn name(self) -> &'static str {
        match self {
            ObserverId::Cie1931_2deg => "cie1931_2deg",
            ObserverId::Cie1964_10deg => "cie1964_10deg",
            ObserverId::Cie2015_2deg => "cie2015_2deg",
            ObserverId::Cie2015_10deg => "cie2015_10deg",
        }
    }

    /// Looks an observer up by [`name`](Self::name).
    pub fn from_name(name: &str) -> Option<ObserverId> {
        Self::ALL.into_iter().find(|o| o.name() == name)
    }

    /// The data file, relative to the crate root.
    pub fn file(self) -> &'static str {
        match self {
            ObserverId::Cie1931_2deg => "data/cmf_cie1931_2deg_1nm.csv",
            ObserverId::Cie1964_10deg => "data/cmf_cie1964_10deg_1nm.csv",
            ObserverId::Cie2015_2deg => "data/cmf_cie2015_2deg_1nm.csv",
            ObserverId::Cie2015_10deg => "data/cmf_cie2015_10deg_1nm.csv",
        }
    }

    /// The file's text, embedded in the crate so the derivation needs no file system.
    pub fn csv_text(self) -> &'static str {
        match self {
            ObserverId::Cie1931_2deg => include_str!("../../data/cmf_cie1931_2deg_1nm.csv"),
            ObserverId::Cie1964_10deg => include_str!("../../data/cmf_cie1964_10deg_1nm.csv"),
            ObserverId::Cie2015_2deg => include_str!("../../data/cmf_cie2015_2deg_1nm.csv"),
            ObserverId::Cie2015_10deg => include_str!("../../data/cmf_cie2015_10deg_1nm.csv"),
        }
    }

    /// Loads the embedded table.
    pub fn load(self) -> Result<Observer, DataError> {
        Observer::parse(self.name(), self.file(), self.csv_text())
    }
}

/// Colour-matching functions on an evenly spaced wavelength grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Observer {
    /// Name used in tables, e.g. `cie1931_2deg`.
    pub name: String,
    /// Where the data came from (file label).
    pub file: String,
    /// Wavelengths in nm, evenly spaced.
    pub wavelengths: Vec<f64>,
    /// x̄, ȳ, z̄ at each wavelength.
    pub xyz: Vec<[f64; 3]>,
    /// SHA-256 of the file's text, for generated headers.
    pub sha256: String,
}

impl Observer {
    /// Parses an observer table: header plus rows `wavelength,x_bar,y_bar,z_bar`, evenly spaced.
    /// Errors name `file` and the offending line.
    pub fn parse(name: &str, file: &str, text: &str) -> Result<Observer, DataError> {
        let table = parse_table(file, text, Some(3), Spacing::Even)?;
        Ok(Observer {
            name: name.into(),
            file: table.file,
            wavelengths: table.wavelengths,
            xyz: table.values.iter().map(|r| [r[0], r[1], r[2]]).collect(),
            sha256: super::sha256_hex(text.as_bytes()),
        })
    }

    /// Reads an observer table from a file on disk.
    pub fn read(name: &str, path: &std::path::Path) -> Result<Observer, DataError> {
        let (label, text) = super::table::read_text(path)?;
        Self::parse(name, &label, &text)
    }

    /// The table's step in nm.
    pub fn step(&self) -> f64 {
        if self.wavelengths.len() < 2 {
            0.0
        } else {
            self.wavelengths[1] - self.wavelengths[0]
        }
    }

    /// Indices of the rows on the grid `start, start + step, ..., end` (inclusive), or an error
    /// saying why that grid is not a subset of this table.
    pub fn grid_rows(&self, start: f64, end: f64, step: f64) -> Result<Vec<usize>, String> {
        let own = self.step();
        let first = *self.wavelengths.first().ok_or("empty observer table")?;
        let last = *self.wavelengths.last().ok_or("empty observer table")?;
        if !(start.is_finite() && end.is_finite() && step.is_finite())
            || start >= end
            || step <= 0.0
        {
            return Err(std::format!(
                "range {start}-{end} nm with step {step} nm is not a valid grid"
            ));
        }
        if start < first - 1e-9 || end > last + 1e-9 {
            return Err(std::format!(
                "range {start}-{end} nm is not covered by {} ({first}-{last} nm)",
                self.file
            ));
        }
        let ratio = step / own;
        let per = ratio.round();
        if per < 1.0 || (ratio - per).abs() > 1e-9 {
            return Err(std::format!(
                "step {step} nm is not a whole multiple of {}'s {own} nm",
                self.file
            ));
        }
        let per = per as usize;
        let offset = (start - first) / own;
        if (offset - offset.round()).abs() > 1e-9 {
            return Err(std::format!(
                "range start {start} nm is not on {}'s grid",
                self.file
            ));
        }
        let span = (end - start) / step;
        if (span - span.round()).abs() > 1e-9 {
            return Err(std::format!(
                "range {start}-{end} nm is not a whole number of {step} nm steps"
            ));
        }
        let first_row = offset.round() as usize;
        Ok((0..=span.round() as usize)
            .map(|k| first_row + k * per)
            .collect())
    }
}
