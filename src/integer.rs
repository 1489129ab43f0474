//! The integer path: integer samples (16-bit counts, as a sensor or an ADC gives them) → 8-bit
//! display RGB with integer arithmetic only, for microcontrollers without an FPU (Cortex-M0+),
//! where every f32 operation is a library call. [`IntegerSet`] says how and why.

// Unsafe code only in `dsp`: inline assembly of the DSP extension, on Armv7E-M.
#![deny(unsafe_code)]

use crate::{Display, Error, FoldedSet, Samples, TransferFunction};

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

/// An integer encoder of one transfer function: its f32 thresholds (those of the f32 8-bit
/// encoder), the same thresholds on a 2³¹ scale rounded up, and a table of limits that settles
/// most values with one look-up and one comparison.
// `repr(C)`, the limits first: their address is the curve's.
#[derive(Debug)]
#[repr(C)]
pub(crate) struct IntegerCurve {
    /// Entry j, for the j-th stretch of 2⁻¹² in linear light (from `S = j · 2¹⁹` on the 2³¹
    /// scale): in the low byte the code at S (the number of thresholds at or below S), above
    /// it the next threshold after S on the 2³⁰ scale, rounded down far enough that the low
    /// byte cannot lift it. A value v on the 2³⁰ scale at or above S with `v < limit` (as i32)
    /// is below that threshold, so its code is the low byte. Without a next threshold the
    /// entry is `i32::MAX` (code 255), as [`IntegerSet::new`] requires of the last stretch.
    limits: [i32; INDEX_LEN],
    /// `⌈θₖ · 2³¹⌉` for k = 1..=255 (θₖ ≤ 1); entry 0 is 0, entry 256 is `u32::MAX`, above
    /// every key, so that a search needs no bounds test.
    q31: [u32; 257],
    /// The bits of θₖ as f32, the f32 encoder's own thresholds; entry 0 is 0.
    f32_bits: &'static [u32; 256],
}

/// Entries of [`IntegerCurve::limits`]: one per 2¹⁹ on the 2³¹ scale.
const INDEX_LEN: usize = 1 << 12;
/// The shift from a key on the 2³¹ scale to its entry in the limits.
const INDEX_SHIFT: u32 = 31 - 12;

impl IntegerCurve {
    const fn from_f32_thresholds(f32_bits: &'static [u32; 256]) -> IntegerCurve {
        let mut q31 = [0u32; 257];
        let mut k = 1;
        while k < 256 {
            q31[k] = scaled_ceil(f32_bits[k], 31) as u32;
            k += 1;
        }
        q31[256] = u32::MAX;
        let mut limits = [0i32; INDEX_LEN];
        let mut code = 0;
        let mut j = 0;
        while j < INDEX_LEN {
            let start = (j as u32) << INDEX_SHIFT;
            while code < 255 && q31[code + 1] <= start {
                code += 1;
            }
            limits[j] = if code == 255 {
                i32::MAX
            } else {
                // ⌊next / 2⌋ on the 2³⁰ scale, less one step of 2⁸ before the code goes in:
                // the entry stays below it whatever the code (negative, never passed, for a
                // threshold below 2⁻²² of linear light, which no curve here has).
                let below = ((q31[code + 1] >> 1) >> 8) as i32 - 1;
                (below << 8) | code as i32
            };
            j += 1;
        }
        IntegerCurve {
            limits,
            q31,
            f32_bits,
        }
    }

    /// The number of thresholds θₖ (k ≥ 1) with `⌈θₖ · 2³¹⌉ ≤ key`, which is the number with
    /// θₖ ≤ key / 2³¹ (`key` < 2³¹), and the next threshold on the 2³¹ scale (`u32::MAX` after
    /// the last): the code at the start of the key's stretch, then one step per threshold
    /// inside the stretch.
    #[inline(always)]
    fn count_q31(&self, key: u32) -> (usize, u32) {
        let mut code = self.limits[(key >> INDEX_SHIFT) as usize & (INDEX_LEN - 1)] as u8;
        loop {
            // code ≤ 255, so the index is in range: the sentinel at 256 ends the search.
            let next = self.q31[usize::from(code) + 1];
            if next > key {
                return (usize::from(code), next);
            }
            code = code.wrapping_add(1);
        }
    }

    /// `⌈θₖ · 2⁶³⌉` (θₖ ≤ 1, so at most 2⁶³).
    #[inline]
    fn q63(&self, k: usize) -> u64 {
        scaled_ceil(self.f32_bits[k & 255], 63)
    }
}

/// `⌈θ · 2^scale⌉` for the positive f32 θ with bits `bits` (at most 1.0), `scale` ≤ 63; 0 for
/// `bits` = 0.
const fn scaled_ceil(bits: u32, scale: i32) -> u64 {
    let exp = ((bits >> 23) & 0xff) as i32;
    let frac = (bits & 0x7f_ffff) as u64;
    // θ = m · 2^(e − 150) with m the 24-bit significand (subnormals: exponent field 1, no
    // implicit bit).
    let (m, e) = if exp == 0 {
        (frac, 1)
    } else {
        (frac | 0x80_0000, exp)
    };
    if m == 0 {
        return 0;
    }
    let s = e - 150 + scale;
    if s >= 0 {
        m << s
    } else if -s >= 64 {
        1
    } else {
        let r = -s as u32;
        (m >> r) + if m & ((1u64 << r) - 1) != 0 { 1 } else { 0 }
    }
}

/// The f32 thresholds of `quantize_u8`, the 8-bit encoder of [`TransferFunction::Linear`]:
/// entry k is the smallest f32 x in 0..=1 with `(x · 255 + 0.5) as u8 ≥ k` (f32 arithmetic, as
/// `quantize_u8` computes it), found by bisection on the bits.
const fn linear_thresholds() -> [u32; 256] {
    let mut t = [0u32; 256];
    let mut k = 1;
    while k < 256 {
        // quantize_u8 is non-decreasing in x: bisect on the bits of 0..=1.
        let (mut lo, mut hi) = (0u32, 0x3f80_0000u32);
        while lo < hi {
            let mid = lo + (hi - lo) / 2;
            let x = f32::from_bits(mid);
            if (x * 255.0 + 0.5) as u8 as usize >= k {
                hi = mid;
            } else {
                lo = mid + 1;
            }
        }
        t[k] = lo;
        k += 1;
    }
    t
}

static SRGB_THRESHOLDS: [u32; 256] = crate::encode::THRESHOLDS;
static SRGB: IntegerCurve = IntegerCurve::from_f32_thresholds(&SRGB_THRESHOLDS);
static LINEAR_THRESHOLDS: [u32; 256] = linear_thresholds();
static LINEAR: IntegerCurve = IntegerCurve::from_f32_thresholds(&LINEAR_THRESHOLDS);
/// One per baked power law, in the order of `tables::GAMMA_ENCODERS`.
static GAMMA: [IntegerCurve; crate::tables::GAMMA_ENCODERS.len()] = {
    const K: usize = crate::tables::GAMMA_ENCODERS.len();
    let mut curves = [const {
        IntegerCurve {
            limits: [0; INDEX_LEN],
            q31: [0; 257],
            f32_bits: &SRGB_THRESHOLDS,
        }
    }; K];
    let mut i = 0;
    while i < K {
        curves[i] = IntegerCurve::from_f32_thresholds(&crate::tables::GAMMA_ENCODERS[i].thresholds);
        i += 1;
    }
    curves
};

/// The integer encoder for `transfer`: sRGB, linear, and the power laws of the baked displays.
const fn curve_for(transfer: TransferFunction) -> Option<&'static IntegerCurve> {
    match transfer {
        TransferFunction::Srgb => Some(&SRGB),
        TransferFunction::Linear => Some(&LINEAR),
        TransferFunction::Gamma(g) => {
            let mut i = 0;
            while i < GAMMA.len() {
                if crate::tables::GAMMA_ENCODERS[i].gamma.to_bits() == g.to_bits() {
                    return Some(&GAMMA[i]);
                }
                i += 1;
            }
            None
        }
        TransferFunction::Lut(_) => None,
    }
}

/// A value `x` as `(negative, m, e)` with |x| = m · 2^e exactly; `None` for ±Inf and NaN.
const fn decompose(x: f32) -> Option<(bool, u64, i32)> {
    let bits = x.to_bits();
    let exp = ((bits >> 23) & 0xff) as i32;
    let frac = (bits & 0x7f_ffff) as u64;
    let negative = bits >> 31 == 1;
    match exp {
        0xff => None,
        0 => Some((negative, frac, -149)),
        _ => Some((negative, frac | 0x80_0000, exp - 150)),
    }
}

/// `w · q · 2^p` rounded to the nearest integer (ties away from zero), exactly; `None` if `w`
/// or `q` is not finite or the result reaches 2⁶².
const fn fixed_point(w: f32, q: f32, p: i32) -> Option<i64> {
    let (Some((nw, mw, ew)), Some((nq, mq, eq))) = (decompose(w), decompose(q)) else {
        return None;
    };
    // Both significands have at most 24 bits: the product is exact in 48.
    let m = mw * mq;
    if m == 0 {
        return Some(0);
    }
    let e = ew + eq + p;
    let magnitude = if e >= 0 {
        // m < 2⁴⁸: shifted by 14 or more it could reach 2⁶².
        if e >= 14 || (m << e) >= 1 << 62 {
            return None;
        }
        m << e
    } else if -e >= 64 {
        0
    } else {
        let r = -e as u32;
        // m < 2⁴⁸, so adding half of 2^r cannot overflow.
        (m + (1u64 << (r - 1))) >> r
    };
    let v = magnitude as i64;
    Some(if nw != nq { -v } else { v })
}

/// The fixed-point weights of `weights · q` at `p` fractional bits, and their top bits
/// (`V >> 16`, floor), if `p` keeps every channel's coarse sum inside i32 with room for the
/// margin `N · 65535`; `None` otherwise. Then each `|V >> 16| < 2¹⁵` and each `|V| < 2³¹`.
#[allow(clippy::type_complexity)]
const fn split_at<const N: usize>(
    weights: &[[f32; N]; 3],
    q: f32,
    p: i32,
) -> Option<([[i32; N]; 3], [[i32; N]; 3])> {
    let mut full = [[0i32; N]; 3];
    let mut coarse = [[0i32; N]; 3];
    let margin = N as i64 * 65535;
    let mut c = 0;
    while c < 3 {
        let mut sum: i64 = margin;
        let mut i = 0;
        while i < N {
            let Some(v) = fixed_point(weights[c][i], q, p) else {
                return None;
            };
            let a = v >> 16;
            sum += (if a < 0 { -a } else { a }) * 65535;
            if sum > i32::MAX as i64 {
                return None;
            }
            // |a| · 65535 < 2³¹, so |a| < 2¹⁵ and |v| < 2³¹.
            full[c][i] = v as i32;
            coarse[c][i] = a as i32;
            i += 1;
        }
        c += 1;
    }
    Some((full, coarse))
}

/// One sample into the coarse sums `acc` (three channels, then the samples' total).
#[inline(always)]
fn mac(acc: &mut [i32; 4], x: u16, w0: i32, w1: i32, w2: i32) {
    let s = i32::from(x);
    acc[0] = acc[0].wrapping_add(w0.wrapping_mul(s));
    acc[1] = acc[1].wrapping_add(w1.wrapping_mul(s));
    acc[2] = acc[2].wrapping_add(w2.wrapping_mul(s));
    acc[3] = acc[3].wrapping_add(s);
}

/// [`mac`] over the samples four at a time; returns how many it took.
#[cfg(not(arm_dsp))]
#[inline(always)]
fn mac_steps_of_4<const N: usize>(w: &[[i32; N]; 3], x: &[u16; N], acc: &mut [i32; 4]) -> usize {
    let (x4, _) = x.as_chunks::<4>();
    let (w0, w1, w2) = (
        w[0].as_chunks::<4>().0,
        w[1].as_chunks::<4>().0,
        w[2].as_chunks::<4>().0,
    );
    for (((x, w0), w1), w2) in x4.iter().zip(w0).zip(w1).zip(w2) {
        mac(acc, x[0], w0[0], w1[0], w2[0]);
        mac(acc, x[1], w0[1], w1[1], w2[1]);
        mac(acc, x[2], w0[2], w1[2], w2[2]);
        mac(acc, x[3], w0[3], w1[3], w2[3]);
    }
    N / 4 * 4
}

/// [`mac`] over the samples two at a time; returns how many it took.
#[cfg(not(arm_dsp))]
#[inline(always)]
fn mac_steps_of_2<const N: usize>(w: &[[i32; N]; 3], x: &[u16; N], acc: &mut [i32; 4]) -> usize {
    let (x2, _) = x.as_chunks::<2>();
    let (w0, w1, w2) = (
        w[0].as_chunks::<2>().0,
        w[1].as_chunks::<2>().0,
        w[2].as_chunks::<2>().0,
    );
    for (((x, w0), w1), w2) in x2.iter().zip(w0).zip(w1).zip(w2) {
        mac(acc, x[0], w0[0], w1[0], w2[0]);
        mac(acc, x[1], w0[1], w1[1], w2[1]);
    }
    N / 2 * 2
}

/// The coarse weights `cᵢ = Vᵢ >> 16` packed for a dual 16 × 16-bit multiply-accumulate
/// (Armv7E-M's `SMLAD`), which multiplies signed halves. The counts are unsigned, so they go in
/// as `xᵢ − 32768` (a u16 with its top bit flipped, read as i16), and the head adds back what
/// that took away: `Σᵢ cᵢ xᵢ = 32768 · Σᵢ cᵢ + Σᵢ cᵢ (xᵢ − 32768)`. Nothing overflows: |cᵢ| <
/// 2¹⁵ (so cᵢ is an i16), |xᵢ − 32768| ≤ 2¹⁵, and every partial sum, in any order, is
/// `Σ cᵢ xᵢ` over the samples taken plus `32768 · Σ cᵢ` over the others, at most
/// `Σᵢ |cᵢ| · 65535` in magnitude: inside the bound new() proved for `h`. Likewise the total's.
#[repr(C, align(4))]
#[derive(Debug, Clone, Copy)]
struct Packed<const N: usize> {
    /// `32768 · Σᵢ cᵢ` per channel (R, G, B), then `32768 · n`, the start of `Σᵢ xᵢ` (to which
    /// a multiply-accumulate by 1 adds each `xᵢ − 32768`), over the n = 2 · ⌊N / 2⌋ samples
    /// in pairs (an odd N's last sample is added as it is).
    head: [i32; 4],
    /// In pairs of samples (2k, 2k + 1), for k below N / 2: three words, R, G and B, each
    /// `c₂ₖ` in its low half and `c₂ₖ₊₁` in its high half, as halves `6k + 2·channel + 0/1`
    /// of this array read flat (three halves per entry). An odd N's last sample is not here.
    halves: [[i16; 3]; N],
}

impl<const N: usize> Packed<N> {
    const fn new(coarse: &[[i32; N]; 3]) -> Packed<N> {
        let mut head = [0i32; 4];
        let mut halves = [[0i16; 3]; N];
        let mut c = 0;
        while c < 3 {
            let mut i = 0;
            while i < N {
                // |cᵢ| < 2¹⁵ (new()'s bound), so both casts are exact and |Σᵢ cᵢ| · 32768 is
                // within the same bound.
                if i < N / 2 * 2 {
                    head[c] += coarse[c][i] * 32768;
                    let flat = 6 * (i / 2) + 2 * c + i % 2;
                    halves[flat / 3][flat % 3] = coarse[c][i] as i16;
                }
                i += 1;
            }
            c += 1;
        }
        head[3] = (N / 2 * 2) as i32 * 32768;
        Packed { head, halves }
    }

    /// Word `3k + channel` of the pairs (k < N / 2), as `SMLAD` reads it from memory.
    #[cfg(test)]
    fn pair_word(&self, k: usize, c: usize) -> u32 {
        let half = |flat: usize| u32::from(self.halves[flat / 3][flat % 3] as u16);
        let flat = 6 * k + 2 * c;
        half(flat) | half(flat + 1) << 16
    }
}

/// The coarse sums with the DSP extension's `SMLAD` (Armv7E-M: Cortex-M4, M7, M33 with DSP),
/// which stable Rust reaches only by inline assembly. The build script sets `arm_dsp` for
/// thumbv7em targets, where the instruction always exists.
#[cfg(arm_dsp)]
#[allow(unsafe_code)]
mod dsp {
    use super::Packed;
    use core::arch::asm;

    /// `[Σᵢ c_Rᵢ xᵢ, Σᵢ c_Gᵢ xᵢ, Σᵢ c_Bᵢ xᵢ, Σᵢ xᵢ]` over the samples in pairs (an odd N's last
    /// sample is left to the caller), exactly: see [`Packed`] for why nothing overflows.
    #[inline(always)]
    pub(super) fn pair_sums<const N: usize>(packed: &Packed<N>, x: &[u16; N]) -> [i32; 4] {
        let mut p = (packed as *const Packed<N>).cast::<u32>();
        let (mut h0, mut h1, mut h2, mut t): (i32, i32, i32, i32);
        // SAFETY: reads the head, the first 16 bytes at p (a 4-byte aligned `Packed`, head
        // first), and leaves p at the pairs; no store, no stack, no flags.
        unsafe {
            asm!(
                "ldrd {h0}, {h1}, [{p}], #8",
                "ldrd {h2}, {t}, [{p}], #8",
                p = inout(reg) p,
                h0 = out(reg) h0,
                h1 = out(reg) h1,
                h2 = out(reg) h2,
                t = out(reg) t,
                options(pure, readonly, nostack, preserves_flags),
            );
        }
        let ones = 0x0001_0001u32;
        // Both counts of a pair less 32768: the top bit of each half flipped.
        let biased =
            |pair: &[u16; 2]| (u32::from(pair[0]) | u32::from(pair[1]) << 16) ^ 0x8000_8000;
        let (quads, rest) = x.as_chunks::<4>();
        for quad in quads {
            let (x01, x23) = (biased(&[quad[0], quad[1]]), biased(&[quad[2], quad[3]]));
            // SAFETY: reads two pairs' six words at p (24 bytes: N / 2 pairs follow the
            // head, and this loop and the next take them in order, all 4-byte aligned) and
            // leaves p at the next pair; no store, no stack. SMLAD sets only the Q flag (on
            // overflow, which cannot happen here).
            unsafe {
                asm!(
                    "ldrd {w0}, {w1}, [{p}], #8",
                    "smlad {h0}, {x01}, {w0}, {h0}",
                    "smlad {h1}, {x01}, {w1}, {h1}",
                    "ldrd {w0}, {w1}, [{p}], #8",
                    "smlad {h2}, {x01}, {w0}, {h2}",
                    "smlad {h0}, {x23}, {w1}, {h0}",
                    "ldrd {w0}, {w1}, [{p}], #8",
                    "smlad {h1}, {x23}, {w0}, {h1}",
                    "smlad {h2}, {x23}, {w1}, {h2}",
                    "smlad {t}, {x01}, {ones}, {t}",
                    "smlad {t}, {x23}, {ones}, {t}",
                    p = inout(reg) p,
                    x01 = in(reg) x01,
                    x23 = in(reg) x23,
                    ones = in(reg) ones,
                    h0 = inout(reg) h0,
                    h1 = inout(reg) h1,
                    h2 = inout(reg) h2,
                    t = inout(reg) t,
                    w0 = out(reg) _,
                    w1 = out(reg) _,
                    options(pure, readonly, nostack),
                );
            }
        }
        for pair in rest.as_chunks::<2>().0 {
            let x01 = biased(pair);
            // SAFETY: reads the pair's three words at p (as above) and leaves p after them.
            unsafe {
                asm!(
                    "ldrd {w0}, {w1}, [{p}], #8",
                    "ldr {w2}, [{p}], #4",
                    "smlad {h0}, {x01}, {w0}, {h0}",
                    "smlad {h1}, {x01}, {w1}, {h1}",
                    "smlad {h2}, {x01}, {w2}, {h2}",
                    "smlad {t}, {x01}, {ones}, {t}",
                    p = inout(reg) p,
                    x01 = in(reg) x01,
                    ones = in(reg) ones,
                    h0 = inout(reg) h0,
                    h1 = inout(reg) h1,
                    h2 = inout(reg) h2,
                    t = inout(reg) t,
                    w0 = out(reg) _,
                    w1 = out(reg) _,
                    w2 = out(reg) _,
                    options(pure, readonly, nostack),
                );
            }
        }
        [h0, h1, h2, t]
    }

    /// `limits[clamp(h >> S, 0, 4095)]`: the limit of the stretch of a coarse sum `h` on the
    /// scale `2^(S + 12)` (P = S + 28), in two instructions (USAT clamps after the shift).
    #[inline(always)]
    pub(super) fn limit<const S: u32>(limits: &[i32; super::INDEX_LEN], h: i32) -> i32 {
        let limit: i32;
        // SAFETY: USAT leaves j in 0..=4095, so the load reads one of the 4096 entries of
        // `limits` (4-byte aligned); no store, no stack. USAT sets only the Q flag.
        unsafe {
            asm!(
                "usat {j}, #12, {h}, asr #{s}",
                "ldr {limit}, [{base}, {j}, lsl #2]",
                h = in(reg) h,
                base = in(reg) limits.as_ptr(),
                j = out(reg) _,
                limit = lateout(reg) limit,
                s = const S,
                options(pure, readonly, nostack),
            );
        }
        limit
    }
}

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

    /// `Σᵢ (Vᵢ >> 16) · xᵢ` per channel, in i32, and `Σᵢ xᵢ`: no overflow for any u16 input,
    /// by the bound [`new`](Self::new) checked (wrapping operations only so that no overflow
    /// check is compiled in). The samples go a few at a time, written out: at opt-level "s"
    /// the compiler keeps loops rolled, and a Cortex-M0, with eight registers for a loop's
    /// sums, pointers and counter, spills them. Four a step suits N = 4 (one step, no loop),
    /// two a step larger N (fewer values live at once).
    #[inline(always)]
    fn coarse_sums(&self, x: &[u16; N]) -> ([i32; 3], i32) {
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
        // F / 2^16 = h + Σᵢ (Vᵢ mod 2¹⁶) · xᵢ / 2¹⁶, and the low halves are below 2¹⁶: F / 2^16
        // is at least h and, unless every count is 0 (then F = h = 0), below h + Σᵢ xᵢ, `top`.
        // No overflow: new() bounded |h| + N · 65535 by i32::MAX.
        let top = h.wrapping_add(total);
        // h clamped to 0..1.0 on the 2³¹ scale: below 0 it has code 0 (the first threshold is
        // above 0), from 1.0 − 2^(16−P) up code 255 (new() checked that the last threshold is
        // not above it, nor in the last stretch).
        let key = (h.clamp(0, self.one - 1) as u32) << self.shift;
        let limit = self.limit::<S>(h, key);
        // top on the 2³⁰ scale, as i32. For 0 ≤ h < 1.0 it is exact: top is below 1.0 plus
        // the margin, less than 2 · 1.0 (new() made 1.0 exceed the margin). Then below the
        // limit it is below the next threshold after the stretch's start, and so is F: the
        // code is the low byte. For h < 0 the entry is the first (code 0, right for any F
        // below top, which is then below the first threshold or negative), and for h ≥ 1.0
        // the last (code 255, `i32::MAX`): there a wrapped value is wrong only in which path
        // it takes, never in the code.
        let top30 = (top as u32).wrapping_shl(self.shift - 1) as i32;
        if top30 < limit {
            return limit as u8;
        }
        // Most often the stretch holds one threshold, at or below h: then the code is one
        // more, if the threshold after it is above top. (code + 1 ≤ 256 is in range; code + 2
        // is masked, and entry 0 for code 254 only sends the value on to `settle`.)
        let code = usize::from(limit as u8);
        if key >= self.curve.q31[code + 1] {
            let key_top = (top.max(0) as u32) << self.shift;
            if key_top < self.curve.q31[(code + 2) & 255] {
                return code as u8 + 1;
            }
        }
        self.settle(c, h, total, x)
    }

    /// The limit of the stretch of `h`, whose key (h clamped to 0..1.0 on the 2³¹ scale) is
    /// `key`. `S` is 0, or on Armv7E-M `P − 28`: then the shift is a constant in the code.
    #[inline(always)]
    fn limit<const S: u32>(&self, h: i32, key: u32) -> i32 {
        // (h clamped) >> (P − 28) is key >> 19: see `dsp::limit`.
        #[cfg(arm_dsp)]
        if S != 0 {
            return dsp::limit::<S>(&self.curve.limits, h);
        }
        let _ = h;
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

    /// The limits' low bytes give the code at the start of each stretch, and from there the
    /// search finds every threshold: every key at and next to each threshold, for each curve.
    #[test]
    fn the_limits_find_every_threshold() {
        for curve in [&SRGB, &LINEAR].into_iter().chain(GAMMA.iter()) {
            let full = |key: u32| (1..256).filter(|&k| curve.q31[k] <= key).count();
            for k in 1..256 {
                let t = curve.q31[k];
                for key in [t.saturating_sub(1), t, t + 1] {
                    if key < 1 << 31 {
                        assert_eq!(curve.count_q31(key).0, full(key), "{key:#x}");
                    }
                }
            }
            for key in (0..1u32 << 31).step_by(65_537) {
                assert_eq!(curve.count_q31(key).0, full(key), "{key:#x}");
            }
        }
        // sRGB: a stretch holds at most one threshold (so one step from its start finds the
        // code, as the encoder's second test assumes most often).
        for j in 0..INDEX_LEN - 1 {
            let code = usize::from(SRGB.limits[j] as u8);
            assert!(
                usize::from(SRGB.limits[j + 1] as u8) <= code + 1,
                "stretch {j}"
            );
        }
    }

    /// Each limit is what the encoder's one comparison needs: its low byte the code at the
    /// stretch's start, and every value on the 2³⁰ scale below it below the next threshold
    /// (`2 · v < ⌈θ · 2³¹⌉` for the largest such v), by at most 2¹¹ on the 2³¹ scale (so the
    /// test passes nearly every value that could pass). The last stretch holds no threshold.
    #[test]
    fn each_limit_is_below_the_next_threshold_and_holds_the_code() {
        for curve in [&SRGB, &LINEAR].into_iter().chain(GAMMA.iter()) {
            for (j, &limit) in curve.limits.iter().enumerate() {
                let start = (j as u32) << INDEX_SHIFT;
                let code = (1..256).filter(|&k| curve.q31[k] <= start).count();
                assert_eq!(usize::from(limit as u8), code, "stretch {j}");
                if code == 255 {
                    assert_eq!(limit, i32::MAX);
                    continue;
                }
                let next = i64::from(curve.q31[code + 1]);
                let largest_below = i64::from(limit) - 1;
                assert!(2 * largest_below < next, "stretch {j}");
                assert!(2 * largest_below >= next - (1 << 11), "stretch {j}");
            }
            assert_eq!(curve.limits[INDEX_LEN - 1], i32::MAX);
        }
    }

    /// On Armv7E-M the stretch is `USAT #12` of `h >> (P − 28)` (`dsp::limit`), elsewhere the
    /// key's top bits: the same entry for every h, at P = 45 and 46 (the two it is used for).
    #[test]
    fn the_clamped_shift_finds_the_keys_stretch() {
        for p in [45u32, 46] {
            let one = 1i32 << (p - 16);
            let usat12 = |h: i32| (h >> (p - 28)).clamp(0, 4095) as usize;
            let by_key =
                |h: i32| (((h.clamp(0, one - 1) as u32) << (47 - p)) >> INDEX_SHIFT) as usize;
            let mut state = 0x243f_6a88_85a3_08d3u64;
            let mut values = std::vec![
                i32::MIN,
                i32::MIN + 1,
                -one,
                -1,
                0,
                1,
                one - 1,
                one,
                one + 1
            ];
            values.extend([
                i32::MAX - 1,
                i32::MAX,
                (one >> 12) - 1,
                one >> 12,
                one >> 12 | 1,
            ]);
            // Miri runs about a million times slower: fewer there.
            for _ in 0..if cfg!(miri) { 300 } else { 100_000 } {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                values.push(state as i32 >> (state >> 59));
            }
            for h in values {
                assert_eq!(usat12(h), by_key(h), "P {p}, h {h}");
            }
        }
    }

    /// The thresholds on the 2³¹ and 2⁶³ scales are the f32 thresholds rounded up.
    #[test]
    fn scaled_thresholds() {
        assert_eq!(scaled_ceil(1.0f32.to_bits(), 31), 1 << 31);
        assert_eq!(scaled_ceil(1.0f32.to_bits(), 63), 1 << 63);
        assert_eq!(scaled_ceil(0.5f32.to_bits(), 31), 1 << 30);
        // 2⁻⁴⁰ · (1 + 2⁻²³) on the 2³¹ scale is a little over 2⁻⁹: rounded up to 1.
        assert_eq!(scaled_ceil((87 << 23) | 1, 31), 1);
        assert_eq!(scaled_ceil((87 << 23) | 1, 63), (1 << 23) + 1);
        assert_eq!(scaled_ceil(1, 63), 1);
        assert_eq!(scaled_ceil(0, 63), 0);
        for k in 1..256 {
            let theta = f64::from(f32::from_bits(SRGB.f32_bits[k]));
            assert!(f64::from(SRGB.q31[k]) >= theta * 2f64.powi(31));
            assert!(f64::from(SRGB.q31[k]) - 1.0 < theta * 2f64.powi(31));
        }
    }

    /// `fixed_point` against f64 (exact here: both significands have 24 bits).
    #[test]
    fn fixed_point_is_exact() {
        for (w, q, p) in [
            (0.3f32, 1.0 / 65535.0, 46),
            (-1.7, 3.1e-4, 40),
            (1e-30, 1.0, 46),
            (6.0e-39, 1.0, 46),
            (-2.5, 1.0, 20),
        ] {
            let exact = f64::from(w) * f64::from(q) * 2f64.powi(p);
            let want = (exact.abs() + 0.5).floor().copysign(exact) as i64;
            assert_eq!(fixed_point(w, q, p), Some(want), "{w} {q} {p}");
        }
        assert_eq!(fixed_point(1e30, 1.0, 46), None);
        assert_eq!(fixed_point(f32::NAN, 1.0, 20), None);
        assert_eq!(fixed_point(1.0, f32::INFINITY, 20), None);
    }
    /// `SMLAD` as the Arm architecture defines it: `acc` plus the products of the signed low
    /// halves and of the signed high halves, computed exactly; the result must fit i32 (else
    /// the instruction would wrap and set the Q flag).
    fn smlad(a: u32, b: u32, acc: i32) -> i32 {
        let half = |v: u32, k: u32| i64::from((v >> (16 * k)) as u16 as i16);
        let r = i64::from(acc) + half(a, 0) * half(b, 0) + half(a, 1) * half(b, 1);
        i32::try_from(r).expect("SMLAD overflows")
    }

    /// `dsp::pair_sums` in portable Rust: the same words, the same instructions in the same
    /// order (the quads' interleaving, then a last pair, then an odd N's last sample).
    fn pair_sums_emulated<const N: usize>(set: &IntegerSet<N>, x: &[u16; N]) -> ([i32; 3], i32) {
        let packed = &set.packed;
        let [mut h0, mut h1, mut h2, mut t] = packed.head;
        let ones = 0x0001_0001;
        let biased = |i: usize| (u32::from(x[i]) | u32::from(x[i + 1]) << 16) ^ 0x8000_8000;
        let w = |k: usize, c: usize| packed.pair_word(k, c);
        for q in 0..N / 4 {
            let (x01, x23) = (biased(4 * q), biased(4 * q + 2));
            h0 = smlad(x01, w(2 * q, 0), h0);
            h1 = smlad(x01, w(2 * q, 1), h1);
            h2 = smlad(x01, w(2 * q, 2), h2);
            h0 = smlad(x23, w(2 * q + 1, 0), h0);
            h1 = smlad(x23, w(2 * q + 1, 1), h1);
            h2 = smlad(x23, w(2 * q + 1, 2), h2);
            t = smlad(x01, ones, t);
            t = smlad(x23, ones, t);
        }
        if N % 4 >= 2 {
            let k = N / 2 - 1;
            let x01 = biased(2 * k);
            h0 = smlad(x01, w(k, 0), h0);
            h1 = smlad(x01, w(k, 1), h1);
            h2 = smlad(x01, w(k, 2), h2);
            t = smlad(x01, ones, t);
        }
        let mut acc = [h0, h1, h2, t];
        if N % 2 == 1 {
            let [w0, w1, w2] = &set.coarse;
            mac(&mut acc, x[N - 1], w0[N - 1], w1[N - 1], w2[N - 1]);
        }
        ([acc[0], acc[1], acc[2]], acc[3])
    }

    /// The plain coarse sums, `Σᵢ cᵢ xᵢ` and `Σᵢ xᵢ`, in i64 (no overflow to hide).
    fn plain_sums<const N: usize>(set: &IntegerSet<N>, x: &[u16; N]) -> ([i32; 3], i32) {
        let sum = |w: &[i32; N]| {
            (0..N)
                .map(|i| i64::from(w[i]) * i64::from(x[i]))
                .sum::<i64>()
        };
        let h = set
            .coarse
            .each_ref()
            .map(|w| i32::try_from(sum(w)).unwrap());
        (h, x.iter().map(|&v| i32::from(v)).sum())
    }

    /// The packed weights and their head, through SMLAD as Armv7E-M runs it, give the plain
    /// coarse sums (and so does the portable path), with no intermediate overflow: on the
    /// extreme counts (0, 32767, 32768 and 65535 in every combination that makes a sum
    /// largest or smallest) and on random ones.
    fn check_packed<const N: usize>(name: &str, set: &IntegerSet<N>) -> usize {
        let mut inputs: std::vec::Vec<[u16; N]> = std::vec::Vec::new();
        for c in 0..3 {
            // Largest and smallest h: full scale where the weight is positive (negative).
            for sign in [1, -1] {
                inputs.push(core::array::from_fn(|i| {
                    if set.coarse[c][i] * sign > 0 {
                        u16::MAX
                    } else {
                        0
                    }
                }));
            }
        }
        for v in [0, 1, 0x7fff, 0x8000, 0x8001, u16::MAX] {
            inputs.push([v; N]);
        }
        let mut state = 0x9e37_79b9_7f4a_7c15u64 ^ N as u64;
        for _ in 0..if cfg!(miri) { 10 } else { 2_000 } {
            inputs.push(core::array::from_fn(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                let x = (state >> 48) as u16;
                // A quarter at the ends of the range, where the halves' signs flip.
                match state % 8 {
                    0 => u16::MAX - (x & 3),
                    1 => x & 3,
                    _ => x >> (state % 5),
                }
            }));
        }
        for x in &inputs {
            let plain = plain_sums(set, x);
            assert_eq!(pair_sums_emulated(set, x), plain, "{name} {x:?}");
            assert_eq!(set.coarse_sums(x), plain, "{name} {x:?}");
        }
        inputs.len()
    }

    macro_rules! check_packed_baked {
        ($($name:ident,)*) => {{
            let mut n = 0;
            $(
                check_packed(stringify!($name), &crate::tables::integer::$name);
                n += 1;
            )*
            n
        }};
    }

    #[test]
    fn the_packed_weights_give_the_coarse_sums_for_every_baked_set() {
        // The build's own list of the integer sets it baked.
        let n = crate::tables::integer::all!(check_packed_baked);
        assert_eq!(n, crate::tables::integer::NAMES.len());
        // The list holds every integer set the build baked.
        let baked = include_str!(concat!(env!("OUT_DIR"), "/tables.rs"));
        assert_eq!(baked.matches(": IntegerSet<").count(), n);
    }

    /// Sets made at run time, at other sizes (odd ones, whose last sample is not paired) and
    /// other P, with weights whose coarse form nearly fills the bound, of both signs.
    #[test]
    fn the_packed_weights_give_the_coarse_sums_for_sets_made_at_run_time() {
        fn made<const N: usize>(scale: f32, seed: u64) -> IntegerSet<N> {
            let mut state = seed;
            let weights = [0, 1, 2].map(|_| {
                core::array::from_fn(|_| {
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    ((state >> 40) as f32 / (1u64 << 24) as f32 - 0.5) * scale
                })
            });
            let base = crate::tables::folded::TABLE2_ROW2_SRGB;
            let folded = FoldedSet::<N> {
                wavelengths_nm: [550.0; N],
                weights,
                samples: base.samples,
                display: base.display,
            };
            IntegerSet::new(&folded, 1.0 / 65535.0).unwrap()
        }
        let mut frac_bits = std::collections::BTreeSet::new();
        for (k, scale) in [0.01f32, 1.0, 3.0, 40.0, 150.0].into_iter().enumerate() {
            let seed = 0x5851_f42d_4c95_7f2d ^ k as u64;
            macro_rules! run {
                ($($n:literal),*) => {$({
                    let set = made::<$n>(scale, seed);
                    frac_bits.insert(set.frac_bits);
                    check_packed(stringify!($n), &set);
                })*};
            }
            run!(1, 2, 3, 4, 5, 6, 7, 8, 9, 12, 16);
        }
        // P from the cap down to well below the two the Armv7E-M limit has a shift for.
        assert!(frac_bits.len() >= 5, "{frac_bits:?}");
    }
}
