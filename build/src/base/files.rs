//! The data files: where a label such as `data/illuminant_C.csv` lives under the data
//! directory, reading it with an error that names it, and the SHA-256 checksums that generated
//! headers give for every input.

use std::path::{Path, PathBuf};
use std::string::String;
use std::vec::Vec;

use super::error::DataError;

/// Hex SHA-256 of some bytes (checksums of inputs in generated headers).
pub(crate) fn sha256_hex(bytes: &[u8]) -> String {
    use sha2::Digest;
    let digest = sha2::Sha256::digest(bytes);
    digest.iter().map(|b| std::format!("{b:02x}")).collect()
}

/// The path of a data file labelled `data/<file>` (or just `<file>`) under `data_dir`.
pub(crate) fn data_path(data_dir: &Path, label: &str) -> PathBuf {
    data_dir.join(label.strip_prefix("data/").unwrap_or(label))
}

/// Reads the data file labelled `data/<file>` under `data_dir` ([`data_path`]). The error names
/// the label, and the path it tried.
pub(crate) fn read_data(data_dir: &Path, label: &str) -> Result<Vec<u8>, DataError> {
    let path = data_path(data_dir, label);
    std::fs::read(&path).map_err(|e| read_error(label, &path, &e))
}

/// [`read_data`], as text.
pub(crate) fn read_data_text(data_dir: &Path, label: &str) -> Result<String, DataError> {
    let path = data_path(data_dir, label);
    std::fs::read_to_string(&path).map_err(|e| read_error(label, &path, &e))
}

/// The text of a cache file under `data_dir` that may be absent: `None` when there is no such
/// file; an error naming the label and the path when it cannot be read.
pub(crate) fn read_optional_text(
    data_dir: &Path,
    label: &str,
) -> Result<Option<String>, DataError> {
    let path = data_path(data_dir, label);
    match std::fs::read_to_string(&path) {
        Ok(t) => Ok(Some(t)),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(read_error(label, &path, &e)),
    }
}

/// The rows of a cache file's `text` below its header, each with its line number (from 1) and
/// trimmed; blank lines and `#` comments are skipped. An error names `file` and the line when the
/// first other line is not `header`.
pub(crate) fn cache_rows<'a>(
    file: &str,
    text: &'a str,
    header: &str,
) -> Result<Vec<(u64, &'a str)>, DataError> {
    let mut rows = Vec::new();
    let mut seen_header = false;
    for (i, raw) in text.lines().enumerate() {
        let line = i as u64 + 1;
        let l = raw.trim();
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        if !seen_header {
            if l != header {
                return Err(DataError {
                    file: file.into(),
                    line,
                    message: std::format!("expected the header {header}, found {l:?}"),
                });
            }
            seen_header = true;
            continue;
        }
        rows.push((line, l));
    }
    Ok(rows)
}

/// The error of a data file that could not be read: it names the label and the path.
pub(crate) fn read_error(label: &str, path: &Path, e: &std::io::Error) -> DataError {
    DataError {
        file: label.into(),
        line: 0,
        message: std::format!("cannot read {}: {e}", path.display()),
    }
}
