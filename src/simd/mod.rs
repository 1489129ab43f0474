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
//! [`set::mat_vec_for_encoding`](crate::set::mat_vec_for_encoding) (or
//! [`set::mat_vec`](crate::set::mat_vec) for linear output) and encodes with the same table
//! (`encode::SEGMENT_TABLE`) or, in the AVX-512 loops, with a polynomial that agrees with it
//! wherever it does not hand the value back to the table, so all of them give the per-pixel
//! function's bytes, bit for bit. FMA is not used in the products, although every AVX2 CPU of
//! the x86-64 world has it: a fused multiply-add rounds once where the per-pixel function (and
//! every target without FMA, the Cortex-M4F among them) rounds twice, so the outputs would
//! differ in the last bit, and now and then in an encoded code value. (The AVX-512 encoder's
//! polynomial uses FMA: its result is checked, not trusted.)

#[cfg(target_arch = "x86_64")]
pub(crate) mod avx512;

/// Runs an accelerated planar sRGB 8-bit loop, `steps` (whole steps of `unit` pixels from the
/// start of the planes and output it is given; it returns how many pixels it wrote), once at
/// the planes' start and then from [`on_lines`]. Returns how many pixels were written in all:
/// all but fewer than `unit`, or 0 below `unit`. The pixels in between are computed twice, to
/// the same values.
#[cfg(target_arch = "x86_64")]
#[inline]
fn srgb8_from_lines<const N: usize>(
    planes: [&[f32]; N],
    out: &mut [u8],
    unit: usize,
    line: usize,
    mut steps: impl FnMut([&[f32]; N], &mut [u8]) -> usize,
) -> usize {
    let pixels = planes
        .iter()
        .map(|p| p.len())
        .fold(out.len() / 3, usize::min);
    let head = on_lines(&planes, pixels, unit, line);
    if head > 0 {
        steps(planes.map(|p| &p[..unit]), &mut out[..3 * unit]);
    }
    head + steps(planes.map(|p| &p[head..]), &mut out[3 * head..])
}

/// As [`srgb8_from_lines`], for a planar linear loop: `steps`' last argument is whether it
/// runs the step at the planes' start (which is not worth streaming).
#[cfg(target_arch = "x86_64")]
#[inline]
fn linear_from_lines<const N: usize>(
    planes: [&[f32]; N],
    out: [&mut [f32]; 3],
    unit: usize,
    line: usize,
    mut steps: impl FnMut([&[f32]; N], [&mut [f32]; 3], bool) -> usize,
) -> usize {
    let pixels = planes
        .iter()
        .map(|p| p.len())
        .fold(out.iter().map(|o| o.len()).min().unwrap_or(0), usize::min);
    let head = on_lines(&planes, pixels, unit, line);
    let [r, g, b] = out;
    if head > 0 {
        let first = [&mut r[..unit], &mut g[..unit], &mut b[..unit]];
        steps(planes.map(|p| &p[..unit]), first, true);
    }
    let rest = [&mut r[head..], &mut g[head..], &mut b[head..]];
    head + steps(planes.map(|p| &p[head..]), rest, false)
}

/// Where an accelerated planar loop starts its steps of `unit` pixels: the pixel from which
/// the most planes start a `line`-byte boundary (0, or the first such pixel in plane order,
/// where several tie), where that is below `unit` and `pixels` holds a step after it; else 0.
///
/// A 64-byte line of a plane read from such a boundary is read by one group of pixels, not
/// two. On the CPU measured (AMD Zen 4), planes of 2²⁵ pixels in separate allocations (which
/// start 16 bytes past a page with glibc and lie 128 MiB apart) took 39.1 ms in the AVX-512
/// planar sRGB loop at N = 4 read from a boundary against 47.2 ms read from their start,
/// while the streaming bound did not change (`soa/srgb_u8_aligned` in the bench, before the
/// loops started on a line; the commit that added that case has the run). Starting on a line
/// took the loop at N = 4 from 47.5 to 39.9 ms, and at N = 16 from 178.7 to 118.3 ms (README,
/// Performance).
#[cfg(target_arch = "x86_64")]
#[inline]
fn on_lines<const N: usize>(
    planes: &[&[f32]; N],
    pixels: usize,
    unit: usize,
    line: usize,
) -> usize {
    // Pixels to each plane's first boundary (f32 are 4-byte aligned: 0..line / 4).
    let to_line = planes.map(|p| p.as_ptr().align_offset(line));
    let votes = |h: usize| to_line.iter().filter(|&&t| t == h).count();
    let head = to_line
        .iter()
        .copied()
        .fold(0, |best, h| if votes(h) > votes(best) { h } else { best });
    if head < unit && pixels >= head + unit {
        head
    } else {
        0
    }
}

/// The accelerated planar sRGB 8-bit loop, where the CPU has one: encodes the first pixels
/// of `planes` into `out` (3 bytes per pixel), all but fewer than one of its groups (8 or 16
/// pixels), and returns how many; 0 where there is no accelerated loop, so the caller's
/// portable loop does everything.
#[inline]
pub(crate) fn encode_srgb8_planar<const N: usize>(
    weights: &[[f32; N]; 3],
    planes: [&[f32]; N],
    out: &mut [u8],
) -> usize {
    #[cfg(target_arch = "x86_64")]
    {
        if avx512::available() {
            // SAFETY: the CPU has the AVX-512 subsets the loop needs (checked just above).
            return unsafe { avx512::encode_srgb8_planar(weights, planes, out) };
        }
        if avx2::available() {
            // SAFETY: the CPU has AVX2 (checked just above).
            return unsafe { avx2::encode_srgb8_planar(weights, planes, out) };
        }
    }
    let _ = (weights, planes, out);
    0
}

/// As [`encode_srgb8_planar`], for linear f32 output (three planes); the accelerated loop
/// writes all but fewer than 16 pixels.
#[inline]
pub(crate) fn linear_planar<const N: usize>(
    weights: &[[f32; N]; 3],
    planes: [&[f32]; N],
    out: [&mut [f32]; 3],
) -> usize {
    #[cfg(target_arch = "x86_64")]
    {
        let stream = out.iter().map(|o| o.len()).min().unwrap_or(0) >= STREAM_MIN_PIXELS;
        if avx512::available() {
            // SAFETY: the CPU has the AVX-512 subsets the loop needs (checked just above).
            return unsafe { avx512::linear_planar(weights, planes, out, stream) };
        }
        if avx2::available() {
            // SAFETY: the CPU has AVX2 (checked just above).
            return unsafe { avx2::linear_planar(weights, planes, out, stream) };
        }
    }
    let _ = (weights, planes, out);
    0
}

/// From this many pixels on, the accelerated planar linear loops write their output with
/// non-temporal stores: the AVX-512 loop at every width (see [`avx512::linear_planar`]), the
/// AVX2 loop above four planes (see [`avx2::linear_planar`]). 2²⁰ pixels are 12 MiB of output,
/// more than a core's share of the last-level cache on common x86-64 CPUs, so the output would
/// leave the caches before it is read again anyway. Smaller calls (a row, a tile) write through
/// the caches, where the caller reads them next.
#[cfg(target_arch = "x86_64")]
pub(crate) const STREAM_MIN_PIXELS: usize = 1 << 20;

/// As [`encode_srgb8_planar`], for interleaved samples (one `[f32; N]` per pixel).
#[inline]
pub(crate) fn encode_srgb8_batch<const N: usize>(
    weights: &[[f32; N]; 3],
    samples: &[[f32; N]],
    out: &mut [u8],
) -> usize {
    #[cfg(target_arch = "x86_64")]
    {
        if avx512::available() && avx512::BATCH_WIDTHS.contains(&N) {
            // SAFETY: the CPU has the AVX-512 subsets the loop needs (checked just above).
            return unsafe { avx512::encode_srgb8_batch(weights, samples, out) };
        }
        if avx2::available() {
            // SAFETY: the CPU has AVX2 (checked just above).
            return unsafe { avx2::encode_srgb8_batch(weights, samples, out) };
        }
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

    /// How far ahead of the group being computed the loops over planes ask for the samples,
    /// in groups of [`LANES`] pixels (256 bytes per plane). The hardware prefetchers keep up
    /// with one stream, but a loop that reads four to sixteen planes and does work between
    /// the loads waited for memory on the CPU measured (AMD Zen 3): the README's Performance
    /// section has what this changed. 16 and 32 groups measured no better than 8.
    const PREFETCH_GROUPS: usize = 8;

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

    /// Asks for the cache line at `p` ahead of its use. A hint: any address is allowed, and
    /// nothing is read from it here.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn prefetch<T>(p: *const T) {
        _mm_prefetch::<_MM_HINT_T0>(p.cast());
    }

    /// `weights · samples` for eight pixels (one per lane), channel c as `start[c]` plus the
    /// products `weights[c][i] · s[i]` added in index order; with `start` `None`, each channel
    /// from its first product with the rest added in index order: `set::mat_vec_for_encoding`,
    /// lane by lane (and, from `Some` of zeros, `set::mat_vec`).
    #[inline]
    #[target_feature(enable = "avx2")]
    fn add_products<const N: usize>(
        weights: &[[f32; N]; 3],
        s: &[__m256; N],
        start: Option<[__m256; 3]>,
    ) -> [__m256; 3] {
        // Plain loops, no closures: a closure is compiled without the enclosing function's
        // target features, and its calls would not be inlined.
        let mut out = [_mm256_setzero_ps(); 3];
        for (c, (acc, row)) in out.iter_mut().zip(weights).enumerate() {
            for (i, (w, s)) in row.iter().zip(s).enumerate() {
                let p = _mm256_mul_ps(_mm256_set1_ps(*w), *s);
                *acc = match (i, start) {
                    (0, None) => p,
                    (0, Some(start)) => _mm256_add_ps(start[c], p),
                    _ => _mm256_add_ps(*acc, p),
                };
            }
        }
        out
    }

    // --- The sRGB 8-bit loop ------------------------------------------------------------------
    //
    // Each group of eight pixels passes three stages:
    //
    // 1. vector: the 3×N product, the NaN rule and the clamp of `encode::segment_bits`; the
    //    clamped values' bits go to the group's slot;
    // 2. scalar: the table entry of each of the 24 values (`encode::SEGMENT_TABLE`, indexed by
    //    the top 16 bits), a load each, into the slot;
    // 3. vector: the code values, the top byte of entry + bits · 2⁸ (see `encode::FIRST_TOP`),
    //    interleaved into 24 bytes.
    //
    // A step of the loop runs stage 1 of group j, stage 2 of group j − 1 and stage 3 of group
    // j − 2, so that the table loads, which run on the load and integer units, overlap the
    // vector work of the other two groups. Moving the indices and entries through vector
    // registers instead (`vpextrq`, `vpinsrd`, the loop this one replaced) kept the vector
    // units busy with shuffles, and `vpgatherdd` issues its eight loads more slowly than
    // scalar loads on the CPU measured (AMD Zen 3); the README's Performance section lists
    // what else was measured.

    /// Groups in flight between the stages: slots for groups j, j − 1 and j − 2, rounded up to a
    /// power of two so that the slot of group j is `j % RING`.
    const RING: usize = 4;

    /// One group's 24 values (channel by channel, eight lanes each) as the stages pass them on.
    #[repr(C, align(32))]
    #[derive(Clone, Copy)]
    struct Slot {
        /// The bits of the clamped values (stage 1).
        bits: [u32; 3 * LANES],
        /// Their table entries (stage 2), two to a word: value 2k in the low half of word k.
        entries: [u64; 3 * LANES / 2],
    }

    impl Slot {
        const ZERO: Slot = Slot {
            bits: [0; 3 * LANES],
            entries: [0; 3 * LANES / 2],
        };
    }

    /// Stage 1: the channels of eight pixels, clamped to `LO..=1` as `encode::segment_bits`
    /// clamps them (NaN → `LO`), with every channel of a pixel that has a NaN channel set to
    /// `LO` first (code 0: the pixel is black, the NaN rule of the per-pixel function).
    #[inline]
    #[target_feature(enable = "avx2")]
    fn clamp_into(rgb: [__m256; 3], slot: &mut Slot) {
        let [r, g, b] = rgb;
        // Unordered compares: true where either operand is NaN.
        let nan = _mm256_or_ps(
            _mm256_cmp_ps::<_CMP_UNORD_Q>(r, g),
            _mm256_cmp_ps::<_CMP_UNORD_Q>(b, b),
        );
        let (dst, _) = slot.bits.as_chunks_mut::<LANES>();
        for (d, x) in dst.iter_mut().zip(rgb) {
            // +0.0 in every channel of a NaN pixel; then max(x, LO), which is LO for 0.0.
            let x = _mm256_andnot_ps(nan, x);
            let c = _mm256_min_ps(_mm256_max_ps(x, _mm256_set1_ps(LO)), _mm256_set1_ps(1.0));
            // SAFETY: `d` is valid for writing 8 u32; no alignment requirement.
            unsafe { _mm256_storeu_si256(d.as_mut_ptr().cast(), _mm256_castps_si256(c)) };
        }
    }

    /// Stage 2: the table entry of each clamped value, one scalar load each. The reads and
    /// writes are volatile: the compiler otherwise sees through stage 1's stores and moves the
    /// values through vector registers again (`vpextrq`, `vpinsrd`), which is what these stages
    /// avoid.
    #[inline(always)]
    fn look_up(slot: &mut Slot) {
        let bits = slot.bits.as_ptr().cast::<u16>();
        for (k, e) in slot.entries.iter_mut().enumerate() {
            // SAFETY: u16 2·(2k) + 1 and 2·(2k + 1) + 1 lie inside `bits` (2 · 24 u16 for
            // k < 12): the upper halves of values 2k and 2k + 1, their top 16 bits on a
            // little-endian CPU (x86-64 is). Stage 1 clamped every value to `LO..=1`, so each
            // top lies in `FIRST_TOP..=LAST_TOP`, as `entry_at_top` requires.
            let (lo, hi) = unsafe {
                let lo = core::ptr::read_volatile(bits.add(4 * k + 1));
                let hi = core::ptr::read_volatile(bits.add(4 * k + 3));
                (entry_at_top(u32::from(lo)), entry_at_top(u32::from(hi)))
            };
            // SAFETY: `e` is a valid, aligned u64.
            unsafe { core::ptr::write_volatile(e, u64::from(lo) | u64::from(hi) << 32) };
        }
    }

    /// Stage 3: the code values of a slot, interleaved into 24 bytes `r, g, b, r, …`. With
    /// `even_odd` (a constant where it is inlined) the slot's lanes hold pixels 0, 2, 4, 6, 1,
    /// 3, 5, 7 (see [`transpose_even_odd`]) and are put back in order first.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn codes_into(slot: &Slot, even_odd: bool, dst: &mut [u8; 3 * LANES]) {
        let (bits, _) = slot.bits.as_chunks::<LANES>();
        let entries = slot.entries.as_ptr().cast::<u32>();
        // Channel c's code values, shifted to byte c of each word. A loop, not a closure: a
        // closure is compiled without this function's target features.
        let mut words = _mm256_setzero_si256();
        for (c, bits) in bits.iter().enumerate() {
            // SAFETY: `bits` is valid for reading 8 u32, and so is `entries` (24 u32, in the
            // order of `bits`) at channel c's offset; no alignment requirement.
            let (b, e) = unsafe {
                (
                    _mm256_loadu_si256(bits.as_ptr().cast()),
                    _mm256_loadu_si256(entries.add(LANES * c).cast()),
                )
            };
            // `bits << 8` is `(bits − LO_BITS) << 8`: see `encode::FIRST_TOP`.
            let code = _mm256_srli_epi32::<24>(_mm256_add_epi32(e, _mm256_slli_epi32::<8>(b)));
            let code = match c {
                0 => code,
                1 => _mm256_slli_epi32::<8>(code),
                _ => _mm256_slli_epi32::<16>(code),
            };
            words = _mm256_or_si256(words, code);
        }
        if even_odd {
            words = _mm256_permutevar8x32_epi32(words, _mm256_setr_epi32(0, 4, 1, 5, 2, 6, 3, 7));
        }
        store_rgb8(words, dst);
    }

    /// Eight words `r | g << 8 | b << 16` → 24 bytes: bytes 0-2 of each word, packed to the
    /// front of each 128-bit half, then the two halves' 12 bytes joined.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn store_rgb8(words: __m256i, dst: &mut [u8; 3 * LANES]) {
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

    /// Group `$j` of `$planes` (`[&[[f32; LANES]]; N]`, every plane longer than `$j`), sample i
    /// of the eight pixels in register i, with the samples of group `$j + PREFETCH_GROUPS`
    /// asked for. A macro, so that it is inlined at every width (a function with target
    /// features may not be `#[inline(always)]`, and at N = 8 and 16 the compiler called it).
    macro_rules! plane_group {
        ($planes:expr, $j:expr) => {{
            let (planes, j) = (&$planes, $j);
            if j % 2 == 0 {
                // One 64-byte line per plane every two groups.
                for p in planes {
                    prefetch(p.as_ptr().wrapping_add(j + PREFETCH_GROUPS));
                }
            }
            let mut s = [_mm256_setzero_ps(); N];
            for (s, p) in s.iter_mut().zip(planes) {
                debug_assert!(j < p.len());
                // SAFETY: every caller passes a `$j` below the length of every plane (the
                // number of groups it loops over is the minimum of those lengths).
                *s = load(unsafe { p.get_unchecked(j) });
            }
            s
        }};
    }

    /// Sample i of eight pixels in register i (lane k: pixel k): four at a time by
    /// [`transpose4`], the last N mod 4 one by one.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn transpose<const N: usize>(px: &[[f32; N]; LANES]) -> [__m256; N] {
        let mut s = [_mm256_setzero_ps(); N];
        if N == 4 {
            s.copy_from_slice(&transpose_even_odd(px.as_flattened()));
            return s;
        }
        for b in 0..N / 4 {
            s[4 * b..4 * b + 4].copy_from_slice(&transpose4(px, 4 * b));
        }
        for (i, s) in s.iter_mut().enumerate().skip(N / 4 * 4) {
            *s = _mm256_setr_ps(
                px[0][i], px[1][i], px[2][i], px[3][i], px[4][i], px[5][i], px[6][i], px[7][i],
            );
        }
        s
    }

    /// The four samples of eight pixels of four samples each (`px`: 32 f32, pixel by pixel),
    /// one register per sample with the pixels in lanes 0, 2, 4, 6, 1, 3, 5, 7: pixels 2k and
    /// 2k + 1 in one 32-byte load, then 4 × 4 transposes within each 128-bit half. Four loads
    /// and eight shuffles where [`transpose4`] takes eight loads and eight inserts besides;
    /// stage 3 puts the pixels back in order ([`codes_into`] with `even_odd`).
    #[inline]
    #[target_feature(enable = "avx2")]
    fn transpose_even_odd(px: &[f32]) -> [__m256; 4] {
        let (pairs, _) = px.as_chunks::<{ 2 * 4 }>();
        let mut rows = [_mm256_setzero_ps(); 4];
        for (row, pair) in rows.iter_mut().zip(pairs) {
            *row = load(pair);
        }
        // Low halves hold pixels 0, 2, 4, 6; high halves 1, 3, 5, 7.
        transpose_halves(rows)
    }

    /// Samples `i..i + 4` of eight pixels, one register per sample (lane k: pixel k): the
    /// pixels' four values loaded two rows to a register (pixel k in the low half, k + 4 in
    /// the high) and transposed 4 × 4 within each half. Eight loads and eight shuffles where
    /// inserting lane by lane takes 32 of each. `i + 4 ≤ N`.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn transpose4<const N: usize>(px: &[[f32; N]; LANES], i: usize) -> [__m256; 4] {
        let mut rows = [_mm256_setzero_ps(); 4];
        for (k, row) in rows.iter_mut().enumerate() {
            let (lo, hi) = (&px[k][i..i + 4], &px[k + 4][i..i + 4]);
            // SAFETY: `lo` and `hi` are valid for reading 4 f32 each; no alignment requirement.
            *row = unsafe { _mm256_loadu2_m128(hi.as_ptr(), lo.as_ptr()) };
        }
        transpose_halves(rows)
    }

    /// A 4 × 4 transpose within each 128-bit half: value k of row i (in its half) becomes
    /// value i of row k, in both halves at once. Eight shuffles.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn transpose_halves(rows: [__m256; 4]) -> [__m256; 4] {
        let [r0, r1, r2, r3] = rows;
        let (t0, t1) = (_mm256_unpacklo_ps(r0, r1), _mm256_unpackhi_ps(r0, r1));
        let (t2, t3) = (_mm256_unpacklo_ps(r2, r3), _mm256_unpackhi_ps(r2, r3));
        // Per half: t0 = [a0 b0 a1 b1], t2 = [c0 d0 c1 d1] → [a0 b0 c0 d0] and [a1 b1 c1 d1].
        let pd = _mm256_castps_pd;
        [
            _mm256_castpd_ps(_mm256_unpacklo_pd(pd(t0), pd(t2))),
            _mm256_castpd_ps(_mm256_unpackhi_pd(pd(t0), pd(t2))),
            _mm256_castpd_ps(_mm256_unpacklo_pd(pd(t1), pd(t3))),
            _mm256_castpd_ps(_mm256_unpackhi_pd(pd(t1), pd(t3))),
        ]
    }

    /// The three-stage sRGB 8-bit loop over groups `0..groups` into `dst` (24 bytes per group,
    /// at least `groups` of them), with group j's three channels from `$products` (`j` bound to
    /// the group, written as a closure but substituted, so that no closure is called). It writes
    /// every whole group, even one alone, since a step runs only the stages whose group
    /// exists. A macro, so that each source's loads are
    /// inlined into the loop: functions with target features may not be `#[inline(always)]`,
    /// and the compiler did not inline a shared function that took the source as a parameter.
    macro_rules! encode_srgb8 {
        ($groups:expr, $dst:expr, $even_odd:expr, |$j:ident| $products:expr) => {{
            let (groups, dst) = ($groups, $dst);
            let mut ring = [Slot::ZERO; RING];
            // Step j: stage 1 of group j, stage 2 of group j − 1, stage 3 of group j − 2,
            // each where that group exists. One step per iteration, slot indices computed:
            // unrolled by RING with constant slots, the loop was no faster in cache and
            // slower from memory on the CPU measured (AMD Zen 3; the commit that made this
            // change has the figures).
            for j in 0..groups + 2 {
                if j < groups {
                    let $j = j;
                    clamp_into($products, &mut ring[j % RING]);
                }
                if (1..=groups).contains(&j) {
                    look_up(&mut ring[(j - 1) % RING]);
                }
                if j >= 2 {
                    codes_into(&ring[(j - 2) % RING], $even_odd, &mut dst[j - 2]);
                }
            }
        }};
    }

    /// `$f::<K>($args)` with K the number of planes of the last pass, `$k` (1 to 4), as a
    /// constant: the last pass's arrays are K wide.
    macro_rules! with_last_pass {
        ($k:expr, $f:ident($($arg:expr),*)) => {
            match $k {
                1 => $f::<1>($($arg),*),
                2 => $f::<2>($($arg),*),
                3 => $f::<3>($($arg),*),
                _ => $f::<4>($($arg),*),
            }
        };
    }

    /// The planar sRGB 8-bit loop: `planes[i]` and `out` (3 bytes per pixel). Returns how
    /// many pixels it wrote (8 or more, or 0 below 8); the caller encodes the rest. Its groups
    /// start where most planes start a 32-byte boundary ([`on_lines`](super::on_lines)), so
    /// that no group's samples straddle two 64-byte lines, after one group at the planes'
    /// start.
    #[target_feature(enable = "avx2")]
    pub(crate) fn encode_srgb8_planar<const N: usize>(
        weights: &[[f32; N]; 3],
        planes: [&[f32]; N],
        out: &mut [u8],
    ) -> usize {
        super::srgb8_from_lines(planes, out, LANES, 32, |planes, out| {
            encode_srgb8_groups(weights, planes, out)
        })
    }

    /// [`encode_srgb8_planar`] over whole groups of eight pixels from the planes' start;
    /// returns how many pixels it wrote (a multiple of 8). Above [`PASS_PLANES`] planes, in
    /// passes (see there).
    #[target_feature(enable = "avx2")]
    fn encode_srgb8_groups<const N: usize>(
        weights: &[[f32; N]; 3],
        planes: [&[f32]; N],
        out: &mut [u8],
    ) -> usize {
        let planes: [&[[f32; LANES]]; N] = planes.map(|p| p.as_chunks::<LANES>().0);
        let (dst, _) = out.as_chunks_mut::<{ 3 * LANES }>();
        let groups = planes.iter().map(|p| p.len()).fold(dst.len(), usize::min);
        let dst = &mut dst[..groups];
        if N <= PASS_PLANES {
            encode_srgb8!(groups, dst, false, |j| add_products(
                weights,
                &plane_group!(planes, j),
                None
            ));
            return groups * LANES;
        }
        let mut sums = Sums::ZERO;
        for (b, dst) in dst.chunks_mut(BLOCK_GROUPS).enumerate() {
            let first = b * BLOCK_GROUPS;
            add_passes(
                weights,
                &planes,
                first,
                dst.len(),
                Start::FirstProduct,
                &mut sums,
            );
            let last = last_pass_from::<N>();
            with_last_pass!(
                N - last,
                encode_srgb8_last_pass(
                    &columns(weights, last),
                    &sub(&planes, last),
                    first,
                    &sums,
                    dst
                )
            );
        }
        groups * LANES
    }

    /// The last pass of a block of the planar sRGB 8-bit loop: group j of `dst` from the
    /// block's partial sums plus the products of the last planes (`planes`, with their
    /// `weights`) for group `first + j`, through the three stages.
    #[target_feature(enable = "avx2")]
    fn encode_srgb8_last_pass<const N: usize>(
        weights: &[[f32; N]; 3],
        planes: &[&[[f32; LANES]]; N],
        first: usize,
        sums: &Sums,
        dst: &mut [[u8; 3 * LANES]],
    ) {
        encode_srgb8!(dst.len(), dst, false, |j| add_products(
            weights,
            &plane_group!(*planes, first + j),
            Some(sums.get(j))
        ));
    }

    /// The interleaved (one `[f32; N]` per pixel) sRGB 8-bit loop over whole groups of eight
    /// pixels; returns how many pixels it wrote.
    #[target_feature(enable = "avx2")]
    pub(crate) fn encode_srgb8_batch<const N: usize>(
        weights: &[[f32; N]; 3],
        samples: &[[f32; N]],
        out: &mut [u8],
    ) -> usize {
        let (pixels, _) = samples.as_chunks::<LANES>();
        let (dst, _) = out.as_chunks_mut::<{ 3 * LANES }>();
        let groups = pixels.len().min(dst.len());
        let (pixels, dst) = (&pixels[..groups], &mut dst[..groups]);
        encode_srgb8!(groups, dst, N == 4, |j| add_products(
            weights,
            &transpose(&pixels[j]),
            None
        ));
        groups * LANES
    }

    // --- Planes in passes ---------------------------------------------------------------------
    //
    // With more than `PASS_PLANES` planes, the planar loops go through the pixels in blocks of
    // `BLOCK_GROUPS` groups, and through each block's planes four at a time: each pass but the
    // last adds four planes' products to the block's partial sums, held on the stack (in the
    // first-level cache); the last pass adds the last one to four planes' products and encodes
    // the block or writes it out. Each sum still takes its products in index order, rounded
    // as in one pass (an f32 stored and loaded back is unchanged), so the bits are those of the
    // one-pass loop. The loops then read four input streams at a time instead of N, which on
    // the CPU measured (AMD Zen 3) was faster from eight planes up for both loops, and at six
    // for linear output; the sRGB loop at six lost a few per cent (the README's Performance
    // section has the figures).

    /// Planes per pass: at most this many input streams are read at a time.
    const PASS_PLANES: usize = 4;

    /// Groups per block: 1024 pixels, 4 KiB of each plane, 12 KiB of partial sums.
    pub(crate) const BLOCK_GROUPS: usize = 128;

    /// A block's partial sums: channel by channel, eight lanes per group.
    struct Sums([[[f32; LANES]; BLOCK_GROUPS]; 3]);

    impl Sums {
        const ZERO: Sums = Sums([[[0.0; LANES]; BLOCK_GROUPS]; 3]);

        /// Group j's three partial sums.
        #[inline]
        #[target_feature(enable = "avx2")]
        fn get(&self, j: usize) -> [__m256; 3] {
            [
                load(&self.0[0][j]),
                load(&self.0[1][j]),
                load(&self.0[2][j]),
            ]
        }

        /// Sets group j's three partial sums.
        #[inline]
        #[target_feature(enable = "avx2")]
        fn set(&mut self, j: usize, v: [__m256; 3]) {
            for (s, v) in self.0.iter_mut().zip(v) {
                // SAFETY: `s[j]` is valid for writing 8 f32; no alignment requirement.
                unsafe { _mm256_storeu_ps(s[j].as_mut_ptr(), v) };
            }
        }
    }

    /// The first plane of the last pass: the passes before it take four planes each, the last
    /// one to four.
    const fn last_pass_from<const N: usize>() -> usize {
        N.saturating_sub(1) / PASS_PLANES * PASS_PLANES
    }

    /// Columns `from..from + K` of `weights`.
    #[inline]
    fn columns<const N: usize, const K: usize>(
        weights: &[[f32; N]; 3],
        from: usize,
    ) -> [[f32; K]; 3] {
        core::array::from_fn(|c| core::array::from_fn(|i| weights[c][from + i]))
    }

    /// Planes `from..from + K`.
    #[inline]
    fn sub<'a, T, const N: usize, const K: usize>(
        planes: &[&'a [T]; N],
        from: usize,
    ) -> [&'a [T]; K] {
        core::array::from_fn(|i| planes[from + i])
    }

    /// Every pass of a block but the last: groups `first..first + groups` of the planes before
    /// [`last_pass_from`] into `sums` (group `first + j` at j), four planes at a time, the first
    /// pass from `start`.
    #[target_feature(enable = "avx2")]
    fn add_passes<const N: usize>(
        weights: &[[f32; N]; 3],
        planes: &[&[[f32; LANES]]; N],
        first: usize,
        groups: usize,
        start: Start,
        sums: &mut Sums,
    ) {
        for from in (0..last_pass_from::<N>()).step_by(PASS_PLANES) {
            let start = if from > 0 { Start::Sums } else { start };
            add_pass::<PASS_PLANES>(
                &columns(weights, from),
                &sub(planes, from),
                first,
                groups,
                start,
                sums,
            );
        }
    }

    /// Where a pass's sums start.
    #[derive(Clone, Copy)]
    enum Start {
        /// From 0.0 (`set::mat_vec`).
        Zero,
        /// From the first product (`set::mat_vec_for_encoding`).
        FirstProduct,
        /// From the block's partial sums.
        Sums,
    }

    /// One pass of [`add_passes`]: the products of `planes` (with their `weights`) for groups
    /// `first..first + groups`, added to `start`, into `sums`.
    #[target_feature(enable = "avx2")]
    fn add_pass<const N: usize>(
        weights: &[[f32; N]; 3],
        planes: &[&[[f32; LANES]]; N],
        first: usize,
        groups: usize,
        start: Start,
        sums: &mut Sums,
    ) {
        for j in 0..groups {
            let s = plane_group!(*planes, first + j);
            let start = match start {
                Start::Zero => Some([_mm256_setzero_ps(); 3]),
                Start::FirstProduct => None,
                Start::Sums => Some(sums.get(j)),
            };
            let v = add_products(weights, &s, start);
            sums.set(j, v);
        }
    }

    /// The planar linear f32 loop in pairs of groups (16 pixels). Above [`PASS_PLANES`]
    /// planes, in passes (see there).
    ///
    /// With `stream` and above [`PASS_PLANES`] planes, the last pass too adds into the block's
    /// sums, which are then copied to the three output planes one after the other with
    /// non-temporal stores (`vmovntps`, [`stream_out`]). These write whole lines without first
    /// reading them from memory, as ordinary stores do: at N = 8 that read is 12 of the 56
    /// bytes per pixel that cross the memory bus. On the CPU measured (AMD Zen 3) this was
    /// faster from memory at N = 6, 8 and 16; at N = 4, where one pass writes the output
    /// directly, the extra copy made it slower, and copying the sums plane by plane with
    /// ordinary stores was slower than the last pass's direct stores (README, Performance).
    /// The output is then not in the caches, hence the caller's threshold.
    ///
    /// Its pairs of groups start where most planes start a 32-byte boundary
    /// ([`on_lines`](super::on_lines)), after one pair at the planes' start. Returns how many
    /// pixels it wrote (16 or more, or 0 below 16).
    #[target_feature(enable = "avx2")]
    pub(crate) fn linear_planar<const N: usize>(
        weights: &[[f32; N]; 3],
        planes: [&[f32]; N],
        out: [&mut [f32]; 3],
        stream: bool,
    ) -> usize {
        super::linear_from_lines(planes, out, 2 * LANES, 32, |planes, out, first| {
            linear_pairs(weights, planes, out, stream && !first)
        })
    }

    /// [`linear_planar`] over whole pairs of groups of eight pixels from the planes' start;
    /// returns how many pixels it wrote (a multiple of 16).
    #[target_feature(enable = "avx2")]
    fn linear_pairs<const N: usize>(
        weights: &[[f32; N]; 3],
        planes: [&[f32]; N],
        out: [&mut [f32]; 3],
        stream: bool,
    ) -> usize {
        let planes: [&[[f32; LANES]]; N] = planes.map(|p| p.as_chunks::<LANES>().0);
        let out = out.map(|o| o.as_chunks_mut::<{ 2 * LANES }>().0);
        let pairs = planes.iter().map(|p| p.len()).min().unwrap_or(0) / 2;
        let pairs = out.iter().map(|o| o.len()).fold(pairs, usize::min);
        let [r, g, b] = out;
        let (r, g, b) = (&mut r[..pairs], &mut g[..pairs], &mut b[..pairs]);
        if N <= PASS_PLANES {
            linear_last_pass(weights, &planes, 0, None, [r, g, b]);
            return pairs * 2 * LANES;
        }
        let mut sums = Sums::ZERO;
        let block = BLOCK_GROUPS / 2;
        let blocks = r
            .chunks_mut(block)
            .zip(g.chunks_mut(block))
            .zip(b.chunks_mut(block));
        let last = last_pass_from::<N>();
        for (k, ((r, g), b)) in blocks.enumerate() {
            let (first, groups) = (2 * k * block, 2 * r.len());
            add_passes(weights, &planes, first, groups, Start::Zero, &mut sums);
            if stream {
                with_last_pass!(
                    N - last,
                    add_pass(
                        &columns(weights, last),
                        &sub(&planes, last),
                        first,
                        groups,
                        Start::Sums,
                        &mut sums
                    )
                );
                for (c, o) in [r, g, b].into_iter().enumerate() {
                    stream_out(sums.0[c][..groups].as_flattened(), o.as_flattened_mut());
                }
            } else {
                with_last_pass!(
                    N - last,
                    linear_last_pass(
                        &columns(weights, last),
                        &sub(&planes, last),
                        first,
                        Some(&sums),
                        [r, g, b]
                    )
                );
            }
        }
        if stream {
            // Non-temporal stores are weakly ordered: this orders them before every store that
            // follows, as ordinary stores are (another thread that synchronizes with this one
            // afterwards sees the output).
            _mm_sfence();
        }
        pairs * 2 * LANES
    }

    /// `dst.copy_from_slice(src)` (equal lengths), with non-temporal stores from the first
    /// 32-byte boundary of `dst` to the last; the floats before and after it with ordinary
    /// stores.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn stream_out(src: &[f32], dst: &mut [f32]) {
        debug_assert_eq!(src.len(), dst.len());
        // Floats before the first 32-byte boundary (f32 are 4-byte aligned, so this is exact).
        let head = dst.as_ptr().align_offset(32).min(dst.len());
        let (dst_head, dst_rest) = dst.split_at_mut(head);
        let (src_head, src_rest) = src.split_at(head);
        dst_head.copy_from_slice(src_head);
        let (dst_body, dst_tail) = dst_rest.as_chunks_mut::<LANES>();
        let (src_body, src_tail) = src_rest.as_chunks::<LANES>();
        for (d, s) in dst_body.iter_mut().zip(src_body) {
            // SAFETY: `d` is valid for writing 8 f32 and 32-byte aligned: it starts `head`
            // floats into `dst`, at its first 32-byte boundary, plus a multiple of 32 bytes.
            unsafe { _mm256_stream_ps(d.as_mut_ptr(), load(s)) };
        }
        dst_tail.copy_from_slice(src_tail);
    }

    /// The planar linear loop's last pass (its only one up to [`PASS_PLANES`] planes): pair k
    /// of `out` (16 pixels of each channel) from `sums` (pair k's groups, 2k and 2k + 1), or
    /// from 0.0 without, plus the products of `planes` (with their `weights`) for groups
    /// `first + 2k` and `first + 2k + 1`.
    ///
    /// Each step writes 64 bytes to the red plane, then 64 to green, then 64 to blue, a cache
    /// line's worth at a time, rather than eight pixels of each plane in turn, which filled
    /// every output line in two visits and was slower from memory on the CPU measured (AMD
    /// Zen 3; the README's Performance section has the figures).
    #[target_feature(enable = "avx2")]
    fn linear_last_pass<const N: usize>(
        weights: &[[f32; N]; 3],
        planes: &[&[[f32; LANES]]; N],
        first: usize,
        sums: Option<&Sums>,
        out: [&mut [[f32; 2 * LANES]]; 3],
    ) {
        let [r, g, b] = out;
        for (k, ((r, g), b)) in r.iter_mut().zip(g.iter_mut()).zip(b.iter_mut()).enumerate() {
            let j = first + 2 * k;
            // Both halves of each plane's 64-byte line together, plane after plane: planes that
            // lie 128 MiB and 4 KiB apart (consecutive allocations of 2²⁵ f32) are read more
            // slowly on the CPU measured (AMD Zen 3; README, Performance), and reading each
            // line at once measured faster there from N = 8 up than reading all planes' first
            // halves, then all second halves.
            let mut s = [[_mm256_setzero_ps(); N]; 2];
            for (i, p) in planes.iter().enumerate() {
                prefetch(p.as_ptr().wrapping_add(j + PREFETCH_GROUPS));
                debug_assert!(j + 1 < p.len());
                // SAFETY: the callers give `out` no more pairs than every plane has from group
                // `first` on, so j + 1 = first + 2k + 1 is below every plane's length.
                let (a, b) = unsafe { (p.get_unchecked(j), p.get_unchecked(j + 1)) };
                s[0][i] = load(a);
                s[1][i] = load(b);
            }
            let mut halves = [[_mm256_setzero_ps(); 3]; 2];
            for (h, (half, s)) in halves.iter_mut().zip(&s).enumerate() {
                let start = match sums {
                    Some(sums) => sums.get(2 * k + h),
                    None => [_mm256_setzero_ps(); 3],
                };
                *half = add_products(weights, s, Some(start));
            }
            for (c, o) in [r, g, b].into_iter().enumerate() {
                for (h, half) in o.as_chunks_mut::<LANES>().0.iter_mut().enumerate() {
                    // SAFETY: `half` is valid for writing 8 f32; no alignment requirement.
                    unsafe { _mm256_storeu_ps(half.as_mut_ptr(), halves[h][c]) };
                }
            }
        }
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

    /// The index in `buf` of the float `k % 16` floats past `buf`'s first 64-byte boundary:
    /// where the tests put a plane that starts at that offset within a line (`buf` holds 31
    /// floats more than the plane).
    #[cfg(target_arch = "x86_64")]
    fn past_line(buf: &[f32], k: usize) -> usize {
        buf.as_ptr().align_offset(64) + k % 16
    }

    /// One x86-64 form of the accelerated loops, as the tests force them.
    #[cfg(target_arch = "x86_64")]
    struct X86Loops<const N: usize> {
        name: &'static str,
        available: bool,
        /// Pixels per group of the sRGB loops.
        group: usize,
        planar: PlanarLoop<N>,
        batch: BatchLoop<N>,
        /// Whether the interleaved loop takes width N (it returns 0 for others).
        batch_takes: fn(usize) -> bool,
        linear: LinearLoop<N>,
    }

    /// The accelerated planar sRGB loops' signature.
    #[cfg(target_arch = "x86_64")]
    type PlanarLoop<const N: usize> = unsafe fn(&[[f32; N]; 3], [&[f32]; N], &mut [u8]) -> usize;
    /// The accelerated interleaved sRGB loops' signature.
    #[cfg(target_arch = "x86_64")]
    type BatchLoop<const N: usize> = unsafe fn(&[[f32; N]; 3], &[[f32; N]], &mut [u8]) -> usize;
    /// The accelerated planar linear loops' signature (the last argument: `stream`).
    #[cfg(target_arch = "x86_64")]
    type LinearLoop<const N: usize> =
        unsafe fn(&[[f32; N]; 3], [&[f32]; N], [&mut [f32]; 3], bool) -> usize;

    /// The AVX-512 and the AVX2 loops.
    #[cfg(target_arch = "x86_64")]
    fn x86_loops<const N: usize>() -> [X86Loops<N>; 2] {
        use super::{avx2, avx512};
        [
            X86Loops {
                name: "AVX-512",
                available: avx512::available(),
                group: avx512::LANES,
                planar: avx512::encode_srgb8_planar::<N>,
                batch: avx512::encode_srgb8_batch::<N>,
                batch_takes: |n| avx512::BATCH_WIDTHS.contains(&n),
                linear: avx512::linear_planar::<N>,
            },
            X86Loops {
                name: "AVX2",
                available: avx2::available(),
                group: avx2::LANES,
                planar: avx2::encode_srgb8_planar::<N>,
                batch: avx2::encode_srgb8_batch::<N>,
                batch_takes: |_| true,
                linear: avx2::linear_planar::<N>,
            },
        ]
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
        crate::planar::encode_srgb8_planar_portable(&set.weights, planes, &mut got);
        compare("portable planar", &got);
        let mut got = std::vec![[0u8; 3]; pixels];
        crate::planar::encode_srgb8_batch_portable(&set.weights, &aos, &mut got);
        compare("portable batch", &got);
        let mut lin = [0, 1, 2].map(|_| std::vec![0.0f32; pixels]);
        {
            let [r, g, b] = &mut lin;
            crate::planar::linear_planar_portable(&set.weights, planes, [r, g, b]);
        }
        compare_linear("portable planar linear", &lin);

        // The AVX-512 and AVX2 loops, where this CPU has them: every whole group (of 16 and of
        // 8 pixels; the AVX2 sRGB loops a lone group too, as their pipeline runs only the stages
        // whose group exists; the AVX-512 interleaved loop only at its widths, else nothing).
        // Linear output with and without `stream` (with AVX2, at most four planes, `stream`
        // changes nothing), into output planes starting 0 to 15 floats past a 64-byte boundary
        // (different for each plane and seed), so that the streamed copies' ordinary head and
        // tail stores are used too; nothing outside the output planes may change.
        #[cfg(target_arch = "x86_64")]
        for x86 in x86_loops::<N>() {
            if !x86.available {
                continue;
            }
            let name = x86.name;
            let srgb8_done = pixels / x86.group * x86.group;
            // The planar loops on copies of the planes starting 0 to 15 floats past a 64-byte
            // boundary, planes 2k and 2k + 1 at the same offset (which depends on the seed):
            // where the loops start their groups depends on those offsets (`on_lines`). They
            // must leave fewer pixels than a step, and write nothing past those they report.
            let mut copies: std::vec::Vec<std::vec::Vec<f32>> =
                (0..N).map(|_| std::vec![0.0f32; pixels + 32]).collect();
            let starts: [usize; N] =
                core::array::from_fn(|i| past_line(&copies[i], seed as usize + 7 * (i / 2)));
            for ((c, p), &o) in copies.iter_mut().zip(&planes).zip(&starts) {
                c[o..o + pixels].copy_from_slice(p);
            }
            let shifted: [&[f32]; N] =
                core::array::from_fn(|i| &copies[i][starts[i]..starts[i] + pixels]);
            let mut got = std::vec![[0xA5u8; 3]; pixels];
            // SAFETY: the CPU has the loop's features (`available`).
            let done = unsafe { (x86.planar)(&set.weights, shifted, got.as_flattened_mut()) };
            assert!(
                done <= pixels && done + x86.group > pixels,
                "{name} planar: {done} of {pixels}"
            );
            compare(&std::format!("{name} planar"), &got[..done]);
            assert!(
                got[done..].iter().all(|p| *p == [0xA5; 3]),
                "{name} planar: written past {done}"
            );
            let mut got = std::vec![[0u8; 3]; pixels];
            // SAFETY: the CPU has the loop's features (`available`).
            let done = unsafe { (x86.batch)(&set.weights, &aos, got.as_flattened_mut()) };
            let batch_done = if (x86.batch_takes)(N) { srgb8_done } else { 0 };
            assert_eq!(done, batch_done, "{name} batch");
            compare(&std::format!("{name} batch"), &got[..done]);
            for stream in [false, true] {
                let mut buf = [0, 1, 2].map(|_| std::vec![0.0f32; pixels + 32]);
                let offset = |c: usize, b: &[f32]| past_line(b, 5 * c + seed as usize);
                let [r, g, b] = &mut buf;
                let (or, og, ob) = (offset(0, r), offset(1, g), offset(2, b));
                let out = [
                    &mut r[or..or + pixels],
                    &mut g[og..og + pixels],
                    &mut b[ob..ob + pixels],
                ];
                // SAFETY: the CPU has the loop's features (`available`).
                let done = unsafe { (x86.linear)(&set.weights, shifted, out, stream) };
                // Steps of 16 pixels.
                assert!(
                    done <= pixels && done + 16 > pixels,
                    "{name} planar linear: {done} of {pixels}"
                );
                let lin = [(r, or), (g, og), (b, ob)].map(|(c, o)| c[o..o + done].to_vec());
                compare_linear(&std::format!("{name} planar linear, {stream}"), &lin);
                for (c, o) in [(&buf[0], or), (&buf[1], og), (&buf[2], ob)] {
                    let untouched = c[..o].iter().chain(&c[o + done..]);
                    assert!(
                        untouched.copied().all(|v| v == 0.0),
                        "{name}: written outside"
                    );
                }
            }
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

    /// Pixels per block of the planar loops in passes (`avx2::BLOCK_GROUPS` groups of 8), so
    /// that the counts of the test below fall on and around the blocks' ends.
    const BLOCK: usize = 1024;
    #[cfg(target_arch = "x86_64")]
    const _: () = assert!(BLOCK == super::avx2::BLOCK_GROUPS * super::avx2::LANES);

    #[test]
    fn the_loops_in_passes_give_the_per_pixel_bytes_around_their_blocks() {
        // More than four planes: passes of four planes over blocks of 1024 pixels, the last
        // pass with one (N = 5, 9), two (6), three (7) or four planes (8, 12, 16). One block,
        // a block and a group, two blocks less a group, two and a part, three and a pair.
        for (k, pixels) in [
            BLOCK,
            BLOCK + 8,
            2 * BLOCK - 8,
            2 * BLOCK + 21,
            3 * BLOCK + 16,
        ]
        .into_iter()
        .enumerate()
        {
            let seed = 100 * (k as u64 + 2);
            check(&random_set::<5>(seed), pixels, seed + 1);
            check(&random_set::<6>(seed), pixels, seed + 2);
            check(&random_set::<7>(seed), pixels, seed + 3);
            check(&KQ_C_8_SRGB, pixels, seed + 4);
            check(&random_set::<9>(seed), pixels, seed + 5);
            check(&random_set::<12>(seed), pixels, seed + 6);
            check(&random_set::<16>(seed), pixels, seed + 7);
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
        // Fewer pixels than one group: the tails alone; one group and a part (the pipeline's
        // shortest run, where no two stages overlap); two, three and five groups, and one step
        // of the linear loop and a part.
        check(&TABLE2_ROW2_SRGB, 7, 12);
        check(&TABLE2_ROW2_SRGB, 0, 13);
        for (pixels, seed) in [(9, 14), (16, 15), (17, 16), (24, 17), (40, 18), (31, 19)] {
            check(&TABLE2_ROW2_SRGB, pixels, seed);
            check(&random_set::<16>(seed), pixels, seed + 100);
        }
    }
}
