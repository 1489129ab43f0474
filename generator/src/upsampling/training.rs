//! The reflectances the upsampling is fitted on: the CIE test colour samples and the 190
//! rawtoaces patches ([`TRAINING_FILES`]). The ColorChecker is left out, so that the report can
//! judge the fit on reflectances it never saw.

use std::string::String;
use std::vec::Vec;

use crate::base::error::{DataError, Error};
use crate::base::files::read_data_text;
use crate::base::table::{parse_table, Spacing};
use crate::derivation::evaluate::{Curve, MAX_WAVELENGTH_NM};

/// The training reflectances (labels relative to the runtime crate).
pub const TRAINING_FILES: [&str; 2] = [
    "data/reflectance_cie_tcs.csv",
    "data/reflectance_rawtoaces_190.csv",
];

/// How far below zero a reflectance in a training file may be and still be read, as zero.
/// `reflectance_rawtoaces_190.csv` holds values such as −6.9e-18 and −5.6e-17: the rounding
/// noise of a computation, ten orders of magnitude below the files' fourth decimal. 1e-9 takes
/// such noise and nothing a measurement could mean; anything more negative is an error naming
/// the file, the line and the column.
pub const NEGATIVE_TOLERANCE: f64 = 1e-9;

/// Parses one training file: a spectra table whose values are reflectances in [0, 1] up to
/// [`NEGATIVE_TOLERANCE`] below zero (read as zero); the curves must cover `range_nm`.
pub fn parse_training(file: &str, text: &str, range_nm: [f64; 2]) -> Result<Vec<Curve>, DataError> {
    let table = parse_table(file, text, None, Spacing::Any)?;
    let err = |line: u64, message: String| DataError {
        file: file.into(),
        line,
        message,
    };
    let (first, last) = (
        table.wavelengths[0],
        table.wavelengths[table.wavelengths.len() - 1],
    );
    if !(first > 0.0 && last <= MAX_WAVELENGTH_NM) {
        return Err(err(table.lines[0], "wavelengths are not in nm".into()));
    }
    if first > range_nm[0] + 1e-9 || last < range_nm[1] - 1e-9 {
        return Err(err(
            table.lines[0],
            std::format!(
                "the data cover {first}-{last} nm; the observer needs {}-{} nm",
                range_nm[0],
                range_nm[1]
            ),
        ));
    }
    let mut values = table.values.clone();
    for (row, line) in values.iter_mut().zip(&table.lines) {
        for (j, v) in row.iter_mut().enumerate() {
            if *v < -NEGATIVE_TOLERANCE {
                return Err(err(
                    *line,
                    std::format!(
                        "column {} ({}): {} is negative beyond the tolerance of {NEGATIVE_TOLERANCE:e}",
                        j + 2,
                        table.columns[j],
                        v
                    ),
                ));
            }
            *v = v.max(0.0);
        }
    }
    Ok((0..table.columns.len())
        .map(|k| Curve {
            name: table.columns[k].clone(),
            wavelengths: table.wavelengths.clone(),
            values: values.iter().map(|r| r[k]).collect(),
        })
        .collect())
}

/// The training reflectances from the runtime crate's `data/` directory.
pub fn training(data_dir: &std::path::Path, range_nm: [f64; 2]) -> Result<Vec<Curve>, Error> {
    let mut out = Vec::new();
    for file in TRAINING_FILES {
        let text = read_data_text(data_dir, file)?;
        out.extend(parse_training(file, &text, range_nm)?);
    }
    Ok(out)
}
