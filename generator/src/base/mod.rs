//! The bottom layer, which every role uses and which uses none: the error types, and the data
//! files beside `spectral-quadrature-spectra`'s readers (checksums, the cache files).

pub(crate) mod error;
pub(crate) mod files;
