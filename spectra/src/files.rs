//! The data files by label: where a label such as `data/illuminant_C.csv` lives under a data
//! directory, and reading it with an error that names it.

use std::path::{Path, PathBuf};
use std::string::String;

use crate::DataError;

/// The path of a data file labelled `data/<file>` (or just `<file>`) under `data_dir`.
pub fn data_path(data_dir: &Path, label: &str) -> PathBuf {
    data_dir.join(label.strip_prefix("data/").unwrap_or(label))
}

/// Reads the data file labelled `data/<file>` under `data_dir` ([`data_path`]) as text. The
/// error names the label, and the path it tried.
pub fn read_data_text(data_dir: &Path, label: &str) -> Result<String, DataError> {
    let path = data_path(data_dir, label);
    std::fs::read_to_string(&path).map_err(|e| read_error(label, &path, &e))
}

/// The error of a data file that could not be read: it names the label and the path.
pub fn read_error(label: &str, path: &Path, e: &std::io::Error) -> DataError {
    DataError {
        file: label.into(),
        line: 0,
        message: std::format!("cannot read {}: {e}", path.display()),
    }
}
