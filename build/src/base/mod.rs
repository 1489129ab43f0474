//! The bottom layer, which every role uses and which uses none: the error types, the data
//! files (paths, reading, checksums) and the CSV reader of spectral tables.

pub(crate) mod error;
pub(crate) mod files;
pub(crate) mod table;
