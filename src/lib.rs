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

mod batch;
mod display;
mod dynamic;
mod encode;
mod error;
mod lab;
mod set;
mod soa;

#[cfg(feature = "defmt")]
mod defmt;
#[cfg(feature = "micromath")]
mod fast;

pub mod paper;

pub use display::{
    quantize_u16, quantize_u8, ChannelLuts, Display, GamutMapping, TransferFunction,
};
pub use dynamic::DynamicSet;
pub use encode::{srgb8_from_linear, SRGB8_MAX_DELTA_E, SRGB8_MAX_STEP_ERROR};
pub use error::Error;
#[cfg(feature = "micromath")]
pub use fast::ENCODE_FAST_MAX_ERROR;
pub use lab::{delta_e2000, delta_e76, lab_from_xyz};
pub use set::{Channel, FoldedSet, GaussRule, RuleStatus, WavelengthSet};

/// `[X, Y, Z]` from `[A, C1, C2]` with [`tables::AC1C2_TO_XYZ`]. IEEE arithmetic: NaN and ±Inf
/// propagate; never panics.
#[inline]
pub fn xyz_from_ac1c2(ac1c2: [f32; 3]) -> [f32; 3] {
    mat3_vec(&tables::AC1C2_TO_XYZ, ac1c2)
}

/// `[A, C1, C2]` from `[X, Y, Z]` with [`tables::XYZ_TO_AC1C2`] (Eq. 9). IEEE arithmetic: NaN
/// and ±Inf propagate; never panics.
#[inline]
pub fn ac1c2_from_xyz(xyz: [f32; 3]) -> [f32; 3] {
    mat3_vec(&tables::XYZ_TO_AC1C2, xyz)
}

/// The f32 error budget of an N-term weighted sum whose terms have absolute sum `abs_sum`
/// (`Σ |w_i · s_i|`): `(N + 1) · f32::EPSILON · abs_sum + N · 2⁻¹⁵⁰`. This is the stated accuracy
/// of [`WavelengthSet::ac1c2`] and [`FoldedSet::linear_rgb`] against the exact f64 sum; the tests
/// assert it. Computed in f64; `abs_sum` NaN or infinite gives NaN or infinity.
pub fn f32_budget(n: usize, abs_sum: f64) -> f64 {
    const HALF_SUBNORMAL: f64 = 7.006_492_321_624_085e-46; // 2^-150
    (n as f64 + 1.0) * f64::from(f32::EPSILON) * abs_sum + n as f64 * HALF_SUBNORMAL
}

#[inline]
pub(crate) fn mat3_vec(m: &[[f32; 3]; 3], v: [f32; 3]) -> [f32; 3] {
    [
        m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
        m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
        m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2],
    ]
}

pub(crate) fn mat3_mul(a: &[[f32; 3]; 3], b: &[[f32; 3]; 3]) -> [[f32; 3]; 3] {
    let mut out = [[0.0f32; 3]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    out
}

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
