//! The Cornell box rendered with every spectral method, on top of the desk tools' library
//! (`spectral-quadrature-tools`: the upsampling peers, the random-wavelength samplers, the data
//! folder). The programs are `cornell` (the box by radiosity, once per spectral method) and
//! `render` (the box path traced with every method, error against render time).
//!
//! - [`cornell`]: the Cornell box rendered by radiosity, once per spectral method (`cornell`).
//! - [`render`]: one path tracer for every spectral method, error against render time (`render`).
#![deny(missing_docs)]

pub mod cornell;
pub mod render;

/// The error of every fallible function here: the desk tools' error
/// ([`spectral_quadrature_tools::Error`]), whose data errors name the file and line.
pub use spectral_quadrature_tools::Error;
