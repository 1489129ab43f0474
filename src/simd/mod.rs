//! Explicit x86-64 vector code for the sRGB 8-bit and linear f32 paths.
//!
//! - [`sse2`]: the per-pixel [`FoldedSet::encode_u8`](crate::FoldedSet::encode_u8) for the
//!   sRGB curve with [`Clip`](crate::GamutMapping::Clip), the three channels in the lanes of
//!   one SSE2 register. SSE2 is part of x86-64, so this needs no detection.
//! - [`avx512`]: the planar loops (sRGB 8-bit and linear f32) and the interleaved sRGB 8-bit
//!   loop at N = 4, sixteen pixels per register, chosen at run time when the CPU has
//!   `avx512f`, `avx512bw` and `avx512vbmi` ([`avx512::available`]). The code values are
//!   computed by a polynomial, exact because the values it flags near a rounding boundary are
//!   encoded again by the per-pixel function (the module has the argument); the planar loops
//!   ask for their samples into the first- and second-level caches ahead of use.
//! - [`avx2`]: the batch and planar loops, eight pixels per AVX2 register, chosen at run time
//!   when the CPU has AVX2 but not the AVX-512 loops ([`avx2::available`]). The sRGB 8-bit
//!   loops pass each group of eight pixels through three stages (vector product and clamp,
//!   scalar table loads, vector code values and interleave), a group apart, so that the table
//!   loads overlap the vector work; the planar loops ask for their samples a few cache lines
//!   ahead, and above four planes go through blocks of pixels four planes at a time, with
//!   partial sums on the stack.
//!
//! Features are detected once, with the `cpufeatures` crate, which works without `std`.
//! Otherwise the portable loops of `planar` run.
//!
//! Every path computes each channel with the same f32 operations in the same order as
//! [`pixel::mat_vec_for_encoding`](crate::pixel::mat_vec_for_encoding) (or
//! [`pixel::mat_vec`](crate::pixel::mat_vec) for linear output) and encodes with the same table
//! (`encode::SEGMENT_TABLE`) or, in the AVX-512 loops, with a polynomial that agrees with it
//! wherever it does not hand the value back to the table, so all of them give the per-pixel
//! function's bytes, bit for bit. FMA is not used in the products, although every AVX2 CPU of
//! the x86-64 world has it: a fused multiply-add rounds once where the per-pixel function (and
//! every target without FMA, the Cortex-M4F among them) rounds twice, so the outputs would
//! differ in the last bit, and now and then in an encoded code value. (The AVX-512 encoder's
//! polynomial uses FMA: its result is checked, not trusted.)

pub(crate) use lights::Lights;
pub(crate) use target::VECTOR_UNITS;

#[cfg(target_arch = "x86_64")]
pub(crate) mod avx2;
#[cfg(target_arch = "x86_64")]
pub(crate) mod avx512;
#[cfg(any(test, fuzzing))]
pub(crate) mod forced;
mod lights;
#[cfg(target_arch = "x86_64")]
mod loops;
#[cfg(target_arch = "x86_64")]
pub(crate) mod sse2;
mod target;
#[cfg(test)]
mod tests;

/// Whether the loops of a level of [`forced::Loops`] (`Scalar`, `Portable`, `Avx2`, `Avx512`)
/// may run: always, except in test and fuzz builds, where [`forced`] caps them per thread.
macro_rules! allowed {
    ($level:ident) => {{
        #[cfg(any(test, fuzzing))]
        let allowed = $crate::simd::forced::allows($crate::simd::forced::Loops::$level);
        #[cfg(not(any(test, fuzzing)))]
        let allowed = true;
        allowed
    }};
}
pub(crate) use allowed;

/// In test and fuzz builds, records which level of loops a fast path ran and whether it
/// streamed ([`forced::take_ran`]); nothing otherwise.
macro_rules! note {
    ($level:ident, $streamed:expr) => {
        #[cfg(any(test, fuzzing))]
        $crate::simd::forced::note($crate::simd::forced::Loops::$level, $streamed);
    };
}
pub(crate) use note;

/// The accelerated planar sRGB 8-bit loop, where the CPU has one: encodes the first pixels
/// of `planes` into `out` (3 bytes per pixel), all but fewer than one of its groups (8 or 16
/// pixels), and returns how many; 0 where there is no accelerated loop, so the caller's
/// portable loop does everything.
///
/// The planes and weights are light by light: a folded set is one light
/// (`core::array::from_ref(&weights)`, `[planes]`), a light-group set L. Each pixel's channels
/// are the lights' products added in light order, each light's from its first product (see
/// [`LightGroupSet::encode_u8`](crate::LightGroupSet::encode_u8)).
#[inline]
pub(crate) fn encode_srgb8_planar<const N: usize, const L: usize>(
    weights: &[[[f32; N]; 3]; L],
    planes: [[&[f32]; N]; L],
    out: &mut [u8],
) -> usize {
    #[cfg(target_arch = "x86_64")]
    {
        if allowed!(Avx512) && avx512::available() {
            note!(Avx512, false);
            // SAFETY: the CPU has the AVX-512 subsets the loop needs (checked just above).
            return unsafe { avx512::encode_srgb8_planar(weights, planes, out) };
        }
        if allowed!(Avx2) && avx2::available() {
            note!(Avx2, false);
            // SAFETY: the CPU has AVX2 (checked just above).
            return unsafe { avx2::encode_srgb8_planar(weights, planes, out) };
        }
    }
    note!(Portable, false);
    let _ = (weights, planes, out);
    0
}

/// As [`encode_srgb8_planar`], for linear f32 output (three planes); the accelerated loop
/// writes all but fewer than 16 pixels. Each light's product is summed from 0.0 and the
/// lights added in order (`pixel::mat_vec`, then
/// [`LightGroupSet::linear_rgb`](crate::LightGroupSet::linear_rgb)'s sum).
#[inline]
pub(crate) fn linear_planar<const N: usize, const L: usize>(
    weights: &[[[f32; N]; 3]; L],
    planes: [[&[f32]; N]; L],
    out: [&mut [f32]; 3],
) -> usize {
    #[cfg(target_arch = "x86_64")]
    {
        let stream = out.iter().map(|o| o.len()).min().unwrap_or(0) >= STREAM_MIN_PIXELS;
        if allowed!(Avx512) && avx512::available() {
            note!(Avx512, stream);
            // SAFETY: the CPU has the AVX-512 subsets the loop needs (checked just above).
            return unsafe { avx512::linear_planar(weights, planes, out, stream) };
        }
        if allowed!(Avx2) && avx2::available() {
            note!(Avx2, stream && avx2::streams::<N, L>());
            // SAFETY: the CPU has AVX2 (checked just above).
            return unsafe { avx2::linear_planar(weights, planes, out, stream) };
        }
    }
    note!(Portable, false);
    let _ = (weights, planes, out);
    0
}

/// From this many pixels on, the accelerated planar linear loops write their output with
/// non-temporal stores: the AVX-512 loop at every width (see [`avx512::linear_planar`]), the
/// AVX2 loop of a folded set above four planes (see [`avx2::linear_planar`]). 2²⁰ pixels are
/// 12 MiB of output, more than a core's share of the last-level cache on common x86-64 CPUs, so
/// the output would leave the caches before it is read again anyway. Smaller calls (a row, a
/// tile) write through the caches, where the caller reads them next.
#[cfg(target_arch = "x86_64")]
pub(crate) const STREAM_MIN_PIXELS: usize = 1 << 20;

/// As [`encode_srgb8_planar`], for interleaved samples (one `P` per pixel: a folded set's
/// `[f32; N]`, one light, or a light-group set's `[[f32; N]; L]`).
#[inline]
pub(crate) fn encode_srgb8_batch<const N: usize, const L: usize, P: Lights<N, L>>(
    weights: &[[[f32; N]; 3]; L],
    samples: &[P],
    out: &mut [u8],
) -> usize {
    #[cfg(target_arch = "x86_64")]
    {
        // The AVX-512 interleaved loop takes a folded set (one light) at its widths.
        if let (1, Some(w)) = (L, weights.first()) {
            if allowed!(Avx512) && avx512::available() && avx512::BATCH_WIDTHS.contains(&N) {
                note!(Avx512, false);
                // SAFETY: the CPU has the AVX-512 subsets the loop needs (checked just above).
                // With one light, the flattened samples are N per pixel.
                return unsafe { avx512::encode_srgb8_batch(w, P::flatten(samples), out) };
            }
        }
        if allowed!(Avx2) && avx2::available() {
            note!(Avx2, false);
            // SAFETY: the CPU has AVX2 (checked just above).
            return unsafe { avx2::encode_srgb8_batch(weights, samples, out) };
        }
    }
    note!(Portable, false);
    let _ = (weights, samples, out);
    0
}
