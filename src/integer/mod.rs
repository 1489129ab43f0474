//! The integer path: integer samples (16-bit counts, as a sensor or an ADC gives them) → 8-bit
//! display RGB with integer arithmetic only, for microcontrollers without an FPU (Cortex-M0+),
//! where every f32 operation is a library call. [`IntegerSet`] says how and why.
//!
//! This file only declares the submodules: `set` is the type, its constructor and its
//! encoding of counts; below it are `curve` (the transfer curve on the integer scales),
//! `fixed_point` (the weights' conversion, the multiply-accumulate steps), `dsp` (Armv7E-M's
//! dual multiply-accumulate) and `armv6m` (a pixel's common path on Armv6-M).

// Unsafe code only in `dsp` and `armv6m`: inline assembly, on Armv7E-M and Armv6-M. The
// other submodules forbid it.
#![deny(unsafe_code)]

mod armv6m;
mod curve;
mod dsp;
mod fixed_point;
mod set;

pub use set::{IntegerSet, INTEGER_MAX_ERROR_CODES};
