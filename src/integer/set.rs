//! [`IntegerSet`]: the type, its constructor (the fixed-point weights, and the largest P that
//! keeps every sum inside i32), its accessors, and its encoding of counts: the coarse sums of a
//! pixel's counts (portably a few samples a step, with `fixed_point`'s multiply-accumulate; on
//! Armv7E-M through `dsp`) and the exact sum, then each channel's code settled on `curve` from
//! its coarse sum, refined by the exact sum where a threshold lies within the margin; per pixel
//! and over a batch.

#![forbid(unsafe_code)]

#[cfg(all(target_arch = "arm", arm_v6m))]
use super::armv6m;
use super::curve::{curve_for, IntegerCurve, INDEX_LEN, INDEX_SHIFT};
#[cfg(arm_dsp)]
use super::dsp;
use super::dsp::Packed;
use super::fixed_point::{mac, split_at};
#[cfg(not(arm_dsp))]
use super::fixed_point::{mac_steps_of_2, mac_steps_of_4};
use crate::model::error::check_length;
use crate::{Display, Error, FoldedSet, LengthOf, Samples};

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
/// ([`counts_as_f32`](Self::counts_as_f32) gives those samples, for the f32 path): the crate's
/// one convention for the scale of counts, which
/// [`Calibration::to_counts`](crate::Calibration::to_counts) takes too. The baked sets
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
/// instruction, to the same values; on Armv6-M (Cortex-M0, M0+) the batch at N = 4 runs these
/// steps in hand-written assembly, the rarer ways in the same code as elsewhere. So every
/// target gives the same bytes. P is the largest
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
    pub(super) packed: Packed<N>,
    /// `Vᵢ >> 16` (below 2¹⁵ in magnitude; i32, which Armv6-M loads with an immediate offset).
    pub(super) coarse: [[i32; N]; 3],
    /// `Vᵢ`, rows R, G, B.
    weights: [[i32; N]; 3],
    wavelengths_nm: [f32; N],
    /// P: `F / 2^P` is linear RGB.
    pub(super) frac_bits: u32,
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
        let Some(curve) = curve_for(folded.display_ref().transfer()) else {
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
            if let Some((weights, coarse)) = split_at(folded.weights_ref(), sample_unit, p) {
                return Ok(IntegerSet {
                    wavelengths_nm: folded.wavelengths_nm(),
                    weights,
                    coarse,
                    packed: Packed::new(&coarse),
                    frac_bits: p as u32,
                    shift: (47 - p) as u32,
                    one: 1 << (p - 16),
                    sample_unit,
                    samples: folded.samples(),
                    display: folded.display(),
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
    /// [`Display::encode_u8`](crate::Display::encode_u8)) at or below the exact fixed-point value
    /// `F / 2^P` ([`linear_fixed`](Self::linear_fixed)): the f32 path's correctly rounded
    /// curve, applied without rounding the sum. So it is within
    /// [`INTEGER_MAX_ERROR_CODES`](crate::INTEGER_MAX_ERROR_CODES) (1) of the f32 path on the
    /// same input, and the same on every target.
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
    /// Errors with [`Error::LengthMismatch`] (and writes nothing) unless the lengths agree:
    /// [`LengthOf::Output`](crate::LengthOf::Output), `expected` the input's pixels, `got` the
    /// output's.
    pub fn encode_u8_batch(&self, counts: &[[u16; N]], out: &mut [[u8; 3]]) -> Result<(), Error> {
        check_length(LengthOf::Output, counts.len(), out.len())?;
        // As in encode_pixel, once for the whole batch.
        match self.frac_bits {
            #[cfg(any(arm_dsp, all(target_arch = "arm", arm_v6m)))]
            45 => self.encode_batch_with::<17>(counts, out),
            #[cfg(any(arm_dsp, all(target_arch = "arm", arm_v6m)))]
            46 => self.encode_batch_with::<18>(counts, out),
            _ => self.encode_batch_with::<0>(counts, out),
        }
        Ok(())
    }

    /// The batch's loop, with `S` as in [`limit`](Self::limit): the set's addresses stay in
    /// registers across pixels.
    #[inline(always)]
    fn encode_batch_with<const S: u32>(&self, counts: &[[u16; N]], out: &mut [[u8; 3]]) {
        // Armv6-M at N = 4: the pixels' common paths in assembly, what they leave as elsewhere.
        #[cfg(all(target_arch = "arm", arm_v6m))]
        if S != 0 {
            let coarse = self.coarse.as_flattened().as_chunks::<4>().0;
            let counts4 = counts.as_flattened().as_chunks::<4>().0;
            if let (Ok(coarse), true) = (<&[[i32; 4]; 3]>::try_from(coarse), N == 4) {
                let mut sums = [0i32; 4];
                let mut from = 0;
                while let (Some(x4), Some(o)) = (counts4.get(from..), out.get_mut(from..)) {
                    let (j, k) = armv6m::run4::<S>(coarse, self.curve, x4, o, &mut sums);
                    let j = from + j;
                    match (counts.get(j), out.get_mut(j)) {
                        (Some(x), Some(o)) if k < 3 => {
                            self.encode_channels_from::<S>(k, sums, x, o);
                        }
                        _ => break,
                    }
                    from = j + 1;
                }
                return;
            }
        }
        let pixels = out.iter_mut().zip(counts);
        // From the last on Armv6-M (N other than 4, or P other than 45 and 46), which left
        // the Cortex-M0 a register more in the loop (N = 8: 272 instructions a pixel to 265).
        #[cfg(all(target_arch = "arm", arm_v6m))]
        let pixels = pixels.rev();
        for (o, x) in pixels {
            // Each code stored as soon as it is known: three values fewer to hold at once.
            let (h, total) = self.coarse_sums(x);
            o[0] = self.encode_channel::<S>(0, h[0], total, x);
            o[1] = self.encode_channel::<S>(1, h[1], total, x);
            o[2] = self.encode_channel::<S>(2, h[2], total, x);
        }
    }
}

impl<const N: usize> IntegerSet<N> {
    /// Channels `k..3` of the pixel `x`, whose coarse sums are `sums` (`h` of the three
    /// channels, then the total), into `out`: what Armv6-M's assembly leaves (out of line).
    #[cfg(all(target_arch = "arm", arm_v6m))]
    #[cold]
    #[inline(never)]
    fn encode_channels_from<const S: u32>(
        &self,
        k: usize,
        sums: [i32; 4],
        x: &[u16; N],
        out: &mut [u8; 3],
    ) {
        // Channel k took none of the ways before `settle` (below 0 neither: see `below_zero`);
        // at or above 1.0 it would have been 255 (so the test, which also tells the compiler
        // that `settle` sees h below 1.0 wherever it is called).
        let (c, h, total) = (k % 3, sums[k % 3], sums[3]);
        out[c] = if h >= self.one {
            255
        } else {
            self.settle(c, h, total, x)
        };
        for c in k + 1..3 {
            out[c] = self.encode_channel::<S>(c, sums[c], total, x);
        }
    }
}

// The arithmetic `encode_u8` and `encode_u8_batch` run per pixel: the coarse sums of the counts
// and the exact sum, then each channel's code settled on the curve.
impl<const N: usize> IntegerSet<N> {
    /// `Σᵢ (Vᵢ >> 16) · xᵢ` per channel, in i32, and `Σᵢ xᵢ`: no overflow for any u16 input,
    /// by the bound [`new`](Self::new) checked (wrapping operations only so that no overflow
    /// check is compiled in). The samples go a few at a time, written out: at opt-level "s"
    /// the compiler keeps loops rolled, and a Cortex-M0, with eight registers for a loop's
    /// sums, pointers and counter, spills them. Four a step suits N = 4 (one step, no loop),
    /// two a step larger N (fewer values live at once).
    #[inline(always)]
    pub(super) fn coarse_sums(&self, x: &[u16; N]) -> ([i32; 3], i32) {
        #[cfg(arm_dsp)]
        {
            let [h0, h1, h2, t] = dsp::pair_sums(&self.packed, x);
            let mut acc = [h0, h1, h2, t];
            if N % 2 == 1 {
                let [w0, w1, w2] = &self.coarse;
                let i = N - 1;
                mac(&mut acc, x[i], w0[i], w1[i], w2[i]);
            }
            ([acc[0], acc[1], acc[2]], acc[3])
        }
        #[cfg(not(arm_dsp))]
        {
            let mut acc = [0i32; 4];
            let done = if N <= 4 {
                mac_steps_of_4(&self.coarse, x, &mut acc)
            } else {
                mac_steps_of_2(&self.coarse, x, &mut acc)
            };
            let [w0, w1, w2] = &self.coarse;
            for (i, &s) in x.iter().enumerate().skip(done) {
                mac(&mut acc, s, w0[i], w1[i], w2[i]);
            }
            ([acc[0], acc[1], acc[2]], acc[3])
        }
    }

    /// `F = Σᵢ Vᵢ · xᵢ` for channel `c`, in i64 (each term below 2⁴⁷).
    #[inline]
    fn exact_sum(&self, c: usize, x: &[u16; N]) -> i64 {
        let w = &self.weights[c % 3];
        let mut sum = 0i64;
        for i in 0..N {
            sum += i64::from(w[i]) * i64::from(x[i]);
        }
        sum
    }

    /// The code value of channel `c` from its coarse sum `h` and `total = Σᵢ xᵢ`.
    #[inline(always)]
    fn encode_channel<const S: u32>(&self, c: usize, h: i32, total: i32, x: &[u16; N]) -> u8 {
        // h clamped to 0..1.0 on the 2³¹ scale: below 0 it has code 0 (the first threshold is
        // above 0), from 1.0 − 2^(16−P) up code 255 (new() checked that the last threshold is
        // not above it, nor in the last stretch). Armv7E-M clamps in the USAT of `limit`.
        #[cfg(arm_dsp)]
        {
            let key = (h.clamp(0, self.one - 1) as u32) << self.shift;
            let limit = self.limit::<S>(h, key);
            self.code_at_limit(c, h, key, limit, total, x)
        }
        // Elsewhere one unsigned comparison finds h inside 0..1.0; of the rest (channels out
        // of the gamut), h at or above 1.0 is 255 at once, since F ≥ 2^P, and h below 0 takes
        // the key 0 in `below_zero`. Inside, the stretch is h's top bits, with no clamp.
        #[cfg(not(arm_dsp))]
        {
            if (h as u32) >= self.one as u32 {
                if h >= 0 {
                    return 255;
                }
                // Below 0: most often top is below the first threshold too, code 0.
                let limit = self.curve.limits[0];
                if top30(h, total, self.shift) < limit {
                    return limit as u8;
                }
                return self.below_zero(c, h, total, x);
            }
            let stretch = if self.frac_bits >= 28 {
                (h as u32) >> (self.frac_bits - 28)
            } else {
                ((h as u32) << self.shift) >> INDEX_SHIFT
            };
            let limit = self.curve.limits[stretch as usize & (INDEX_LEN - 1)];
            if top30(h, total, self.shift) < limit {
                return limit as u8;
            }
            self.code_at_limit(c, h, (h as u32) << self.shift, limit, total, x)
        }
    }

    /// [`encode_channel`](Self::encode_channel) for a coarse sum below 0: the first stretch's
    /// limit, as for the key 0.
    #[cfg(not(arm_dsp))]
    #[cold]
    #[inline(never)]
    fn below_zero(&self, c: usize, h: i32, total: i32, x: &[u16; N]) -> u8 {
        let limit = self.curve.limits[0];
        self.code_at_limit(c, h, 0, limit, total, x)
    }

    /// The code value of channel `c` from its key (h clamped to 0..1.0 on the 2³¹ scale) and
    /// the limit of the key's stretch.
    #[inline(always)]
    fn code_at_limit(
        &self,
        c: usize,
        h: i32,
        key: u32,
        limit: i32,
        total: i32,
        x: &[u16; N],
    ) -> u8 {
        // F / 2^16 = h + Σᵢ (Vᵢ mod 2¹⁶) · xᵢ / 2¹⁶, and the low halves are below 2¹⁶: F / 2^16
        // is at least h and, unless every count is 0 (then F = h = 0), below h + Σᵢ xᵢ, `top`.
        // No overflow: new() bounded |h| + N · 65535 by i32::MAX.
        let top = h.wrapping_add(total);
        // top on the 2³⁰ scale, as i32. For 0 ≤ h < 1.0 it is exact: top is below 1.0 plus
        // the margin, less than 2 · 1.0 (new() made 1.0 exceed the margin). Then below the
        // limit it is below the next threshold after the stretch's start, and so is F: the
        // code is the low byte. For h < 0 the entry is the first (code 0, right for any F
        // below top, which is then below the first threshold or negative), and for h ≥ 1.0
        // the last (code 255, `i32::MAX`): there a wrapped value is wrong only in which path
        // it takes, never in the code.
        if top30(h, total, self.shift) < limit {
            return limit as u8;
        }
        // Most often the stretch holds one threshold, at or below h: then the code is one
        // more, if the threshold after it is above top. (code + 2 ≤ 257 is in range: for code
        // 254 the entry is `u32::MAX`, and h at or above the last threshold is code 255.)
        let code = usize::from(limit as u8);
        let q = &self.curve.q31;
        if key >= q[code + 1] {
            let key_top = (top.max(0) as u32) << self.shift;
            if key_top < q[code + 2] {
                return code as u8 + 1;
            }
        }
        self.settle(c, h, total, x)
    }

    /// The limit of the stretch of `h`, whose key (h clamped to 0..1.0 on the 2³¹ scale) is
    /// `key`. `S` is 0, or `P − 28`: then the shift is a constant in the code.
    #[cfg(arm_dsp)]
    #[inline(always)]
    fn limit<const S: u32>(&self, h: i32, key: u32) -> i32 {
        // (h clamped) >> (P − 28) is key >> 19: see `dsp::limit`.
        if S != 0 {
            return dsp::limit::<S>(&self.curve.limits, h);
        }
        self.curve.limits[(key >> INDEX_SHIFT) as usize & (INDEX_LEN - 1)]
    }

    /// The code value of channel `c` when neither the limit nor the threshold after it
    /// settles it: a threshold lies in the margin, between h and `top`, or the stretch holds
    /// more than one. From the stretch's code, one step per threshold up to h; if the next one
    /// is above `h + total`, that is the code, else the exact sum's.
    #[cold]
    #[inline(never)]
    fn settle(&self, c: usize, h: i32, total: i32, x: &[u16; N]) -> u8 {
        let top = h.wrapping_add(total);
        let key = (h.clamp(0, self.one - 1) as u32) << self.shift;
        let (code, next) = self.curve.count_q31(key);
        // If the next threshold is above top, F is below it too. For h < 1.0, top is below
        // 2 · 1.0 and fits u32 on the 2³¹ scale; for h ≥ 1.0 the code is 255 and `next` is
        // u32::MAX, above any shifted value (its lowest bit is 0).
        let key_top = (top.max(0) as u32) << self.shift;
        if key_top < next {
            return code as u8;
        }
        self.refine(c, h, x, code)
    }

    /// The code value of channel `c` from the exact sum, for the few values whose coarse
    /// estimate has a threshold within its margin. `code` is the coarse code, at most the
    /// exact one (the coarse sum `h` is never above F / 2^16).
    #[inline]
    fn refine(&self, c: usize, h: i32, x: &[u16; N], code: usize) -> u8 {
        // Armv7E-M multiplies 32 × 32 → 64 bits in one instruction: the exact sum directly.
        #[cfg(arm_dsp)]
        let f = {
            let _ = h;
            self.exact_sum(c, x)
        };
        // F = h · 2¹⁶ + Σᵢ (Vᵢ mod 2¹⁶) · xᵢ: products of two u16, summed in u64 (an Armv6-M
        // has no 32 × 32 → 64 multiply, but adds with carry).
        #[cfg(not(arm_dsp))]
        let f = {
            let mut low = 0u64;
            for (&v, &x) in self.weights[c % 3].iter().zip(x) {
                low += u64::from((v as u32 & 0xffff) * u32::from(x));
            }
            (i64::from(h) << 16) + low as i64
        };
        if f <= 0 {
            return 0;
        }
        let p = self.frac_bits;
        if f >= 1i64 << p {
            return 255;
        }
        // 0 < F < 2^P. On the 2³¹ scale, floored, it is `a` (exact for P ≤ 31), and
        // t = ⌈θ · 2³¹⌉: a ≥ t puts F at or above θ, a + 1 < t below it (t − 1 < θ · 2³¹).
        // Only a = t − 1 needs the 2⁶³ scale, where F fits u64 and compares exactly with
        // ⌈θ · 2⁶³⌉.
        let a = if p >= 31 {
            (f >> (p - 31)) as u32
        } else {
            (f << (31 - p)) as u32
        };
        let mut code = code;
        while code < 255 {
            let t = self.curve.q31[code + 1];
            let above = if a >= t {
                true
            } else if a < t - 1 {
                false
            } else {
                ((f as u64) << (63 - p)) >= self.curve.q63(code + 1)
            };
            if !above {
                break;
            }
            code += 1;
        }
        code as u8
    }
}

/// `h + total` on the 2³⁰ scale (`shift` is that of the 2³¹ scale), as i32.
#[inline(always)]
fn top30(h: i32, total: i32, shift: u32) -> i32 {
    (h.wrapping_add(total) as u32).wrapping_shl(shift - 1) as i32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tables::integer::{KQ_C_8_MEYER_1987, KQ_C_8_SRGB};

    /// The exact code by a full search of the 2⁶³-scale thresholds: what `refine` must give.
    fn exact_code<const N: usize>(set: &IntegerSet<N>, c: usize, x: &[u16; N]) -> u8 {
        let f = set.linear_fixed(x)[c];
        if f <= 0 {
            return 0;
        }
        if f >= 1i64 << set.frac_bits {
            return 255;
        }
        let scaled = (f as u64) << (63 - set.frac_bits);
        (1..256).filter(|&k| set.curve.q63(k) <= scaled).count() as u8
    }

    /// Without the refinement the coarse sums would be off by a code on some inputs; with it
    /// every code is the exact one, on both sides of the refinement's test.
    #[test]
    fn the_refinement_runs_where_the_coarse_sum_is_ambiguous() {
        fn run<const N: usize>(set: &IntegerSet<N>) -> (usize, usize) {
            let (mut refined, mut coarse_off) = (0, 0);
            let mut state = 0x9e37_79b9_7f4a_7c15u64;
            for _ in 0..20_000 {
                let x: [u16; N] = core::array::from_fn(|_| {
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    // Dark pixels too, where the thresholds are closest.
                    (state >> 48) as u16 >> (state % 7)
                });
                let (h, total) = set.coarse_sums(&x);
                let got = set.encode_u8(&x);
                for c in 0..3 {
                    assert_eq!(got[c], exact_code(set, c, &x), "{x:?} channel {c}");
                    if h[c] > 0 && h[c] < set.one {
                        let key = (h[c] as u32) << set.shift;
                        let key_top = ((h[c] + total) as u32) << set.shift;
                        let (code, next) = set.curve.count_q31(key);
                        assert_eq!(code, (1..256).filter(|&k| set.curve.q31[k] <= key).count());
                        assert_eq!(next, set.curve.q31[code + 1]);
                        if code < 255 && key_top >= next {
                            refined += 1;
                            assert_eq!(got[c], set.refine(c, h[c], &x, code));
                        }
                        coarse_off += usize::from(code as u8 != got[c]);
                    }
                }
            }
            (refined, coarse_off)
        }
        for (refined, coarse_off) in [run(&KQ_C_8_SRGB), run(&KQ_C_8_MEYER_1987)] {
            assert!(refined > 0 && coarse_off > 0, "{refined} {coarse_off}");
            assert!(coarse_off <= refined);
        }
    }

    /// Every fractional precision P from the largest down, with coarse sums below 0, inside
    /// 0..1.0 and at or above 1.0 (the channels out of the gamut take their own branches,
    /// and a set's stretch is found from h's top bits at P ≥ 28, from its key below): every
    /// code is the exact one, on random counts of every magnitude and on the extremes.
    #[test]
    fn every_precision_gives_the_exact_code_inside_and_outside_the_gamut() {
        fn run<const N: usize>(folded: &FoldedSet<N>, seed: u64) -> [usize; 3] {
            // [h < 0, 0 ≤ h < 1.0, h ≥ 1.0] over all sets and inputs, channel by channel.
            let mut seen = [0usize; 3];
            let mut state = seed;
            let mut next = || {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                state
            };
            // Larger sample units lower P, by one bit per doubling.
            for k in 0..=24 {
                let unit = (1u64 << k) as f32 / 65535.0;
                let Ok(set) = IntegerSet::new(folded, unit) else {
                    continue;
                };
                let extremes = [[0u16; N], [65535; N], [1; N]];
                let random = (0..400).map(|_| {
                    core::array::from_fn(|_| {
                        let r = next();
                        (r >> 48) as u16 >> (r % 16)
                    })
                });
                for x in extremes.into_iter().chain(random) {
                    let (h, _) = set.coarse_sums(&x);
                    let got = set.encode_u8(&x);
                    for c in 0..3 {
                        assert_eq!(
                            got[c],
                            exact_code(&set, c, &x),
                            "P {} {x:?} {c}",
                            set.frac_bits
                        );
                        let i = if h[c] < 0 {
                            0
                        } else if h[c] < set.one {
                            1
                        } else {
                            2
                        };
                        seen[i] += 1;
                    }
                }
            }
            seen
        }
        let seen = run(
            &crate::tables::folded::TABLE2_ROW2_SRGB,
            0x1234_5678_9abc_def1,
        );
        assert!(seen.iter().all(|&n| n > 100), "{seen:?}");
        let seen = run(&crate::tables::folded::KQ_C_8_SRGB, 0x0fed_cba9_8765_4321);
        assert!(seen.iter().all(|&n| n > 100), "{seen:?}");
    }

    /// Which way each channel of the sensor firmware's N = 4 sweep takes (its generator, over
    /// 4096 pixels), every code the exact one; `--nocapture` prints the shares that
    /// docs/sensor-firmware.md quotes ("Why not under 100 at N = 4").
    #[cfg(not(arm_dsp))]
    #[test]
    fn the_ways_the_firmware_sweep_takes() {
        let set = crate::tables::integer::TABLE2_ROW2_SRGB;
        let mut state = 0x2545_f491_4f6c_dd1du64;
        // Above 1.0, below 0, at the limit, the threshold after the next, settle.
        let mut ways = [0usize; 5];
        for _ in 0..4096 {
            let x: [u16; 4] = core::array::from_fn(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                ((state >> 48) as u16) >> (state % 8)
            });
            let (h, total) = set.coarse_sums(&x);
            let got = set.encode_u8(&x);
            for (c, &h) in h.iter().enumerate() {
                assert_eq!(got[c], exact_code(&set, c, &x), "{x:?} channel {c}");
                let way = if (h as u32) >= set.one as u32 {
                    usize::from(h < 0)
                } else {
                    let limit = set.curve.limits[((h as u32) >> (set.frac_bits - 28)) as usize];
                    let code = usize::from(limit as u8);
                    let key_top = ((h + total).max(0) as u32) << set.shift;
                    if top30(h, total, set.shift) < limit {
                        2
                    } else if (h as u32) << set.shift >= set.curve.q31[code + 1]
                        && key_top < set.curve.q31[code + 2]
                    {
                        3
                    } else {
                        4
                    }
                };
                ways[way] += 1;
            }
        }
        let all = 3.0 * 4096.0 / 100.0;
        let share = ways.map(|n| n as f64 / all);
        std::println!(
            "N = 4 sweep, % of channels: above 1.0 {:.1}, below 0 {:.1}, at the limit {:.1}, \
             the threshold after the next {:.1}, settle {:.1}",
            share[0],
            share[1],
            share[2],
            share[3],
            share[4]
        );
        // Every way taken, the limit the commonest.
        assert!(ways.iter().all(|&n| n > 0) && ways[2] > ways.iter().sum::<usize>() / 2);
    }
}
