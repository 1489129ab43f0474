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
//! The same tables and per-pixel path, as WGSL and GLSL source for shaders, are in
//! [`tables::shaders`].
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
//! The derivation itself is the crate `spectral-quadrature-generator`, this crate's
//! build-dependency: use it directly to run it with your own settings or data. CIELAB, the
//! colour differences and the display matrices come from `spectral-quadrature-math`, shared with
//! the derivation and re-exported here.
//!
//! ## What a pixel goes through
//!
//! Three ways in, named by the methods' suffixes: one pixel (`[f32; N]`), interleaved pixels
//! (`&[[f32; N]]`, `*_batch`) and planes (one `&[f32]` per wavelength, `*_planar`). Every way
//! computes each channel with the same f32 operations in the same order, so all of them give the
//! per-pixel function's bits (linear output) or bytes (encoded output), on every target.
//!
//! **One pixel** (`src/pixel.rs`):
//! - [`WavelengthSet::ac1c2`]: the 3×N product of the weights and the samples, in index order;
//!   [`WavelengthSet::xyz`]: that, then [`xyz_from_ac1c2`]. [`FoldedSet::linear_rgb`]: the same
//!   product with the display's colour matrix folded into the weights, linear RGB in one step.
//! - [`FoldedSet::encode_u8`]: the product, then [`Display::encode_u8`]. With the sRGB curve and
//!   [`GamutMapping::Clip`] that is [`srgb8_from_linear`] on each channel, a table lookup, and
//!   black for a NaN; on x86-64 the product and the table run with the three channels in one
//!   SSE2 register (`src/simd/sse2.rs`). Other curves and mappings: [`Display::map_gamut`] for
//!   [`GamutMapping::PreserveA`], then [`TransferFunction::encode_u8`] per channel (the sRGB
//!   table; thresholds baked for the scene's power laws; otherwise an f32 power and
//!   [`quantize_u8`]).
//! - [`FoldedSet::encode_u16`]: [`FoldedSet::linear_rgb`], [`Display::encode_u16`],
//!   [`Display::map_gamut`], [`TransferFunction::encode_u16`] (the curve in f32) and
//!   [`quantize_u16`].
//! - Encoded f32 in 0..=1, the reference (not a per-pixel function, see "Conventions"):
//!   [`Display::encode`], [`Display::map_gamut`] then [`TransferFunction::encode`], the exact
//!   curve in f64, rounded once.
//!
//! **Interleaved pixels** (`src/batch.rs`): [`WavelengthSet::ac1c2_batch`],
//! [`FoldedSet::linear_rgb_batch`] and [`FoldedSet::encode_u16_batch`] call the per-pixel
//! function on each pixel. [`FoldedSet::encode_u8_batch`] with the sRGB curve and `Clip`, on a
//! target with f32 vector units, runs a vector loop over whole groups and the portable loop over
//! the rest:
//! - x86-64 with AVX-512 (F, BW and VBMI) and N = 4: sixteen pixels per register, the code
//!   values from a polynomial, the few it cannot vouch for encoded again by the per-pixel
//!   function (`src/simd/avx512.rs`);
//! - x86-64 with AVX2 (and AVX-512 at other N): eight pixels per register, the table read by
//!   scalar loads between vector stages (`src/simd/avx2.rs`);
//! - the portable loop, and all of it on other targets with vector units (SSE2 alone, NEON,
//!   WebAssembly SIMD): chunks of 16 pixels transposed into planes on the stack, in loops the
//!   compiler vectorizes (`src/planar/portable.rs`).
//!
//! Other curves and mappings, and targets without vector units (microcontrollers), go pixel by
//! pixel through [`FoldedSet::encode_u8`].
//!
//! **Planes** (`src/planar/`): [`FoldedSet::linear_rgb_planar`] and, with the sRGB curve and
//! `Clip`, [`FoldedSet::encode_u8_planar_to_interleaved`] (and [`FoldedSet::encode_u8_planar`],
//! the same loops on chunks of 64 pixels, its bytes scattered to three planes) run the AVX-512 loop (any N) or the AVX2 loop on
//! x86-64 CPUs that have them, then the portable chunked loop for the pixels left (or for all,
//! elsewhere). Without vector units, `encode_u8_planar_to_interleaved` runs a scalar loop one pixel at a time
//! with the weights in registers (`src/planar/scalar.rs`); other curves and mappings go pixel
//! by pixel through [`FoldedSet::encode_u8`].
//! [`FoldedSet::encode_u16_planar`] and [`FoldedSet::encode_u16_planar_to_interleaved`] go pixel
//! by pixel through [`FoldedSet::encode_u16`].
//!
//! **Several lights** (`src/group.rs`): [`LightGroupSet`] holds one folded weight matrix per
//! light at shared nodes; its per-pixel functions run [`FoldedSet::linear_rgb`]'s product for
//! each light's accumulator (light 0's as [`FoldedSet::encode_u8`] starts it), add them in light
//! order, and encode the sum with [`Display::encode_u8`] or [`Display::encode_u16`] (on x86-64,
//! the sRGB curve with `Clip` in one SSE2 register, as [`FoldedSet::encode_u8`]). Its batch and
//! planar functions run the folded sets' loops above (AVX-512, AVX2, portable) light by light,
//! for the 8-bit forms with the sRGB curve and `Clip` and for [`LightGroupSet::linear_rgb_planar`],
//! with L · N up to [`MAX_WAVELENGTHS`]: each light's product in the per-pixel order, the lights
//! added in order, so the same bits; the others call the per-pixel functions on each pixel (see
//! `docs/light-groups.md`).
//!
//! **RGB materials** (`src/upsample.rs`): [`Upsampling::reflectance`] takes a linear RGB colour
//! to a set's N node reflectances: each channel clamped to [0, 1] (NaN to 0), the cell of the
//! baked grid and one of its six tetrahedra, then four table entries weighted and summed per node
//! ([`Upsampling::interpolate`]); in a cell at the edge of what the set reaches, where the colour's
//! residual exceeds the table's rounding, the [`RoundTrip`] correction (`src/upsample/round_trip.rs`:
//! a small active-set solve), all in f32; [`Upsampling::reflectance_batch`] (pixels to pixels),
//! [`Upsampling::reflectance_planar`] (RGB planes to node planes) and
//! [`Upsampling::reflectance_interleaved_to_planar`] (an RGB texture to the node planes the
//! planar encoders take) call it on each pixel.
//! The tables are in [`tables::upsampling`] for the sets and displays the scene names (see
//! `docs/upsampling.md`).
//!
//! The x86-64 loops are chosen at run time: the CPU's features are detected on the first call
//! (`cpuid`, with the `cpufeatures` crate) and cached, in `src/simd/mod.rs`. None of this uses
//! f64 (the list of per-pixel functions, and where f64 is, is in "Conventions").
//!
//! **Integer counts** (`src/integer/`), for microcontrollers without an FPU:
//! [`IntegerSet::encode_u8`] (`set.rs`) takes u16 counts, sums each channel's fixed-point
//! weights times the counts in 32 bits (the weights' top bits, `fixed_point.rs`; on Armv7E-M two
//! samples an instruction, with the DSP extension's `SMLAD`, `dsp.rs`), settles most codes with
//! one look-up in a table of limits on the transfer curve's thresholds (an entry per 2⁻¹² of
//! linear light, `curve.rs`) and one comparison, and only where a threshold lies within the
//! coarse sum's margin forms the exact sum and compares it.
//! [`IntegerSet::encode_u8_batch`] runs the same steps in one loop over the pixels. No f32 and
//! no f64: the baked [`tables::integer`] sets are the folded sets in fixed point.
//!
//! ## Beyond a pixel
//!
//! For sensor firmware, from any set's XYZ: [`PlanckianLocus::cct`] on
//! `tables::PLANCKIAN_LOCUS` (correlated colour temperature and Duv, f32, the scene's
//! `[extras] cct`), [`LuxScale`] (illuminance), and a device's calibration before the set's
//! matrix, [`Calibration`] in f32 or [`CountCalibration`] in integers (dark offsets and gains,
//! from a dark and a white reading or fitted at build time). See
//! `docs/colour-temperature-and-calibration.md`.
//!
//! ## Conventions
//!
//! The rules every public item follows, so that a name or an argument list says what it does:
//!
//! - **Argument order**: the receiver, then *how* (a [`GamutMapping`], a channel selector such as
//!   [`Rgb`]), then the input, then the output buffer:
//!   `set.encode_u8(mapping, &samples)`, `display.encode_u8(mapping, rgb)`,
//!   `transfer.encode_u8(Rgb::R, x)`, `set.encode_u8_batch(mapping, &pixels, &mut out)`.
//! - **Layouts, by suffix**: none, one pixel (`[f32; N]` in); `_batch`, interleaved pixels in
//!   (`&[[T; N]]`) and out (`&mut [[U; 3]]`); `_planar`, planes in (one slice per wavelength or
//!   channel) and planes out (one slice per output channel); `_planar_to_interleaved`, planes in
//!   and interleaved pixels out; `_interleaved_to_planar`, the reverse. Every layout gives the
//!   per-pixel function's bits or bytes, and a call whose slices differ in length returns
//!   [`Error::LengthMismatch`] before writing anything, naming what it compared ([`LengthOf`]:
//!   the output against the input, a plane against the first) and the two lengths.
//! - **One word per idea**: *samples* are the f32 values a set takes (and [`Samples`] says what
//!   they are); *counts* are the u16 inputs of [`IntegerSet`] and [`CountCalibration`], a count
//!   standing for `sample_unit` of the samples (what [`IntegerSet::new`] and
//!   [`Calibration::to_counts`] take); an error bound is `<WHAT>_MAX_ERROR`, with a unit
//!   suffix where the unit is not the quantity's own ([`INTEGER_MAX_ERROR_CODES`],
//!   [`SRGB8_MAX_ERROR_DE76`], [`CCT_MAX_ERROR_MIRED`]); a channel of AC1C2 is a [`Channel`], of RGB an [`Rgb`], and a
//!   sensor's channel is an index (`channel_index`).
//! - **Names**: an enum's `name()` is its variant's identifier in kebab-case, lower-case words
//!   joined by hyphens (`"clip"`, `"preserve-a"`, `"vanishing-norm"`, `"out-of-range"`): the
//!   same text in every version, for CSV columns, logs and settings. Its `fmt::Display` is the
//!   sentence for messages. The one exception is the channel selectors, named by their symbols
//!   as the paper and colour science write them: [`Channel`] `"A"`, `"C1"`, `"C2"`, [`Rgb`]
//!   `"R"`, `"G"`, `"B"`. A value's `name()` ([`Display::name`]) is the name it was made with
//!   (`"sRGB"`, `"Display P3"` for the baked displays). `src/model/tests.rs` holds every public
//!   enum to this.
//! - **Errors**: every fallible function (one that can refuse its arguments) returns
//!   `Result<_, `[`Error`]`>`; a refused display is [`Error::Display`] with the [`DisplayError`]
//!   the build-time generator reports too. `Option` is for an answer that may not exist for
//!   any argument, never for a refusal: no CCT beyond |Duv| = 0.05 or without a chromaticity
//!   ([`PlanckianLocus::cct`], [`uv_from_xyz`]), no member beyond L
//!   ([`LightGroupSet::member`]), no figure the build did not measure
//!   ([`Upsampling::lipschitz`]). Enums that may grow (errors, problems, [`LengthOf`],
//!   [`Samples`], [`GamutMapping`], [`TransferFunction`], [`RuleStatus`]) are
//!   `#[non_exhaustive]`.
//! - **Construction**: the baked types' fields are private; read them through `const fn`
//!   accessors of the same names (`set.weights()`, `display.name()`), and build your own with a
//!   checked `const fn new` ([`WavelengthSet::new`], [`FoldedSet::new`], [`GaussRule::new`],
//!   [`LightGroupSet::new`], [`Upsampling::new`] and [`Upsampling::with_measured`],
//!   [`IntegerSet::new`], [`PlanckianLocus::new`], [`ChannelLuts::new`], [`Calibration::new`],
//!   [`LuxScale::new`]), [`Display::from_matrices`], or [`Display::new`] (f64, not `const`);
//!   where no value can be wrong the `new` cannot fail ([`CountCalibration::new`],
//!   [`RoundTrip::new`]). The generated [`tables`] make every baked constant with the same
//!   constructors, in constant evaluation: a table one refuses stops the build with the
//!   refusal's [`Error::summary`]. No constructor leaves a placeholder (such as NaN) for the
//!   caller to fill. A constructor takes by value what the new value keeps whole
//!   (`Upsampling::new` its [`FoldedSet`], [`LightGroupSet::from_members`] its members) and by
//!   reference what it only reads (`IntegerSet::new` the folded set whose weights it converts).
//!   A function's result that holds no invariant is a plain record with public fields
//!   ([`Cct`]).
//! - **Inputs**: no function panics or allocates on any input; each documents what NaN, ±Inf,
//!   subnormal, huge and negative values yield.
//! - **No f64 per pixel**: the per-pixel functions use f32 and integers only. They are the
//!   sets' `ac1c2`, `xyz`, `linear_rgb`, `linear_rgb_under`, `encode_u8` and `encode_u16`
//!   ([`WavelengthSet`], [`FoldedSet`], [`LightGroupSet`], [`IntegerSet::encode_u8`]); the
//!   display's [`Display::map_gamut`], [`Display::encode_u8`], [`Display::encode_u16`],
//!   [`Display::linear_from_xyz`] and [`Display::xyz_from_linear`]; the transfer function's
//!   [`TransferFunction::encode_u8`], `encode_u16` and `encode_fast`; [`srgb8_from_linear`],
//!   [`quantize_u8`], [`quantize_u16`], [`xyz_from_ac1c2`], [`ac1c2_from_xyz`];
//!   [`Upsampling::reflectance`] and [`Upsampling::interpolate`]; a sensor reading's
//!   [`Calibration::apply`], [`CountCalibration::apply`], [`LuxScale::lux`],
//!   [`PlanckianLocus::cct`] and [`uv_from_xyz`]; and every `_batch`, `_planar`,
//!   `_planar_to_interleaved` and `_interleaved_to_planar` form of them. f64 is only in the
//!   reference encoders, [`TransferFunction::encode`], [`TransferFunction::decode`] and
//!   [`Display::encode`] (the exact curve rounded once, what the per-pixel encoders are
//!   measured against), and in what runs once per display, table, device or test, off the
//!   pixel path: [`Display::new`], [`PlanckianLocus::new`], [`delta_e2000`], [`delta_e76`],
//!   [`lab_from_xyz`], [`f32_budget`].
//! - **Traits**: every public type is `Debug`, `Clone` and `PartialEq` (`Copy` where it holds no
//!   buffer, `Eq` and `Hash` where it holds no float), and `defmt::Format` with the `defmt`
//!   feature.
//!
//! ## Features
//!
//! All additive, none on by default. [`Error`] implements `core::error::Error` (and so
//! `std::error::Error`) without any of them.
//! - `defmt`: `defmt::Format` for the public types, for logging from firmware.
//! - `micromath`: `TransferFunction::encode_fast`, within `ENCODE_FAST_MAX_ERROR` of the
//!   exact curve (a coarse bound: previews and indicators).
#![no_std]
#![cfg_attr(docsrs, feature(doc_cfg))]
#![deny(missing_docs)]
// Unsafe code is in the x86-64 vector loops (`simd`, and the table lookup they share in
// `encode`) and in the integer path's inline assembly on Armv7E-M and Armv6-M (`integer`, cfgs
// `arm_dsp` and `arm_v6m`, set by the build script): every other module forbids it, and on
// other targets the whole crate does.
#![cfg_attr(
    not(any(target_arch = "x86_64", arm_dsp, arm_v6m)),
    forbid(unsafe_code)
)]
#![deny(unsafe_op_in_unsafe_fn)]
#![deny(clippy::undocumented_unsafe_blocks)]

// The unit tests and the fuzz targets' loop switch (`simd::forced`) use std.
#[cfg(any(test, fuzzing))]
extern crate std;

// The modules by role, each importing only from the roles above it in this list; no module
// imports one that imports it back (`python3 .ci/module-graph src` checks both, in CI):
// 1. encode (the 8-bit encoders' tables, clamping); tables (tables.rs, the generated
//    constants); cct (CCT and Duv); lux;
// 2. model (the value types and their own arithmetic: the channel selectors, the error type,
//    3×3 products, transfer functions, displays, sets), on encode and tables; simd (the x86-64
//    loops), on encode;
// 3. pixel (the per-pixel path, on model and simd), planar (the planar path and the portable
//    loops, on model, simd and encode), integer (the integer path, on model, encode and tables),
//    dynamic (on model), fast (on model and encode); calibration and upsample (RGB → node
//    reflectances), on model's error;
// 4. batch (the interleaved path, on model, simd and planar's portable loops); group
//    (light-group sets: one folded matrix per light, on model, simd and pixel's products).
// simd::target (whether the target has f32 vector units) is a leaf that both simd::forced (the
// test and fuzz builds' loop caps) and planar read, so that neither imports the other. The
// generated constants in `tables` also call the checked constructors of the types they
// instantiate (model's, cct's, upsample's, integer's, encode's): references down this list,
// which the module graph cannot see (it does not read the generated file); tables.rs says how
// they meet the reads of `tables` by model and integer.
mod batch;
mod calibration;
mod cct;
mod dynamic;
mod encode;
mod group;
mod integer;
mod lux;
mod model;
mod pixel;
mod planar;
mod simd;
#[cfg(test)]
mod test_inputs;
mod upsample;

#[cfg(feature = "micromath")]
mod fast;

pub mod tables;

pub use calibration::{Calibration, CountCalibration};
pub use cct::{uv_from_xyz, Cct, PlanckianLocus, CCT_MAX_ERROR_MIRED, DUV_MAX_ERROR, MAX_DUV};
pub use dynamic::DynamicSet;
pub use encode::{srgb8_from_linear, SRGB8_MAX_ERROR, SRGB8_MAX_ERROR_DE76};
#[cfg(feature = "micromath")]
pub use fast::ENCODE_FAST_MAX_ERROR;
pub use group::LightGroupSet;
pub use integer::{IntegerSet, INTEGER_MAX_ERROR_CODES};
pub use lux::LuxScale;
pub use model::channel::{Channel, Rgb};
pub use model::display::{Display, GamutMapping};
pub use model::error::{CalibrationProblem, DisplayError, Error, LengthOf, LightGroupProblem};
pub use model::matrix::{ac1c2_from_xyz, xyz_from_ac1c2};
pub use model::set::{FoldedSet, GaussRule, RuleStatus, Samples, WavelengthSet, MAX_WAVELENGTHS};
pub use model::transfer::{
    quantize_u16, quantize_u8, ChannelLuts, TransferFunction, U16_MAX_ERROR,
};
pub use pixel::f32_budget;
pub use spectral_quadrature_math::{
    delta_e2000, delta_e76, lab_from_xyz, Point, MAX_PRIMARIES_CONDITION, MIN_WHITE_SHARE,
};
pub use upsample::{RoundTrip, Upsampling, UPSAMPLING_CODE_ONE};

/// Internal, for the fuzz targets in `fuzz/` alone: caps the loops the batch and planar paths
/// may take on this thread (`simd::forced`). Compiled only with `--cfg fuzzing`, which
/// cargo-fuzz sets; not part of the API, and absent from every other build.
#[cfg(fuzzing)]
#[doc(hidden)]
pub mod __fuzzing {
    pub use crate::simd::forced::{force, take_ran, Loops, Ran};
}

/// The README's examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;

/// The Rust examples of `docs/`, compiled and run as doctests like the README's.
#[cfg(doctest)]
#[doc = include_str!("../docs/using-the-tables.md")]
struct UsingTheTablesDoctests;

#[cfg(doctest)]
#[doc = include_str!("../docs/shared-sets.md")]
struct SharedSetsDoctests;

#[cfg(doctest)]
#[doc = include_str!("../docs/light-groups.md")]
struct LightGroupsDoctests;

#[cfg(doctest)]
#[doc = include_str!("../docs/performance.md")]
struct PerformanceDoctests;

#[cfg(doctest)]
#[doc = include_str!("../docs/shaders.md")]
struct ShadersDoctests;

#[cfg(doctest)]
#[doc = include_str!("../docs/your-light-and-sensor.md")]
struct YourLightAndSensorDoctests;

#[cfg(doctest)]
#[doc = include_str!("../docs/microcontrollers.md")]
struct MicrocontrollersDoctests;

#[cfg(doctest)]
#[doc = include_str!("../docs/upsampling.md")]
struct UpsamplingDoctests;

#[cfg(doctest)]
#[doc = include_str!("../docs/measured-data.md")]
struct MeasuredDataDoctests;

#[cfg(doctest)]
#[doc = include_str!("../docs/colour-temperature-and-calibration.md")]
struct ColourTemperatureAndCalibrationDoctests;

#[cfg(doctest)]
#[doc = include_str!("../docs/sensor-firmware.md")]
struct SensorFirmwareDoctests;
