//! The build-time generator behind `spectral-quadrature`, in f64: Meyer's method from CIE data
//! to Gauss rules, the shared (kernel-quadrature) sets, scenes, and the code generation of the
//! runtime's `const` tables and shader snippets.
//!
//! The runtime's `build.rs` calls [`generate`] with the path of its crate (as chrono-tz's build
//! script calls chrono-tz-build); the tests compare the baked tables with a fresh derivation;
//! the desk tools (report, planner) build on it; and users can run it with their own settings or
//! data:
//!
//! ```
//! use spectral_quadrature_generator::{derive, Settings};
//! # let data_dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../data");
//! // data_dir: a directory laid out like the runtime crate's data/ (CIE tables as CSV).
//! let d = derive(&Settings::new(data_dir)).unwrap();
//! let a3 = &d.rules[0][2]; // channel A, order 3
//! assert_eq!(a3.nodes_nm.len(), 3);
//! ```
//!
//! # What lives here and why
//!
//! Everything a baked table needs, and nothing else: a downstream build runs this crate at
//! Cargo's default build-script opt-level 0. [`plan`] stays here because a scene with a `[plan]`
//! section is resolved at build time by measuring sets against the scene's spectra; the report,
//! the stability and sensitivity studies and the pre-filtering analysis live in the
//! `spectral-quadrature-tools` crate.
//!
//! Spectra come from `spectral-quadrature-spectra`, the crate below this one: the CSV reader
//! (errors naming file and line, negative values as its `Negatives` says), curves, stimuli and
//! the measuring of sets in CIELAB (`EvalSet`, `Reference`). This crate builds the measured
//! sets of a derivation: the exact integration and the uniform sets on the observer's grid
//! ([`Observer::full_integration`], [`Observer::uniform_set`]) and a derived set in XYZ
//! ([`Derivation::eval_set`]).
//!
//! The steps, named after the paper: [`Observer`] holds x̄ȳz̄; [`Opponent`] holds the cone
//! fundamentals (Eq. 1), the covariance (Eq. 4-5) and the KL transform (Eq. 9-10);
//! [`quadrature`] runs the recurrence (Eq. 16) and forms each order's rule; a [`WavelengthSet`]
//! merges rules (Table 2); [`generate`] writes the tables the runtime includes.
//! [`shared`] finds the shared sets by kernel quadrature, and [`user`] fits sets to what a
//! scene brings: a light by file, fixed wavelengths, a sensor's channels. Every fallible
//! function returns [`Error`].
//!
//! # Layout
//!
//! The sources are grouped by role, each role a folder whose modules import only the roles
//! below it (`python3 .ci/module-graph generator/src` prints the graph and fails on a cycle):
//!
//! 1. `base`: the errors, the checksums of the data files, and the cache files;
//! 2. `derivation`: [`Settings`], [`derive()`] and its steps (`observer`, `opponent`,
//!    [`quadrature`], `sets`), the display matrices ([`display`]), the exact integration on the
//!    observer's grid, the Planckian locus and the exact CCT ([`PlanckianLocus`]);
//! 3. `shared`: the shared sets ([`shared`]: model, fit, node search, node cache, light
//!    groups); beside it `upsampling`: RGB materials at a set's nodes ([`upsampling`]: a map's
//!    grid, its training spectra, the bounded least squares, the maps' cache);
//! 4. `scenes`: the scene file ([`scene`]), the sets by name ([`catalog`]), the user's inputs
//!    ([`user`]), a sensor's white reference and fitted calibration ([`calibration`]) and the
//!    planner ([`plan`]);
//! 5. `emit`: the scene's baked model (`model`: every constant, computed once, as f32) and its
//!    formatters, the Rust tables (`codegen`) and the shader snippets ([`shader`]), and
//!    [`generate`].
//!
//! This file only re-exports: the modules above under their own names, and at the root what
//! most callers need.

#![deny(missing_docs)]

mod base;
mod derivation;
mod emit;
mod scenes;
pub mod shared;
#[cfg(test)]
mod tests;
pub mod upsampling;

pub use base::error::{CalibrationProblem, Error, LightProblem, SetNameProblem};
pub use derivation::derive::{derive, derive_with, Derivation};
pub use derivation::observer::{Observer, ObserverId};
pub use derivation::opponent::{Covariance, Opponent};
pub use derivation::planckian::PlanckianLocus;
pub use derivation::quadrature::{Measure, Recurrence, Rule, Status};
pub use derivation::sets::{WavelengthSet, SAME_WAVELENGTH_NM};
pub use derivation::settings::Settings;
pub use derivation::{display, quadrature};
pub use emit::generate::{generate, Output};
pub use emit::{fixed_point, shader};
pub use scenes::scene::SCENE_ENV;
pub use scenes::{calibration, catalog, plan, scene, user};
/// Why a display is refused: the one type the runtime (`Error::Display`) and the derivation
/// ([`Error::Display`]) report.
pub use spectral_quadrature_math::DisplayError;
// The paths the unit tests (src/tests/) name.
#[cfg(test)]
use {
    derivation::{observer, opponent, planckian},
    emit::codegen,
};
