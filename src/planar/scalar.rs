//! The planar sRGB encoder for targets without f32 vector units (microcontrollers such as the
//! Cortex-M4F): one pixel at a time, with the weights held in registers across the loop.
//!
//! [`FoldedSet::encode_u8_planar_to_interleaved`](crate::FoldedSet::encode_u8_planar_to_interleaved) calls it for the sRGB
//! curve with [`GamutMapping::Clip`](crate::GamutMapping::Clip) where the chunked loops of
//! [`planar`](super) would not vectorize. Its bytes equal
//! [`FoldedSet::encode_u8`](crate::FoldedSet::encode_u8) on every pixel: the same sums in the
//! same order, the same table.

#![forbid(unsafe_code)]

use crate::encode::srgb8_not_nan;

/// Steps over the samples written out one by one; steps beyond these (N > 8) run in a loop.
///
/// Written out, every weight is a value of its own that stays in a register for the whole loop
/// over pixels, and every plane's length is known. As a loop over the samples (what
/// `pixel::mat_vec` is), the weights are read from memory for every pixel, since opt-level "s" on
/// Arm unrolls no loop.
const UNROLLED: usize = 8;

/// Whether [`encode_srgb8_clip`] looks for NaN in a pixel's sum first, and in each channel only
/// where the sum is NaN (also where infinities of both signs meet): one test instead of three
/// where f32 arithmetic is an instruction. Not on Arm without an FPU (the Cortex-M0+), where
/// each addition is a call and the three tests are integer compares.
const SUM_FIRST: bool = !cfg!(all(target_arch = "arm", not(target_feature = "fpregs")));

/// `$body` for each `$k` in `0..N` in order: written out for `$k < UNROLLED` (steps with
/// `$k ≥ N` are constant `false` and compile to nothing), then a loop over the rest.
macro_rules! each_sample {
    (|$k:ident| $body:block) => {{
        each_sample!(@written $k $body; 0 1 2 3 4 5 6 7);
        // The same body by index as the written-out steps, not an iterator.
        #[allow(clippy::needless_range_loop)]
        for $k in UNROLLED..N $body
    }};
    (@written $k:ident $body:block; $($i:literal)*) => {
        $({
            let $k: usize = $i;
            if $k < N $body
        })*
    };
}

/// Linear RGB of pixel `p`: `weights · samples` with each channel summed in index order, a
/// product rounded then a sum rounded, as [`FoldedSet::linear_rgb`](crate::FoldedSet::linear_rgb)
/// does, but starting from the first product instead of 0.0. That only turns a sum of exact
/// zeros from +0.0 into −0.0 where the first product is −0.0, and both encode as 0.
#[inline(always)]
fn linear<const N: usize>(w: &[[f32; N]; 3], planes: &[&[f32]; N], p: usize) -> [f32; 3] {
    let mut acc = [0.0f32; 3];
    each_sample!(|k| {
        let s = planes[k][p];
        let terms = [w[0][k] * s, w[1][k] * s, w[2][k] * s];
        if k == 0 {
            acc = terms;
        } else {
            acc = [acc[0] + terms[0], acc[1] + terms[1], acc[2] + terms[2]];
        }
    });
    acc
}

/// Planar samples → sRGB-encoded 8-bit RGB with `Clip`, pixel by pixel: `out[p]` from
/// `samples[i][p]`, equal to `FoldedSet::encode_u8(GamutMapping::Clip, ..)` with these weights
/// and the sRGB curve. A pixel with a NaN channel is black; ±Inf and huge values clip.
///
/// The caller has checked that every plane holds `out.len()` samples; if one held fewer, this
/// would write nothing (it never panics).
pub(crate) fn encode_srgb8_clip<const N: usize>(
    weights: &[[f32; N]; 3],
    samples: [&[f32]; N],
    out: &mut [[u8; 3]],
) {
    let pixels = out.len();
    // Every plane cut to `pixels`, so that the compiler sees every index below in range.
    let mut planes = samples;
    each_sample!(|k| {
        match planes[k].get(..pixels) {
            Some(plane) => planes[k] = plane,
            None => return,
        }
    });
    // The weights copied, so that they are values of their own and not reloaded.
    let w = *weights;
    for (p, o) in out.iter_mut().enumerate() {
        let [r, g, b] = linear(&w, &planes, p);
        let px = [srgb8_not_nan(r), srgb8_not_nan(g), srgb8_not_nan(b)];
        // NaN anywhere makes the pixel black, as the per-pixel path does. The sum is NaN where
        // a channel is, and also where infinities of both signs meet: the channels themselves
        // decide then.
        let nan = (!SUM_FIRST || (r + g + b).is_nan()) && (r.is_nan() | g.is_nan() | b.is_nan());
        *o = if nan { [0; 3] } else { px };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tables::folded::TABLE2_ROW2_SRGB;
    use crate::test_inputs::{Rng, EDGES};
    use crate::{FoldedSet, GamutMapping};

    /// Pixels as `[[f32; N]]` to planes, encoded here and per pixel: the same bytes. In batches
    /// of up to `BATCH` pixels, on the stack (the library's tests link no allocator).
    fn check<const N: usize>(set: &FoldedSet<N>, pixels: &[[f32; N]]) {
        const BATCH: usize = 256;
        for batch in pixels.chunks(BATCH) {
            let n = batch.len();
            let planes: [[f32; BATCH]; N] = core::array::from_fn(|i| {
                core::array::from_fn(|p| batch.get(p).map_or(0.0, |px| px[i]))
            });
            let mut out = [[7u8; 3]; BATCH];
            encode_srgb8_clip(
                set.weights_ref(),
                planes.each_ref().map(|p| &p[..n]),
                &mut out[..n],
            );
            for (px, o) in batch.iter().zip(&out) {
                assert_eq!(*o, set.encode_u8(GamutMapping::Clip, px), "{px:?}");
            }
        }
    }

    #[test]
    fn edge_inputs_equal_per_pixel() {
        let set = TABLE2_ROW2_SRGB;
        // Every edge value in every position, the other samples ordinary; then every pair of
        // edge values in the first two and in the last two positions.
        let mut pixels = [[0.0f32; 4]; 4 * EDGES.len() + 2 * EDGES.len() * EDGES.len() + 2];
        let mut n = 0;
        let mut push = |px: [f32; 4]| {
            pixels[n] = px;
            n += 1;
        };
        for pos in 0..4 {
            for &x in &EDGES {
                let mut px = [0.3f32, 0.2, 0.25, 0.1];
                px[pos] = x;
                push(px);
            }
        }
        for &x in &EDGES {
            for &y in &EDGES {
                push([x, y, 0.2, 0.4]);
                push([0.1, 0.6, x, y]);
            }
        }
        push([f32::INFINITY, f32::NEG_INFINITY, 0.0, 0.0]);
        push([-0.0; 4]);
        assert_eq!(n, pixels.len());
        check(&set, &pixels);
        // Weights with both signs and zeros of both signs: first products of −0.0.
        let mut weights = set.weights();
        weights[1] = [-0.5, 0.0, 0.25, -0.0];
        weights[2] = [-0.0, -1.0, 0.0, 2.0];
        let with = |weights| {
            FoldedSet::new(set.wavelengths_nm(), weights, set.samples(), set.display()).unwrap()
        };
        let mixed = with(weights);
        check(&mixed, &pixels);
        // Channels of +Inf and −Inf (a NaN sum, but no NaN channel, so not black) for the
        // pixels with an infinite sample.
        let opposite = with([
            [1.0, 0.5, 0.5, 0.5],
            [-1.0, 0.5, 0.5, 0.5],
            [1.0, -2.0, 3.0, 4.0],
        ]);
        check(&opposite, &pixels);
        let px = [f32::INFINITY, 0.2, 0.25, 0.1];
        let [r, g, b] = opposite.linear_rgb(&px);
        assert!((r + g + b).is_nan() && !(r.is_nan() | g.is_nan() | b.is_nan()));
        assert_eq!(opposite.encode_u8(GamutMapping::Clip, &px), [255, 0, 255]);
    }

    /// `count` pixels of N samples: values in 0..2 (in and out of gamut, across the table's
    /// segments), small and negative ones, and now and then any bit pattern; checked in turn.
    fn check_random<const N: usize>(set: &FoldedSet<N>, seed: u64, count: usize) {
        let mut rng = Rng(seed);
        let mut sample = || {
            let r = rng.next();
            let x = (r >> 40) as f32 / (1u64 << 23) as f32;
            match r & 15 {
                0 => f32::from_bits((r >> 16) as u32),
                1 => -x,
                2 => x * 1e-3,
                _ => x,
            }
        };
        let mut batch = [[0.0f32; N]; 100];
        for _ in 0..count / batch.len() {
            for px in &mut batch {
                *px = core::array::from_fn(|_| sample());
            }
            check(set, &batch);
        }
    }

    #[test]
    fn random_pixels_equal_per_pixel() {
        // Under Miri, a tenth of the pixels.
        let scale = if cfg!(miri) { 10 } else { 1 };
        let set = TABLE2_ROW2_SRGB;
        check_random(&set, 0x9E37_79B9_7F4A_7C15, 5000 / scale);
        // Other lengths of the product: only written-out terms, and terms in the loop (N = 9).
        let with = |weights: [[f32; 9]; 3]| {
            let nm = core::array::from_fn(|i| 400.0 + i as f32);
            FoldedSet::new(nm, weights, set.samples(), set.display()).unwrap()
        };
        let weights4 = set.weights();
        let weights9 = core::array::from_fn(|c| {
            core::array::from_fn(|i| weights4[c][i % 4] * (1.0 - 0.1 * i as f32))
        });
        check_random(&with(weights9), 1, 2000 / scale);
        let one = FoldedSet::new(
            [550.0],
            [[0.7], [0.5], [-0.2]],
            set.samples(),
            set.display(),
        )
        .unwrap();
        check_random(&one, 2, 2000 / scale);
        let none = FoldedSet::<0>::new([], [[]; 3], set.samples(), set.display()).unwrap();
        check(&none, &[[]; 5]);
    }

    #[test]
    fn shorter_planes_are_not_read_past() {
        let set = TABLE2_ROW2_SRGB;
        let a = [0.5f32; 5];
        let b = [0.4f32; 3];
        let mut out = [[9u8; 3]; 5];
        encode_srgb8_clip(set.weights_ref(), [&a, &b, &a, &a], &mut out);
        assert_eq!(out, [[9; 3]; 5]);
        encode_srgb8_clip(set.weights_ref(), [&a, &b, &a, &a], &mut out[..3]);
        let one = set.encode_u8(GamutMapping::Clip, &[0.5, 0.4, 0.5, 0.5]);
        assert_eq!(out, [one, one, one, [9; 3], [9; 3]]);
    }
}
