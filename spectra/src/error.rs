//! The one error of this crate: a data file that is malformed or cannot be read, with the file
//! and the line.

use std::fmt;
use std::string::String;

/// What is wrong with a data file, and where.
#[derive(Debug, Clone, PartialEq)]
pub struct DataError {
    /// The file (or the label of embedded text) the error is in.
    pub file: String,
    /// 1-based line number, or 0 where the error concerns the file as a whole.
    pub line: u64,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for DataError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line == 0 {
            write!(f, "{}: {}", self.file, self.message)
        } else {
            write!(f, "{}:{}: {}", self.file, self.line, self.message)
        }
    }
}

impl std::error::Error for DataError {}
