//! The per-pixel sRGB 8-bit encode with [`Clip`](crate::GamutMapping::Clip)
//! ([`FoldedSet::encode_u8`](crate::FoldedSet::encode_u8) on x86-64): the three channels in the
//! lanes of one SSE2 register, the product and the table encoder's clamp and code values in
//! vector instructions. SSE2 is part of x86-64, so this needs no detection.

use core::arch::x86_64::*;

use crate::encode::{entry_at_top, LO};

/// [`srgb8`]`(`[`mat_vec`]`(weights, samples))`: the per-pixel sRGB 8-bit encode with
/// `Clip`.
#[inline]
pub(crate) fn encode_srgb8<const N: usize>(weights: &[[f32; N]; 3], samples: &[f32; N]) -> [u8; 3] {
    // SAFETY: SSE2 is part of x86-64: every x86-64 CPU has it.
    unsafe { srgb8(mat_vec(weights, samples)) }
}

/// The per-pixel sRGB 8-bit encode with `Clip` of a light-group set
/// ([`LightGroupSet::encode_u8`](crate::LightGroupSet::encode_u8)): each light's [`mat_vec`],
/// added in light order, then [`srgb8`]. Each lane's sum differs from the scalar path's
/// (light 0 started from its first product, the others from 0.0) only where a term is an
/// exact zero, in its sign, which `srgb8` encodes as 0 either way: the same bytes.
#[inline]
pub(crate) fn encode_srgb8_groups<const N: usize, const L: usize>(
    weights: &[[[f32; N]; 3]; L],
    groups: &[[f32; N]; L],
) -> [u8; 3] {
    // SAFETY: SSE2 is part of x86-64: every x86-64 CPU has it.
    unsafe {
        let mut acc = _mm_setzero_ps();
        for (l, (w, s)) in weights.iter().zip(groups).enumerate() {
            let p = mat_vec(w, s);
            acc = if l == 0 { p } else { _mm_add_ps(acc, p) };
        }
        srgb8(acc)
    }
}

/// `pixel::mat_vec(weights, s)` for every pixel `s` of `samples` into `out` (the same length),
/// four pixels at a time: each pixel's channels in the lanes of its own register, its sums
/// started from 0.0 and its products added in index order, as `mat_vec` adds them, so every
/// pixel gets the same bits. The four chains of additions are independent, so while one waits
/// for its last addition the others go on. Returns how many pixels it converted: all but fewer
/// than four. The weights' columns are built once, on the stack (N · 16 bytes; the caller
/// keeps N within `MAX_WAVELENGTHS`).
#[inline]
pub(crate) fn mat_vec_batch<const N: usize>(
    weights: &[[f32; N]; 3],
    samples: &[[f32; N]],
    out: &mut [[f32; 3]],
) -> usize {
    // SAFETY: SSE2 is part of x86-64: every x86-64 CPU has it.
    unsafe { mat_vec_batch_sse2(weights, samples, out) }
}

#[inline]
#[target_feature(enable = "sse2")]
fn mat_vec_batch_sse2<const N: usize>(
    weights: &[[f32; N]; 3],
    samples: &[[f32; N]],
    out: &mut [[f32; 3]],
) -> usize {
    let [w0, w1, w2] = weights;
    // Column i of the weights, built once for every pixel.
    let cols: [__m128; N] = core::array::from_fn(|i| _mm_setr_ps(w0[i], w1[i], w2[i], 0.0));
    let rgb = |a: __m128| {
        let mut v = [0.0f32; 4];
        // SAFETY: `v` has room for the four lanes; `storeu` takes any alignment.
        unsafe { _mm_storeu_ps(v.as_mut_ptr(), a) };
        [v[0], v[1], v[2]]
    };
    let mut done = 0;
    for (s, o) in samples.chunks_exact(4).zip(out.chunks_exact_mut(4)) {
        let [s0, s1, s2, s3] = [&s[0], &s[1], &s[2], &s[3]];
        let zero = _mm_setzero_ps();
        let (mut a0, mut a1, mut a2, mut a3) = (zero, zero, zero, zero);
        for (i, &col) in cols.iter().enumerate() {
            a0 = _mm_add_ps(a0, _mm_mul_ps(col, _mm_set1_ps(s0[i])));
            a1 = _mm_add_ps(a1, _mm_mul_ps(col, _mm_set1_ps(s1[i])));
            a2 = _mm_add_ps(a2, _mm_mul_ps(col, _mm_set1_ps(s2[i])));
            a3 = _mm_add_ps(a3, _mm_mul_ps(col, _mm_set1_ps(s3[i])));
        }
        o.copy_from_slice(&[rgb(a0), rgb(a1), rgb(a2), rgb(a3)]);
        done += 4;
    }
    done
}

/// `weights · samples` with the channels in lanes 0, 1, 2 (lane 3 is 0): each lane is the
/// first product, then the others added in index order, exactly as
/// `pixel::mat_vec_for_encoding`. Column by column: column i of the weights times sample i
/// broadcast, so each lane sees the same products added in the same order.
#[inline]
#[target_feature(enable = "sse2")]
pub(crate) fn mat_vec<const N: usize>(weights: &[[f32; N]; 3], samples: &[f32; N]) -> __m128 {
    let [w0, w1, w2] = weights;
    let mut acc = _mm_setzero_ps();
    for i in 0..N {
        let col = _mm_setr_ps(w0[i], w1[i], w2[i], 0.0);
        let p = _mm_mul_ps(col, _mm_set1_ps(samples[i]));
        acc = if i == 0 { p } else { _mm_add_ps(acc, p) };
    }
    acc
}

/// 8-bit sRGB of lanes 0..=2 of `rgb`, as `encode::srgb8_from_linear` on each, and black
/// when any of the three is NaN: the bytes of
/// [`Display::encode_u8`](crate::Display::encode_u8) with the sRGB curve and `Clip`.
#[inline]
#[target_feature(enable = "sse2")]
pub(crate) fn srgb8(rgb: __m128) -> [u8; 3] {
    // max(x, LO) is LO for a NaN x; the lanes are then in LO..=1.
    let c = _mm_min_ps(_mm_max_ps(rgb, _mm_set1_ps(LO)), _mm_set1_ps(1.0));
    let bits = _mm_castps_si128(c);
    // SAFETY: the top 16 bits of lanes clamped to LO..=1 (`maxps` and `minps`, which turn
    // NaN into LO), as `entry_at_top` requires.
    let at = |top: i32| unsafe { entry_at_top(top as u32) } as i32;
    let e = _mm_setr_epi32(
        at(_mm_extract_epi16::<1>(bits)),
        at(_mm_extract_epi16::<3>(bits)),
        at(_mm_extract_epi16::<5>(bits)),
        0,
    );
    // `bits << 8` is `(bits − LO_BITS) << 8`: see `encode::FIRST_TOP`.
    let code = _mm_srli_epi32::<24>(_mm_add_epi32(e, _mm_slli_epi32::<8>(bits)));
    let bytes = _mm_packus_epi16(_mm_packs_epi32(code, code), code);
    let word = _mm_cvtsi128_si32(bytes) as u32;
    let nan = _mm_movemask_ps(_mm_cmpunord_ps(rgb, rgb)) & 0b111;
    let word = if nan == 0 { word } else { 0 };
    let [r, g, b, _] = word.to_le_bytes();
    [r, g, b]
}
