//! # spectral-quadrature
//!
//! At which few wavelengths must a renderer evaluate a spectrum, and how does it turn those
//! samples into colour? This crate answers with G. W. Meyer's *Wavelength Selection for
//! Synthetic Image Generation* (1988): an opponent colour space AC1C2 from a Karhunen-Loeve
//! expansion of the cone fundamentals, and Gaussian quadrature with the opponent sensitivities as
//! weight functions.
//!
//! The whole derivation runs at compile time (`build.rs`, f64, nalgebra) and is baked into the
//! `const` items of [`tables`]; the runtime is `#![no_std]`, never allocates, and is a handful of
//! multiply-adds per pixel.
//!
//! ```
//! use spectral_quadrature::tables::TABLE2_ROW2;
//!
//! // Paper, Table 2 row 2: four wavelengths for all three channels.
//! let set = TABLE2_ROW2;
//! // Sample an equal-energy spectrum at the set's wavelengths ...
//! let samples = [1.0f32; 4];
//! // ... and get A, C1, C2 (weights are for dλ in nm).
//! let [a, c1, c2] = set.ac1c2(&samples);
//! assert!(a > 100.0 && c1.abs() < a && c2 > 0.0);
//! ```
//!
//! ## Features
//! - `std`: links the standard library (needed by `derive`).
//! - `derive`: the host-side f64 derivation as [`mod@derive`], for users who want to
//!   run it with their own settings or data.
#![no_std]
#![cfg_attr(docsrs, feature(doc_cfg))]
#![deny(missing_docs)]

#[cfg(feature = "std")]
extern crate std;

mod set;

pub mod paper;

pub use set::{Channel, GaussRule, RuleStatus, WavelengthSet};

/// The tables baked at compile time by `build.rs` from `data/` (see the header of the generated
/// file for the inputs and their checksums).
pub mod tables {
    include!(concat!(env!("OUT_DIR"), "/tables.rs"));
}

#[cfg(feature = "derive")]
#[cfg_attr(docsrs, doc(cfg(feature = "derive")))]
pub mod derive;

/// The README's examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;
