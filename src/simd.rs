//! Explicit x86-64 vector code for the sRGB 8-bit and linear f32 paths.
//!
//! - [`sse2`]: the per-pixel [`FoldedSet::encode_u8`](crate::FoldedSet::encode_u8) for the
//!   sRGB curve with [`Clip`](crate::GamutMapping::Clip), the three channels in the lanes of
//!   one SSE2 register. SSE2 is part of x86-64, so this needs no detection.
//! - [`avx2`]: the batch and planar loops, eight pixels per AVX2 register, chosen at run time
//!   when the CPU has AVX2 ([`avx2::available`], detected once with the `cpufeatures` crate,
//!   which works without `std`). Otherwise the portable loops of `soa.rs` and `batch.rs` run.
//!
//! Every path computes each channel with the same f32 operations in the same order as
//! [`set::mat_vec_for_encoding`](crate::set::mat_vec_for_encoding) (or
//! [`set::mat_vec`](crate::set::mat_vec) for linear output) and encodes with the same table
//! (`encode::SEGMENT_TABLE`), so all of them give the per-pixel function's bytes, bit for bit.
//! FMA is not used, although every AVX2 CPU of the x86-64 world has it: a fused multiply-add
//! rounds once where the per-pixel function (and every target without FMA, the Cortex-M4F
//! among them) rounds twice, so the outputs would differ in the last bit, and now and then in an
//! encoded code value.

/// The accelerated planar sRGB 8-bit loop, where the CPU has one: encodes the first pixels
/// (a multiple of 8) of `planes` into `out` (3 bytes per pixel) and returns how many; 0 where
/// there is no accelerated loop, so the caller's portable loop does everything.
#[inline]
pub(crate) fn encode_srgb8_planar<const N: usize>(
    weights: &[[f32; N]; 3],
    planes: [&[f32]; N],
    out: &mut [u8],
) -> usize {
    #[cfg(target_arch = "x86_64")]
    if avx2::available() {
        // SAFETY: the CPU has AVX2 (checked just above).
        return unsafe { avx2::encode_srgb8_planar(weights, planes, out) };
    }
    let _ = (weights, planes, out);
    0
}

/// As [`encode_srgb8_planar`], for linear f32 output (three planes).
#[inline]
pub(crate) fn linear_planar<const N: usize>(
    weights: &[[f32; N]; 3],
    planes: [&[f32]; N],
    out: [&mut [f32]; 3],
) -> usize {
    #[cfg(target_arch = "x86_64")]
    if avx2::available() {
        // SAFETY: the CPU has AVX2 (checked just above).
        return unsafe { avx2::linear_planar(weights, planes, out) };
    }
    let _ = (weights, planes, out);
    0
}

/// As [`encode_srgb8_planar`], for interleaved samples (one `[f32; N]` per pixel).
#[inline]
pub(crate) fn encode_srgb8_batch<const N: usize>(
    weights: &[[f32; N]; 3],
    samples: &[[f32; N]],
    out: &mut [u8],
) -> usize {
    #[cfg(target_arch = "x86_64")]
    if avx2::available() {
        // SAFETY: the CPU has AVX2 (checked just above).
        return unsafe { avx2::encode_srgb8_batch(weights, samples, out) };
    }
    let _ = (weights, samples, out);
    0
}

#[cfg(target_arch = "x86_64")]
pub(crate) mod sse2 {
    use core::arch::x86_64::*;

    use crate::encode::{entry_at_top, LO};

    /// [`srgb8`]`(`[`mat_vec`]`(weights, samples))`: the per-pixel sRGB 8-bit encode with
    /// `Clip`.
    #[inline]
    pub(crate) fn encode_srgb8<const N: usize>(
        weights: &[[f32; N]; 3],
        samples: &[f32; N],
    ) -> [u8; 3] {
        // SAFETY: SSE2 is part of x86-64: every x86-64 CPU has it.
        unsafe { srgb8(mat_vec(weights, samples)) }
    }

    /// `weights · samples` with the channels in lanes 0, 1, 2 (lane 3 is 0): each lane is the
    /// first product, then the others added in index order, exactly as
    /// `set::mat_vec_for_encoding`. Column by column: column i of the weights times sample i
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
}

#[cfg(target_arch = "x86_64")]
pub(crate) mod avx2 {
    use core::arch::x86_64::*;

    use crate::encode::{entry_at_top, LO};

    cpufeatures::new!(cpu_avx2, "avx2");

    /// Pixels per AVX2 register.
    pub(crate) const LANES: usize = 8;

    /// Whether this CPU (and its operating system) supports AVX2: `cpuid` and `xgetbv` on the
    /// first call, a cached flag afterwards.
    #[inline]
    pub(crate) fn available() -> bool {
        cpu_avx2::get()
    }

    /// Eight f32 from an array.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn load(a: &[f32; LANES]) -> __m256 {
        // SAFETY: `a` is valid for reading 8 f32; the load has no alignment requirement.
        unsafe { _mm256_loadu_ps(a.as_ptr()) }
    }

    /// `weights · samples` for eight pixels (one per lane), each channel from its first product
    /// with the rest added in index order: `set::mat_vec_for_encoding`, lane by lane.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn products_for_encoding<const N: usize>(
        weights: &[[f32; N]; 3],
        s: &[__m256; N],
    ) -> [__m256; 3] {
        // Plain loops, no closures: a closure is compiled without the enclosing function's
        // target features, and its calls would not be inlined.
        let mut out = [_mm256_setzero_ps(); 3];
        for (acc, row) in out.iter_mut().zip(weights) {
            for (i, (w, s)) in row.iter().zip(s).enumerate() {
                let p = _mm256_mul_ps(_mm256_set1_ps(*w), *s);
                *acc = if i == 0 { p } else { _mm256_add_ps(*acc, p) };
            }
        }
        out
    }

    /// As [`products_for_encoding`] but from 0.0, as `set::mat_vec`: bit for bit
    /// [`FoldedSet::linear_rgb`](crate::FoldedSet::linear_rgb) (a −0.0 sum comes out +0.0).
    #[inline]
    #[target_feature(enable = "avx2")]
    fn products<const N: usize>(weights: &[[f32; N]; 3], s: &[__m256; N]) -> [__m256; 3] {
        let mut out = [_mm256_setzero_ps(); 3];
        for (acc, row) in out.iter_mut().zip(weights) {
            for (w, s) in row.iter().zip(s) {
                *acc = _mm256_add_ps(*acc, _mm256_mul_ps(_mm256_set1_ps(*w), *s));
            }
        }
        out
    }

    /// The 8-bit sRGB code of each lane (in the low byte of its 32 bits), as
    /// `encode::srgb8_from_linear`: a NaN lane gives 0.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn srgb8(x: __m256) -> __m256i {
        let c = _mm256_min_ps(_mm256_max_ps(x, _mm256_set1_ps(LO)), _mm256_set1_ps(1.0));
        let bits = _mm256_castps_si256(c);
        let top = _mm256_srli_epi32::<16>(bits);
        // The table entries by scalar loads, the indices taken out two at a time (64-bit
        // extracts, then a shift): on the CPUs measured (AMD Zen 3) this beats one
        // `vpgatherdd` (1.93 against 2.14 ns per pixel in cache) and 32-bit extracts.
        let lo = _mm256_castsi256_si128(top);
        let hi = _mm256_extracti128_si256::<1>(top);
        let [a, b, c, d] = [
            _mm_cvtsi128_si64(lo),
            _mm_extract_epi64::<1>(lo),
            _mm_cvtsi128_si64(hi),
            _mm_extract_epi64::<1>(hi),
        ]
        .map(|p| p as u64);
        // SAFETY: both halves of each pair are the top 16 bits of a lane clamped to LO..=1
        // (`maxps` and `minps`, which turn NaN into LO), as `entry_at_top` requires.
        let at = |top: u64| unsafe { entry_at_top(top as u32) } as i32;
        let e = _mm256_setr_epi32(
            at(a),
            at(a >> 32),
            at(b),
            at(b >> 32),
            at(c),
            at(c >> 32),
            at(d),
            at(d >> 32),
        );
        // `bits << 8` is `(bits − LO_BITS) << 8`: see `encode::FIRST_TOP`.
        _mm256_srli_epi32::<24>(_mm256_add_epi32(e, _mm256_slli_epi32::<8>(bits)))
    }

    /// Eight pixels of linear RGB → 24 bytes of interleaved 8-bit sRGB; a pixel with a NaN
    /// channel is black.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn encode8(rgb: [__m256; 3], dst: &mut [u8; 3 * LANES]) {
        let [r, g, b] = rgb;
        let nan = _mm256_or_ps(
            _mm256_or_ps(
                _mm256_cmp_ps::<_CMP_UNORD_Q>(r, r),
                _mm256_cmp_ps::<_CMP_UNORD_Q>(g, g),
            ),
            _mm256_cmp_ps::<_CMP_UNORD_Q>(b, b),
        );
        let words = _mm256_or_si256(
            _mm256_or_si256(srgb8(r), _mm256_slli_epi32::<8>(srgb8(g))),
            _mm256_slli_epi32::<16>(srgb8(b)),
        );
        let words = _mm256_andnot_si256(_mm256_castps_si256(nan), words);
        // Bytes 0-2 of each word, packed to the front of each 128-bit half, then the two
        // halves' 12 bytes joined.
        #[rustfmt::skip]
        let pick = _mm256_setr_epi8(
            0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, -1, -1, -1, -1,
            0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, -1, -1, -1, -1,
        );
        let packed = _mm256_shuffle_epi8(words, pick);
        let joined = _mm256_permutevar8x32_epi32(packed, _mm256_setr_epi32(0, 1, 2, 4, 5, 6, 3, 7));
        let (lo, hi) = dst.split_at_mut(16);
        // SAFETY: `lo` is 16 bytes and `hi` 8: the stores write exactly those (no alignment
        // requirement).
        unsafe {
            _mm_storeu_si128(lo.as_mut_ptr().cast(), _mm256_castsi256_si128(joined));
            _mm_storel_epi64(
                hi.as_mut_ptr().cast(),
                _mm256_extracti128_si256::<1>(joined),
            );
        }
    }

    /// The planar sRGB 8-bit loop over whole groups of eight pixels: `planes[i]` and `out`
    /// (3 bytes per pixel) hold the same number of pixels. Returns how many pixels it wrote
    /// (a multiple of 8); the caller encodes the rest.
    #[target_feature(enable = "avx2")]
    pub(crate) fn encode_srgb8_planar<const N: usize>(
        weights: &[[f32; N]; 3],
        planes: [&[f32]; N],
        out: &mut [u8],
    ) -> usize {
        let full: [&[[f32; LANES]]; N] = planes.map(|p| p.as_chunks::<LANES>().0);
        let (dst, _) = out.as_chunks_mut::<{ 3 * LANES }>();
        let mut done = 0;
        for (j, dst) in dst.iter_mut().enumerate() {
            let Some(s) = gather_planes(&full, j) else {
                break;
            };
            encode8(products_for_encoding(weights, &s), dst);
            done += LANES;
        }
        done
    }

    /// Group `j` of every plane, or `None` past the shortest plane.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn gather_planes<const N: usize>(full: &[&[[f32; LANES]]; N], j: usize) -> Option<[__m256; N]> {
        let mut s = [_mm256_setzero_ps(); N];
        for (s, plane) in s.iter_mut().zip(full) {
            *s = load(plane.get(j)?);
        }
        Some(s)
    }

    /// The planar linear f32 loop over whole groups of eight pixels; returns how many pixels it
    /// wrote.
    #[target_feature(enable = "avx2")]
    pub(crate) fn linear_planar<const N: usize>(
        weights: &[[f32; N]; 3],
        planes: [&[f32]; N],
        out: [&mut [f32]; 3],
    ) -> usize {
        let full: [&[[f32; LANES]]; N] = planes.map(|p| p.as_chunks::<LANES>().0);
        let [r, g, b] = out;
        let chunks = r
            .as_chunks_mut::<LANES>()
            .0
            .iter_mut()
            .zip(g.as_chunks_mut::<LANES>().0)
            .zip(b.as_chunks_mut::<LANES>().0);
        let mut done = 0;
        for (j, ((r, g), b)) in chunks.enumerate() {
            let Some(s) = gather_planes(&full, j) else {
                break;
            };
            let rgb = products(weights, &s);
            for (o, v) in [r, g, b].into_iter().zip(rgb) {
                // SAFETY: `o` is valid for writing 8 f32; no alignment requirement.
                unsafe { _mm256_storeu_ps(o.as_mut_ptr(), v) };
            }
            done += LANES;
        }
        done
    }

    /// The interleaved (one `[f32; N]` per pixel) sRGB 8-bit loop over whole groups of eight
    /// pixels; returns how many pixels it wrote.
    #[target_feature(enable = "avx2")]
    pub(crate) fn encode_srgb8_batch<const N: usize>(
        weights: &[[f32; N]; 3],
        samples: &[[f32; N]],
        out: &mut [u8],
    ) -> usize {
        let (src, _) = samples.as_chunks::<LANES>();
        let (dst, _) = out.as_chunks_mut::<{ 3 * LANES }>();
        let mut done = 0;
        for (px, dst) in src.iter().zip(dst) {
            // Sample i of the eight pixels in one register.
            let mut s = [_mm256_setzero_ps(); N];
            for (i, s) in s.iter_mut().enumerate() {
                *s = _mm256_setr_ps(
                    px[0][i], px[1][i], px[2][i], px[3][i], px[4][i], px[5][i], px[6][i], px[7][i],
                );
            }
            encode8(products_for_encoding(weights, &s), dst);
            done += LANES;
        }
        done
    }
}

#[cfg(test)]
mod tests {
    //! Every loop against the scalar per-pixel form, forced one by one (the public functions
    //! pick one by the CPU, so on an AVX2 machine they would never run the portable loops on
    //! whole chunks): bit for bit for linear output (NaN against NaN), byte for byte for sRGB.

    use crate::set::{mat_vec, mat_vec_for_encoding};
    use crate::tables::folded::{KQ_C_8_SRGB, TABLE2_ROW1_SRGB, TABLE2_ROW2_SRGB};
    use crate::test_inputs::{Rng, EDGES};
    use crate::GamutMapping;

    /// A sample: mostly reflectance-like, the rest negative, any bit pattern, or an edge.
    fn sample(rng: &mut Rng) -> f32 {
        match rng.next() % 10 {
            0 => -rng.unit(),
            1 => f32::from_bits(rng.next() as u32),
            2 => EDGES[(rng.next() % EDGES.len() as u64) as usize],
            _ => 1.2 * rng.unit(),
        }
    }

    /// The scalar reference: the product of `set::mat_vec_for_encoding` then the scalar
    /// `Display::encode_u8`, as on a target without vector code.
    fn reference<const N: usize>(set: &crate::FoldedSet<N>, s: &[f32; N]) -> [u8; 3] {
        set.display
            .encode_u8(mat_vec_for_encoding(&set.weights, s), GamutMapping::Clip)
    }

    fn same_f32(a: f32, b: f32) -> bool {
        a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
    }

    /// `pixels` random pixels (the edge inputs in every sample position first) through every
    /// loop of `set`.
    fn check<const N: usize>(set: &crate::FoldedSet<N>, pixels: usize, seed: u64) {
        let mut rng = Rng(seed);
        let mut aos: std::vec::Vec<[f32; N]> = std::vec::Vec::with_capacity(pixels);
        for i in 0..pixels {
            let mut s: [f32; N] = core::array::from_fn(|_| sample(&mut rng));
            // Pixels 0..16·N: edge e in position i, the others random.
            if i < EDGES.len() * N {
                s[i % N] = EDGES[i / N];
            }
            aos.push(s);
        }
        let planes: std::vec::Vec<std::vec::Vec<f32>> =
            (0..N).map(|i| aos.iter().map(|s| s[i]).collect()).collect();
        let planes: [&[f32]; N] = core::array::from_fn(|i| &planes[i][..]);
        let want: std::vec::Vec<[u8; 3]> = aos.iter().map(|s| reference(set, s)).collect();
        let want_linear: std::vec::Vec<[f32; 3]> =
            aos.iter().map(|s| mat_vec(&set.weights, s)).collect();

        let compare = |what: &str, got: &[[u8; 3]]| {
            for (p, (g, w)) in got.iter().zip(&want).enumerate() {
                assert_eq!(g, w, "{what}, N = {N}, pixel {p}: {:?}", aos[p]);
            }
        };
        let compare_linear = |what: &str, got: &[std::vec::Vec<f32>; 3]| {
            for (p, w) in want_linear.iter().enumerate().take(got[0].len()) {
                for c in 0..3 {
                    assert!(
                        same_f32(got[c][p], w[c]),
                        "{what}, N = {N}, pixel {p}, channel {c}: {} against {} for {:?}",
                        got[c][p],
                        w[c],
                        aos[p]
                    );
                }
            }
        };

        // The per-pixel function (SSE2 on x86-64).
        let got: std::vec::Vec<[u8; 3]> = aos
            .iter()
            .map(|s| set.encode_u8(GamutMapping::Clip, s))
            .collect();
        compare("encode_u8", &got);

        // The portable planar loops.
        let mut got = std::vec![[0u8; 3]; pixels];
        crate::soa::encode_srgb8_planar_portable(&set.weights, planes, &mut got);
        compare("portable planar", &got);
        let mut lin = [0, 1, 2].map(|_| std::vec![0.0f32; pixels]);
        {
            let [r, g, b] = &mut lin;
            crate::soa::linear_planar_portable(&set.weights, planes, [r, g, b]);
        }
        compare_linear("portable planar linear", &lin);

        // The AVX2 loops, where this CPU has AVX2.
        #[cfg(target_arch = "x86_64")]
        if super::avx2::available() {
            let mut got = std::vec![[0u8; 3]; pixels];
            // SAFETY: the CPU has AVX2.
            let done = unsafe {
                super::avx2::encode_srgb8_planar(&set.weights, planes, got.as_flattened_mut())
            };
            assert_eq!(done, pixels / 8 * 8);
            compare("AVX2 planar", &got[..done]);
            let mut got = std::vec![[0u8; 3]; pixels];
            // SAFETY: the CPU has AVX2.
            let done = unsafe {
                super::avx2::encode_srgb8_batch(&set.weights, &aos, got.as_flattened_mut())
            };
            assert_eq!(done, pixels / 8 * 8);
            compare("AVX2 batch", &got[..done]);
            let mut lin = [0, 1, 2].map(|_| std::vec![0.0f32; pixels]);
            let [r, g, b] = &mut lin;
            // SAFETY: the CPU has AVX2.
            let done = unsafe { super::avx2::linear_planar(&set.weights, planes, [r, g, b]) };
            assert_eq!(done, pixels / 8 * 8);
            let lin = lin.map(|mut c| {
                c.truncate(done);
                c
            });
            compare_linear("AVX2 planar linear", &lin);
        }

        // The public functions, whichever loops they pick.
        let mut got = std::vec![[0u8; 3]; pixels];
        set.encode_u8_planar(GamutMapping::Clip, planes, &mut got)
            .unwrap();
        compare("encode_u8_planar", &got);
        let mut got = std::vec![[0u8; 3]; pixels];
        set.encode_u8_batch(GamutMapping::Clip, &aos, &mut got)
            .unwrap();
        compare("encode_u8_batch", &got);
        let mut lin = [0, 1, 2].map(|_| std::vec![0.0f32; pixels]);
        {
            let [r, g, b] = &mut lin;
            set.linear_rgb_planar(planes, [r, g, b]).unwrap();
        }
        compare_linear("linear_rgb_planar", &lin);
        let mut got16 = std::vec![[0u16; 3]; pixels];
        set.encode_u16_batch(GamutMapping::Clip, &aos, &mut got16)
            .unwrap();
        for (p, (g, s)) in got16.iter().zip(&aos).enumerate() {
            assert_eq!(
                *g,
                set.encode_u16(GamutMapping::Clip, s),
                "u16, N = {N}, {p}"
            );
        }
    }

    /// A set with `N` random weights of either sign, on the sRGB display: the widths the baked
    /// sets do not have (1, 3, 5: the SSE2 product's remainder columns; 16: more weights than
    /// registers).
    fn random_set<const N: usize>(seed: u64) -> crate::FoldedSet<N> {
        let mut rng = Rng(seed);
        crate::FoldedSet {
            wavelengths_nm: core::array::from_fn(|i| 400.0 + i as f32),
            weights: [0, 1, 2].map(|_| core::array::from_fn(|_| 2.0 * rng.unit() - 0.6)),
            samples: TABLE2_ROW2_SRGB.samples,
            display: TABLE2_ROW2_SRGB.display,
        }
    }

    #[test]
    fn every_loop_gives_the_per_pixel_bytes_on_a_million_pixels() {
        // 2²⁰ + 13 pixels: a partial group of 8 and a partial chunk of 16 at the end.
        check(&TABLE2_ROW2_SRGB, (1 << 20) + 13, 1);
        check(&TABLE2_ROW1_SRGB, (1 << 20) + 5, 2);
    }

    #[test]
    fn every_loop_gives_the_per_pixel_bytes_for_other_widths() {
        check(&KQ_C_8_SRGB, 100_003, 3);
        check(&random_set::<1>(4), 100_001, 5);
        check(&random_set::<3>(6), 100_007, 7);
        check(&random_set::<5>(8), 100_009, 9);
        check(&random_set::<16>(10), 100_011, 11);
        // Fewer pixels than one group: the tails alone.
        check(&TABLE2_ROW2_SRGB, 7, 12);
        check(&TABLE2_ROW2_SRGB, 0, 13);
    }
}
