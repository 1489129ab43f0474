//! The data files as the generator uses them beside `spectral-quadrature-spectra`'s readers:
//! the SHA-256 checksums that generated headers give for every input, and the cache files
//! (reading them where they may be absent, their rows, writing them).

use std::path::Path;
use std::string::String;
use std::vec::Vec;

use spectral_quadrature_spectra::{data_path, read_error, DataError};

/// Hex SHA-256 of some bytes (checksums of inputs in generated headers).
pub(crate) fn sha256_hex(bytes: &[u8]) -> String {
    use sha2::Digest;
    let digest = sha2::Sha256::digest(bytes);
    digest.iter().map(|b| std::format!("{b:02x}")).collect()
}

/// Reads the data file labelled `data/<file>` under `data_dir` ([`data_path`]). The error names
/// the label, and the path it tried.
pub(crate) fn read_data(data_dir: &Path, label: &str) -> Result<Vec<u8>, DataError> {
    let path = data_path(data_dir, label);
    std::fs::read(&path).map_err(|e| read_error(label, &path, &e))
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

/// The text of a CSV file the crate writes (the node and upsampling caches): `comments`, each
/// on a line of its own after `# `, then the header and the rows through the `csv` crate's
/// writer, which quotes a field where CSV needs it and refuses a row whose length differs from
/// the header's (a bug of the caller: this panics then).
pub(crate) fn write_csv(comments: &[&str], header: &str, rows: &[Vec<String>]) -> String {
    let mut text = String::new();
    for line in comments {
        text += "# ";
        text += line;
        text += "\n";
    }
    let mut writer = csv::WriterBuilder::new()
        .flexible(false)
        .from_writer(Vec::new());
    let written = writer
        .write_record(header.split(','))
        .and_then(|()| rows.iter().try_for_each(|r| writer.write_record(r)));
    if let Err(e) = written {
        panic!("a cache row does not fit its header ({header}): {e}");
    }
    let bytes = writer
        .into_inner()
        .unwrap_or_else(|e| panic!("writing to memory: {}", e.error()));
    text + &String::from_utf8(bytes).expect("the fields are UTF-8")
}
