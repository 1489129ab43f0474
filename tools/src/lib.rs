//! What only people at a desk need, on top of `spectral-quadrature-derive`: the analysis behind
//! the report and the planner. The programs are `report` (error against run time, the crate's
//! main job), `plan` (a scene for an error budget) and `tables` (the derived tables beside the
//! paper's).
//!
//! - [`budget`]: every method at each wavelength budget (report section 5).
//! - [`prefilter`]: spiky lamps, band-averaged and exact-line pre-filtering (section 6d).
//! - [`stability`]: unstable alternatives to the crate's quadrature (section 6b).
//! - [`sensitivity`]: how rules move with the grid, the range and the observer (section 6c).
#![deny(missing_docs)]

pub mod budget;
pub mod prefilter;
pub mod sensitivity;
pub mod stability;

/// The runtime crate's `data/` in this workspace: the CIE tables, illuminants and reflectances
/// the derivation reads ([`spectral_quadrature_derive::Settings::data_dir`]).
pub const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../data");

/// The paper's settings on the workspace's data ([`DATA_DIR`]).
pub fn settings() -> spectral_quadrature_derive::Settings {
    spectral_quadrature_derive::Settings::new(DATA_DIR)
}
