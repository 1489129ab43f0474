//! The fixed-point weights (each f32 weight times the sample unit, rounded once to P
//! fractional bits), and the portable steps of the coarse sums of counts times them (one sample
//! into the sums, and a few samples a step), which `set` runs; on Armv7E-M it runs `dsp`'s
//! instead.

#![forbid(unsafe_code)]

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
pub(super) const fn split_at<const N: usize>(
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
pub(super) fn mac(acc: &mut [i32; 4], x: u16, w0: i32, w1: i32, w2: i32) {
    let s = i32::from(x);
    acc[0] = acc[0].wrapping_add(w0.wrapping_mul(s));
    acc[1] = acc[1].wrapping_add(w1.wrapping_mul(s));
    acc[2] = acc[2].wrapping_add(w2.wrapping_mul(s));
    acc[3] = acc[3].wrapping_add(s);
}

/// [`mac`] over the samples four at a time; returns how many it took.
#[cfg(not(arm_dsp))]
#[inline(always)]
pub(super) fn mac_steps_of_4<const N: usize>(
    w: &[[i32; N]; 3],
    x: &[u16; N],
    acc: &mut [i32; 4],
) -> usize {
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
pub(super) fn mac_steps_of_2<const N: usize>(
    w: &[[i32; N]; 3],
    x: &[u16; N],
    acc: &mut [i32; 4],
) -> usize {
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
