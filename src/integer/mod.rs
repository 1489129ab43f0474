//! The integer path: integer samples (16-bit counts, as a sensor or an ADC gives them) → 8-bit
//! display RGB with integer arithmetic only, for microcontrollers without an FPU (Cortex-M0+),
//! where every f32 operation is a library call. [`IntegerSet`] says how and why.

// Unsafe code only in `dsp`: inline assembly of the DSP extension, on Armv7E-M. The other
// submodules forbid it.
#![deny(unsafe_code)]

mod curve;
mod dsp;
mod fixed_point;

use crate::{Display, Error, FoldedSet, Samples};
use curve::{curve_for, IntegerCurve, INDEX_LEN};
use dsp::Packed;
use fixed_point::split_at;

/// The largest difference, in 8-bit code values per channel, between
/// [`IntegerSet::encode_u8`] and the f32 path on the same input
/// (`folded.encode_u8(GamutMapping::Clip, &set.counts_as_f32(&x))`, with `folded` the set the
/// integer set was made from): 1.
///
/// Both compare a value against the same thresholds θₖ of the transfer curve; the integer path's
/// value is within `δ = Σᵢ |Vᵢ / 2^P − wᵢ·q| · 65535` of the exact `Σᵢ wᵢ·q·xᵢ` (the fixed-point
/// rounding, at most `N · 65535 / 2^(P+1)`), the f32 path's within
/// [`f32_budget`](crate::f32_budget)`(N, Σᵢ |wᵢ·sᵢ|)` (its products and sums; the sample
/// `xᵢ·q` rounds once more, which the budget's weight term covers since the f32 weights are
/// exact here). The codes can differ by 2 only if two thresholds lie between the two values, so
/// the bound holds wherever the thresholds are further apart than the two errors together.
/// `tests/integer.rs` proves that for every channel of every baked set and every u16 input (for
/// each pair of neighbouring thresholds, with `Σ|wᵢ·sᵢ|` bounded by the largest value any input
/// can give next to them), then checks it on random inputs and dense sweeps.
pub const INTEGER_MAX_ERROR_CODES: u8 = 1;

/// The largest number of fractional bits [`IntegerSet::new`] gives a set: the coarse scale
/// `P − 16` stays below 31, so that 1.0 on it is an i32.
const MAX_FRAC_BITS: i32 = 46;

/// A [`FoldedSet`] in fixed point, for integer samples: 16-bit counts in, 8-bit display RGB out,
/// integer arithmetic only (no f32, no f64, no division).
///
/// A count `x` stands for the f32 sample `x · sample_unit` of the folded set it was made from
/// ([`counts_as_f32`](Self::counts_as_f32) gives those samples, for the f32 path). The baked sets
/// ([`tables::integer`](crate::tables::integer)) take 65 535 as the samples of white: a
/// reflectance of 1 (for a set with a light folded in), a radiance of 1 (a spectrum of
/// constant 1, the display white's luminance), or, for a sensor, the largest of its channels'
/// readings of that white, so a white reading fills the 16 bits.
///
/// ```
/// use spectral_quadrature::tables::{folded, integer};
/// use spectral_quadrature::GamutMapping;
///
/// let set = integer::KQ_C_8_SRGB; // KQ_C_8 folded for sRGB, in fixed point
/// let counts: [u16; 8] = [9000, 21000, 33000, 30000, 26000, 17000, 12000, 10000];
/// let rgb = set.encode_u8(&counts);
/// // The f32 path on the same input gives the same bytes, or one code apart.
/// let f32_rgb = folded::KQ_C_8_SRGB.encode_u8(GamutMapping::Clip, &set.counts_as_f32(&counts));
/// assert!(rgb.iter().zip(f32_rgb).all(|(a, b)| a.abs_diff(b) <= 1));
/// ```
///
/// Gamut mapping is [`Clip`](crate::GamutMapping::Clip) (each channel clamped to 0..=1), the
/// transfer function the set's display's: sRGB, linear, or a power law of a baked display.
///
/// # Fixed point, proven free of overflow
///
/// [`new`](Self::new) converts each f32 weight times the sample unit exactly (an f32 times an
/// f32 is a 48-bit integer times a power of two) and rounds it once to P fractional bits:
/// `Vᵢ = round(wᵢ · sample_unit · 2^P)`. A channel is then `F = Σᵢ Vᵢ · xᵢ`, an exact integer,
/// and its code value is the number of the f32 encoder's own thresholds at or below `F / 2^P`:
/// the curve of the f32 path ([`FoldedSet::encode_u8`] with `Clip`), correctly rounded,
/// applied to the exact fixed-point value.
///
/// A 32-bit target without a 64-bit multiply (Armv6-M) cannot form F cheaply. It sums
/// `Vᵢ >> 16` (the weights' top bits, floor) in 32 bits first. That coarse sum `h` is never
/// above `F / 2^16` and less than `Σᵢ xᵢ` below it, since the dropped low halves are below
/// 2¹⁶ and the counts are not negative. When no threshold lies between `h` and `h + Σᵢ xᵢ`
/// (on that scale), the coarse code is the code of F; only otherwise does the channel form F
/// (a 64-bit sum) and compare it. Most channels take one look-up and one comparison: a table
/// with an entry per 2⁻¹² of linear light holds the code at its start and the next threshold
/// after it, and `h + Σᵢ xᵢ` below that threshold settles the code. On Armv7E-M (Cortex-M4,
/// M4F, M7) the sums take the DSP extension's dual 16-bit multiply-accumulate, two samples an
/// instruction, to the same values. So every target gives the same bytes. P is the largest
/// (at most 46) for which each channel satisfies `Σᵢ |Vᵢ >> 16| · 65535 + N · 65535 ≤
/// i32::MAX`: then no coarse sum, nor the sum plus `Σᵢ xᵢ`, overflows for any u16 input. `new`
/// checks it, at compile time for the baked sets.
// `repr(C)` with the packed weights first: on Armv7E-M their address is the set's.
#[derive(Debug, Clone, Copy)]
#[repr(C)]
pub struct IntegerSet<const N: usize> {
    /// `Vᵢ >> 16` in pairs, for Armv7E-M's dual multiply-accumulate (elsewhere only tests read
    /// it; it is part of the set so that a set means the same on every target).
    #[cfg_attr(not(arm_dsp), allow(dead_code))]
    packed: Packed<N>,
    /// `Vᵢ >> 16` (below 2¹⁵ in magnitude; i32, which Armv6-M loads with an immediate offset).
    coarse: [[i32; N]; 3],
    /// `Vᵢ`, rows R, G, B.
    weights: [[i32; N]; 3],
    wavelengths_nm: [f32; N],
    /// P: `F / 2^P` is linear RGB.
    frac_bits: u32,
    /// `31 − (P − 16)`: a coarse sum shifted left by it is on the thresholds' 2³¹ scale.
    shift: u32,
    /// 1.0 on the coarse scale, `2^(P − 16)`.
    one: i32,
    sample_unit: f32,
    samples: Samples,
    display: Display,
    curve: &'static IntegerCurve,
}

impl<const N: usize> PartialEq for IntegerSet<N> {
    fn eq(&self, other: &Self) -> bool {
        // The curve follows from the display; the other derived fields from the weights.
        self.wavelengths_nm == other.wavelengths_nm
            && self.weights == other.weights
            && self.frac_bits == other.frac_bits
            && self.sample_unit.to_bits() == other.sample_unit.to_bits()
            && self.samples == other.samples
            && self.display == other.display
    }
}

/// By hand, not derived: the set's fixed-point curve and packed weights follow from what it
/// shows (the weights, the display) and would fill a log with tables.
#[cfg(feature = "defmt")]
impl<const N: usize> defmt::Format for IntegerSet<N> {
    fn format(&self, f: defmt::Formatter<'_>) {
        let w = self.weights();
        defmt::write!(
            f,
            "IntegerSet {{ samples: {}, display: {=str}, sample_unit: {=f32}, frac_bits: {=u32}, weights: [{=[?]}, {=[?]}, {=[?]}] }}",
            self.samples(),
            self.display().name(),
            self.sample_unit(),
            self.frac_bits(),
            &w[0][..],
            &w[1][..],
            &w[2][..]
        )
    }
}

impl<const N: usize> IntegerSet<N> {
    /// The folded set `folded` in fixed point, for counts that stand for samples of
    /// `sample_unit` each. Each weight `wᵢ · sample_unit` becomes `Vᵢ = round(wᵢ · sample_unit ·
    /// 2^P)`, computed exactly from the two f32 values (ties away from zero), with the largest
    /// P ≤ 46 for which every channel's sum over u16 counts is proven to stay inside i32 (see
    /// the [type's docs](Self)). A `const fn`: the baked sets are checked by the compiler.
    ///
    /// Errors, never a panic: [`Error::IntegerRange`] when a weight is not finite, `sample_unit`
    /// is not finite and positive, or the weights are too large for any P above 16 (a sum of
    /// u16 counts whose coarse form would not fit 32 bits); [`Error::IntegerTransfer`] when the
    /// display's transfer function has no integer encoder (a lookup table, or a γ that no baked
    /// display has).
    ///
    /// It computes in integers only, so it may run on the microcontroller, for a set folded
    /// at run time ([`WavelengthSet::fold`](crate::WavelengthSet::fold)).
    pub const fn new(folded: &FoldedSet<N>, sample_unit: f32) -> Result<IntegerSet<N>, Error> {
        let Some(curve) = curve_for(folded.display.transfer) else {
            return Err(Error::IntegerTransfer);
        };
        // The encoder settles a coarse sum at or above 1.0 by the last stretch's limit: that
        // stretch must hold no threshold (none does for the baked curves, sRGB, linear and
        // the displays' power laws: their last threshold is below 1 − 2⁻¹²).
        if curve.limits[INDEX_LEN - 1] != i32::MAX {
            return Err(Error::IntegerTransfer);
        }
        if !(sample_unit.is_finite() && sample_unit > 0.0) {
            return Err(Error::IntegerRange);
        }
        let margin = N as i64 * 65535;
        let mut p = MAX_FRAC_BITS;
        // The largest P that fits; the coarse scale must also exceed the margin, so that the
        // coarse sum plus the margin stays below 2 · 1.0 and, shifted, inside u32.
        while p > 16 && (1i64 << (p - 16)) > margin {
            // The encoder clamps the coarse sum below 1.0, to 1 − 2^(16−P): the last
            // threshold must not lie above that (it does not for any γ above 0.01).
            let last_below_clamp = curve.q31[255] <= (((1u32 << (p - 16)) - 1) << (47 - p));
            if !last_below_clamp {
                return Err(Error::IntegerTransfer);
            }
            if let Some((weights, coarse)) = split_at(&folded.weights, sample_unit, p) {
                return Ok(IntegerSet {
                    wavelengths_nm: folded.wavelengths_nm,
                    weights,
                    coarse,
                    packed: Packed::new(&coarse),
                    frac_bits: p as u32,
                    shift: (47 - p) as u32,
                    one: 1 << (p - 16),
                    sample_unit,
                    samples: folded.samples,
                    display: folded.display,
                    curve,
                });
            }
            p -= 1;
        }
        Err(Error::IntegerRange)
    }

    /// The wavelengths of the set it was made from (for a sensor, each channel's peak).
    pub const fn wavelengths_nm(&self) -> [f32; N] {
        self.wavelengths_nm
    }

    /// What a count's samples are: radiances, reflectances under a light, a sensor's readings.
    pub const fn samples(&self) -> Samples {
        self.samples
    }

    /// The display whose matrix is in the weights and whose transfer function encodes.
    pub const fn display(&self) -> Display {
        self.display
    }

    /// The f32 sample one count stands for.
    pub const fn sample_unit(&self) -> f32 {
        self.sample_unit
    }

    /// P, the number of fractional bits of the weights: [`linear_fixed`](Self::linear_fixed)
    /// divided by 2^P is linear RGB.
    pub const fn frac_bits(&self) -> u32 {
        self.frac_bits
    }

    /// The fixed-point weights `Vᵢ = round(wᵢ · sample_unit · 2^P)`, rows R, G, B (each
    /// `|Vᵢ| < 2³¹`).
    pub const fn weights(&self) -> [[i32; N]; 3] {
        self.weights
    }

    /// The samples the f32 path takes for the same counts: `x as f32 · sample_unit` (f32; for
    /// comparisons with [`FoldedSet::encode_u8`], and for the f32 functions that take samples,
    /// such as XYZ from the unfolded set).
    pub fn counts_as_f32(&self, counts: &[u16; N]) -> [f32; N] {
        counts.map(|x| f32::from(x) * self.sample_unit)
    }

    /// Linear RGB in fixed point: `F = Σᵢ Vᵢ · xᵢ` per channel, exactly (i64); divided by
    /// 2^[`frac_bits`](Self::frac_bits) it is linear RGB (1.0 the display's white). Every u16
    /// input is in range: `|F| < 2³¹ · 65535 · N`.
    pub fn linear_fixed(&self, counts: &[u16; N]) -> [i64; 3] {
        [0, 1, 2].map(|c| self.exact_sum(c, counts))
    }

    /// Counts → 8-bit display RGB, gamut mapped by clipping, with integer arithmetic only. Every
    /// u16 input is valid; never panics.
    ///
    /// Each channel's code value is the number of the transfer curve's f32 thresholds (those of
    /// [`Display::encode_u8`]) at or below the exact fixed-point value
    /// `F / 2^P` ([`linear_fixed`](Self::linear_fixed)): the f32 path's correctly rounded
    /// curve, applied without rounding the sum. So it is within
    /// [`INTEGER_MAX_ERROR_CODES`] (1) of the f32 path on the same input, and the same on
    /// every target.
    #[inline]
    pub fn encode_u8(&self, counts: &[u16; N]) -> [u8; 3] {
        self.encode_pixel(counts)
    }

    /// [`encode_u8`](Self::encode_u8), always inlined: the batch's loop keeps the set's
    /// addresses in registers across pixels.
    #[inline(always)]
    fn encode_pixel(&self, counts: &[u16; N]) -> [u8; 3] {
        // Armv7E-M finds a stretch's limit in two instructions when the shift is a constant:
        // one copy of the code per P of the baked sets (the compiler keeps only the one a
        // constant set needs).
        match self.frac_bits {
            #[cfg(arm_dsp)]
            45 => self.encode_pixel_with::<17>(counts),
            #[cfg(arm_dsp)]
            46 => self.encode_pixel_with::<18>(counts),
            _ => self.encode_pixel_with::<0>(counts),
        }
    }

    /// [`encode_pixel`](Self::encode_pixel) with `S` as in [`limit`](Self::limit).
    #[inline(always)]
    fn encode_pixel_with<const S: u32>(&self, counts: &[u16; N]) -> [u8; 3] {
        let (h, total) = self.coarse_sums(counts);
        [
            self.encode_channel::<S>(0, h[0], total, counts),
            self.encode_channel::<S>(1, h[1], total, counts),
            self.encode_channel::<S>(2, h[2], total, counts),
        ]
    }

    /// [`encode_u8`](Self::encode_u8) for every pixel: `out[p] = encode_u8(&counts[p])`.
    ///
    /// Errors with [`Error::LengthMismatch`] (and writes nothing) unless the lengths agree.
    pub fn encode_u8_batch(&self, counts: &[[u16; N]], out: &mut [[u8; 3]]) -> Result<(), Error> {
        if counts.len() != out.len() {
            return Err(Error::LengthMismatch {
                inputs: counts.len(),
                outputs: out.len(),
            });
        }
        // As in encode_pixel, once for the whole batch.
        match self.frac_bits {
            #[cfg(arm_dsp)]
            45 => self.encode_batch_with::<17>(counts, out),
            #[cfg(arm_dsp)]
            46 => self.encode_batch_with::<18>(counts, out),
            _ => self.encode_batch_with::<0>(counts, out),
        }
        Ok(())
    }

    /// The batch's loop, with `S` as in [`limit`](Self::limit): the set's addresses stay in
    /// registers across pixels.
    #[inline(always)]
    fn encode_batch_with<const S: u32>(&self, counts: &[[u16; N]], out: &mut [[u8; 3]]) {
        for (o, x) in out.iter_mut().zip(counts) {
            // Each code stored as soon as it is known: three values fewer to hold at once.
            let (h, total) = self.coarse_sums(x);
            o[0] = self.encode_channel::<S>(0, h[0], total, x);
            o[1] = self.encode_channel::<S>(1, h[1], total, x);
            o[2] = self.encode_channel::<S>(2, h[2], total, x);
        }
    }
}
