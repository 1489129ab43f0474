//! # spectral-quadrature-math
//!
//! The colour maths that `spectral-quadrature` (the `no_std` runtime) and its build-time
//! generator both need, in one copy, so that a colour difference or a display matrix means the
//! same on either side:
//!
//! - CIELAB and colour differences: [`lab_from_xyz`], [`delta_e76`] (ΔE*ab 1976) and
//!   [`delta_e2000`] (CIEDE2000, checked against Sharma, Wu and Dalal's 34 test pairs).
//! - Display matrices from three primaries and a white point (CIE 1931 xy):
//!   [`display_matrices`] gives linear RGB → XYZ and back with the white balance derived from
//!   the primaries and the white, and refuses nearly collinear primaries by one definition, the
//!   2-norm [`condition_number`] against [`MAX_PRIMARIES_CONDITION`], and whites on or outside
//!   the primaries' triangle by [`MIN_WHITE_SHARE`].
//!
//! ```
//! use spectral_quadrature_math::{delta_e2000, delta_e76, display_matrices, lab_from_xyz};
//!
//! let srgb = display_matrices([[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]], [0.3127, 0.3290])
//!     .unwrap();
//! let white = [0.9505, 1.0, 1.089];
//! let grey = lab_from_xyz([0.18 * 0.9505, 0.18, 0.18 * 1.089], white);
//! let lighter = lab_from_xyz([0.19 * 0.9505, 0.19, 0.19 * 1.089], white);
//! assert!(delta_e76(grey, lighter) > 1.0 && delta_e2000(grey, lighter) > 0.5);
//! assert!(srgb.condition < 25.0);
//! ```
//!
//! Everything is f64, `#![no_std]`, allocation-free and panic-free, with the transcendental
//! functions from `libm`, so the results are the same bits on every target. In the runtime this
//! is the opt-in path, never per pixel: measuring colour differences, and displays made at run
//! time (`Display::new`). On a microcontroller without a double-precision FPU, f64 is
//! soft-float.
#![no_std]
#![deny(missing_docs)]
#![forbid(unsafe_code)]

mod display;
mod lab;

pub use display::{
    condition_number, display_matrices, invert3, xyz_from_xy, DisplayError, DisplayMatrices, Point,
    MAX_PRIMARIES_CONDITION, MIN_WHITE_SHARE,
};
pub use lab::{delta_e2000, delta_e76, lab_from_xyz};
