//! The transfer curve on the integer scales: the f32 encoder's thresholds rounded up to 2³¹ and
//! 2⁶³, and the table of limits that settles most codes with one look-up and one comparison;
//! the curve of each transfer function an integer set can encode. `set` settles a channel's
//! code on it.

#![forbid(unsafe_code)]

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
    /// entry is `i32::MAX` (code 255), as [`IntegerSet::new`](crate::IntegerSet::new) requires of the last stretch.
    pub(super) limits: [i32; INDEX_LEN],
    /// `⌈θₖ · 2³¹⌉` for k = 1..=255 (θₖ ≤ 1); entry 0 is 0, entries 256 and 257 are
    /// `u32::MAX`, above every key, so that a search needs no bounds test and entries
    /// `code + 1` and `code + 2` of any u8 code are in range.
    pub(super) q31: [u32; 258],
    /// The bits of θₖ as f32, the f32 encoder's own thresholds; entry 0 is 0.
    f32_bits: &'static [u32; 256],
}

/// Entries of [`IntegerCurve::limits`]: one per 2¹⁹ on the 2³¹ scale.
pub(super) const INDEX_LEN: usize = 1 << 12;
/// The shift from a key on the 2³¹ scale to its entry in the limits.
pub(super) const INDEX_SHIFT: u32 = 31 - 12;

impl IntegerCurve {
    const fn from_f32_thresholds(f32_bits: &'static [u32; 256]) -> IntegerCurve {
        let mut q31 = [0u32; 258];
        let mut k = 1;
        while k < 256 {
            q31[k] = scaled_ceil(f32_bits[k], 31) as u32;
            k += 1;
        }
        q31[256] = u32::MAX;
        q31[257] = u32::MAX;
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
    pub(super) fn count_q31(&self, key: u32) -> (usize, u32) {
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
    pub(super) fn q63(&self, k: usize) -> u64 {
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
            q31: [0; 258],
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

#[cfg(test)]
mod tests {
    use super::*;

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
