//! The transfer curve on the integer scales: the f32 encoder's thresholds rounded up to 2³¹ and
//! 2⁶³, the table of limits that settles most codes with one look-up and one comparison, and
//! the settling of a channel's code from its coarse sum (refined by the exact sum where a
//! threshold lies within the margin).

#![forbid(unsafe_code)]

#[cfg(arm_dsp)]
use super::dsp;
use super::IntegerSet;
use crate::TransferFunction;

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
    pub(super) limits: [i32; INDEX_LEN],
    /// `⌈θₖ · 2³¹⌉` for k = 1..=255 (θₖ ≤ 1); entry 0 is 0, entry 256 is `u32::MAX`, above
    /// every key, so that a search needs no bounds test.
    pub(super) q31: [u32; 257],
    /// The bits of θₖ as f32, the f32 encoder's own thresholds; entry 0 is 0.
    f32_bits: &'static [u32; 256],
}

/// Entries of [`IntegerCurve::limits`]: one per 2¹⁹ on the 2³¹ scale.
pub(super) const INDEX_LEN: usize = 1 << 12;
/// The shift from a key on the 2³¹ scale to its entry in the limits.
pub(super) const INDEX_SHIFT: u32 = 31 - 12;

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
pub(super) const fn curve_for(transfer: TransferFunction) -> Option<&'static IntegerCurve> {
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

impl<const N: usize> IntegerSet<N> {
    /// The code value of channel `c` from its coarse sum `h` and `total = Σᵢ xᵢ`.
    #[inline(always)]
    pub(super) fn encode_channel<const S: u32>(
        &self,
        c: usize,
        h: i32,
        total: i32,
        x: &[u16; N],
    ) -> u8 {
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
}
