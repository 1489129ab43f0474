//! The reflectances the upsampling is fitted on: the CIE test colour samples and the 190
//! rawtoaces patches ([`TRAINING_FILES`]). The ColorChecker is left out, so that the report can
//! judge the fit on reflectances it never saw.

use std::vec::Vec;

use crate::base::error::Error;
#[cfg(doc)]
use spectral_quadrature_spectra::NEGATIVE_TOLERANCE;
use spectral_quadrature_spectra::{read_data_text, Curve, DataError, Spectra};

/// The training reflectances (labels relative to the runtime crate).
pub(crate) const TRAINING_FILES: [&str; 2] = [
    "data/reflectance_cie_tcs.csv",
    "data/reflectance_rawtoaces_190.csv",
];

/// Parses one training file with the crate's one reader of spectra ([`Spectra::parse`]):
/// rounding noise down to [`NEGATIVE_TOLERANCE`] of the file's largest value is read as zero
/// (`reflectance_rawtoaces_190.csv` holds 19 values such as −6.9e-18 and −2.2e-16), anything
/// more negative is an error naming the file, the line and the column; the curves must cover
/// `range_nm`.
pub(crate) fn parse_training(
    file: &str,
    text: &str,
    range_nm: [f64; 2],
) -> Result<Vec<Curve>, DataError> {
    Spectra::parse(file, text)?.curves(range_nm)
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
