//! The batch and planar loops for x86-64 CPUs with AVX2 (detected at run time, when the
//! AVX-512 loops are not available): eight pixels per register.
//!
//! - The sRGB 8-bit loops (planar and interleaved) pass each group of eight pixels through
//!   three stages, a group apart, so that the scalar table loads overlap the vector work (see
//!   "The sRGB 8-bit loop" below).
//! - The planar loops ask for their samples a few cache lines ahead, and above
//!   [`PASS_PLANES`] planes go through blocks of pixels four planes at a time, with partial
//!   sums on the stack (see "Planes in passes" below).
//!
//! Each channel is summed with the same f32 operations in the same order as the per-pixel
//! functions, so every loop gives their bytes (linear output: their bits).

use core::arch::x86_64::*;

use super::lights::Lights;
use super::loops::{linear_from_lines, srgb8_from_lines, StoreFence};
use crate::encode::{entry_at_top, LO};

cpufeatures::new!(cpu_avx2, "avx2");

/// Pixels per AVX2 register.
pub(crate) const LANES: usize = 8;

/// How far ahead of the group being computed the loops over planes ask for the samples,
/// in groups of [`LANES`] pixels (256 bytes per plane). The hardware prefetchers keep up
/// with one stream, but a loop that reads four to sixteen planes and does work between
/// the loads waited for memory on the CPU measured (AMD Zen 3); 16 and 32 groups did no
/// better than 8 (docs/performance.md has the figures).
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
    // `_mm_prefetch` is a safe function from Rust 1.91 and unsafe before it (the crate's
    // rust-version is 1.89): the block is needed there and redundant here.
    // SAFETY: a prefetch reads nothing and faults on no address.
    #[allow(unused_unsafe)]
    unsafe {
        _mm_prefetch::<_MM_HINT_T0>(p.cast());
    }
}

/// `weights · samples` for eight pixels (one per lane), channel c as `start[c]` plus the
/// products `weights[c][i] · s[i]` added in index order; with `start` `None`, each channel
/// from its first product with the rest added in index order: `pixel::mat_vec_for_encoding`,
/// lane by lane (and, from `Some` of zeros, `pixel::mat_vec`).
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

/// `a + b`, channel by channel.
#[inline]
#[target_feature(enable = "avx2")]
fn add3(a: [__m256; 3], b: [__m256; 3]) -> [__m256; 3] {
    [
        _mm256_add_ps(a[0], b[0]),
        _mm256_add_ps(a[1], b[1]),
        _mm256_add_ps(a[2], b[2]),
    ]
}

/// The lights' products of eight pixels added in light order: light l's [`add_products`] of
/// `weights[l]` and `$samples` (with `$l` bound to the light, substituted, so that no closure
/// is called) from `$start`, then each added to the lights before it. With one light, that
/// light's products. A macro, for the reason `plane_group!` is one.
macro_rules! sum_lights {
    ($weights:expr, |$l:ident| $samples:expr, $start:expr) => {{
        let mut rgb = [_mm256_setzero_ps(); 3];
        for ($l, w) in $weights.iter().enumerate() {
            let c = add_products(w, &$samples, $start);
            rgb = if $l == 0 { c } else { add3(rgb, c) };
        }
        rgb
    }};
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
// scalar loads on the CPU measured (AMD Zen 3); docs/performance.md lists what else was
// tried.

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

/// Sample i of light l of eight pixels in register i (lane k: pixel k): four at a time by
/// [`transpose4`], the last N mod 4 one by one. With one light and N = 4, the lanes hold
/// pixels 0, 2, 4, 6, 1, 3, 5, 7 instead ([`transpose_even_odd`]; [`even_odd`] says so).
#[inline]
#[target_feature(enable = "avx2")]
fn transpose<const N: usize, const L: usize, P: Lights<N, L>>(
    px: &[P; LANES],
    l: usize,
) -> [__m256; N] {
    let mut s = [_mm256_setzero_ps(); N];
    if even_odd::<N, L>() {
        s.copy_from_slice(&transpose_even_odd(P::flatten(px)));
        return s;
    }
    for b in 0..N / 4 {
        s[4 * b..4 * b + 4].copy_from_slice(&transpose4(px, l, 4 * b));
    }
    for (i, s) in s.iter_mut().enumerate().skip(N / 4 * 4) {
        let at = |k: usize| px[k].lights()[l][i];
        *s = _mm256_setr_ps(at(0), at(1), at(2), at(3), at(4), at(5), at(6), at(7));
    }
    s
}

/// Whether [`transpose`] puts the pixels in lanes 0, 2, 4, 6, 1, 3, 5, 7: one light of four
/// samples, where two pixels are one 32-byte load.
const fn even_odd<const N: usize, const L: usize>() -> bool {
    N == 4 && L == 1
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

/// Samples `i..i + 4` of light l of eight pixels, one register per sample (lane k: pixel
/// k): the pixels' four values loaded two rows to a register (pixel k in the low half, k + 4
/// in the high) and transposed 4 × 4 within each half. Eight loads and eight shuffles where
/// inserting lane by lane takes 32 of each. `i + 4 ≤ N`.
#[inline]
#[target_feature(enable = "avx2")]
fn transpose4<const N: usize, const L: usize, P: Lights<N, L>>(
    px: &[P; LANES],
    l: usize,
    i: usize,
) -> [__m256; 4] {
    let mut rows = [_mm256_setzero_ps(); 4];
    for (k, row) in rows.iter_mut().enumerate() {
        let (lo, hi) = (
            &px[k].lights()[l][i..i + 4],
            &px[k + 4].lights()[l][i..i + 4],
        );
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
        // slower from memory on the CPU measured (AMD Zen 3).
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
/// constant: the last pass's arrays are K wide. `$f<_, L>` gives `$f::<K, L>`.
macro_rules! with_last_pass {
    ($k:expr, $f:ident $(<_, $l:literal>)? ($($arg:expr),*)) => {
        match $k {
            1 => $f::<1 $(, $l)?>($($arg),*),
            2 => $f::<2 $(, $l)?>($($arg),*),
            3 => $f::<3 $(, $l)?>($($arg),*),
            _ => $f::<4 $(, $l)?>($($arg),*),
        }
    };
}

/// The planar sRGB 8-bit loop: `planes[l][i]` (light by light; one light for a folded set)
/// and `out` (3 bytes per pixel). Returns how many pixels it wrote (8 or more, or 0 below
/// 8); the caller encodes the rest. Its groups
/// start where most planes start a 32-byte boundary ([`on_lines`](super::loops::on_lines)), so
/// that no group's samples straddle two 64-byte lines, after one group at the planes'
/// start.
#[target_feature(enable = "avx2")]
pub(crate) fn encode_srgb8_planar<const N: usize, const L: usize>(
    weights: &[[[f32; N]; 3]; L],
    planes: [[&[f32]; N]; L],
    out: &mut [u8],
) -> usize {
    srgb8_from_lines(planes, out, LANES, 32, |planes, out| {
        encode_srgb8_groups(weights, planes, out)
    })
}

/// [`encode_srgb8_planar`] over whole groups of eight pixels from the planes' start;
/// returns how many pixels it wrote (a multiple of 8). A folded set above [`PASS_PLANES`]
/// planes, in passes (see there); a light-group set in one pass, light after light.
#[target_feature(enable = "avx2")]
fn encode_srgb8_groups<const N: usize, const L: usize>(
    weights: &[[[f32; N]; 3]; L],
    planes: [[&[f32]; N]; L],
    out: &mut [u8],
) -> usize {
    let planes: [[&[[f32; LANES]]; N]; L] =
        planes.map(|light| light.map(|p| p.as_chunks::<LANES>().0));
    let (dst, _) = out.as_chunks_mut::<{ 3 * LANES }>();
    let groups = planes
        .as_flattened()
        .iter()
        .map(|p| p.len())
        .fold(dst.len(), usize::min);
    let dst = &mut dst[..groups];
    let (1, Some(weights), Some(planes)) = (L, weights.first(), planes.first()) else {
        encode_srgb8!(groups, dst, false, |j| sum_lights!(
            weights,
            |l| plane_group!(planes[l], j),
            None
        ));
        return groups * LANES;
    };
    if N <= PASS_PLANES {
        encode_srgb8!(groups, dst, false, |j| add_products(
            weights,
            &plane_group!(*planes, j),
            None
        ));
        return groups * LANES;
    }
    let mut sums = Sums::ZERO;
    for (b, dst) in dst.chunks_mut(BLOCK_GROUPS).enumerate() {
        let first = b * BLOCK_GROUPS;
        add_passes(
            weights,
            planes,
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
                &sub(planes, last),
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

/// The interleaved (one `P` per pixel: a folded set's `[f32; N]`, or a light-group set's
/// `[[f32; N]; L]`) sRGB 8-bit loop over whole groups of eight pixels; returns how many
/// pixels it wrote.
#[target_feature(enable = "avx2")]
pub(crate) fn encode_srgb8_batch<const N: usize, const L: usize, P: Lights<N, L>>(
    weights: &[[[f32; N]; 3]; L],
    samples: &[P],
    out: &mut [u8],
) -> usize {
    let (pixels, _) = samples.as_chunks::<LANES>();
    let (dst, _) = out.as_chunks_mut::<{ 3 * LANES }>();
    let groups = pixels.len().min(dst.len());
    let (pixels, dst) = (&pixels[..groups], &mut dst[..groups]);
    encode_srgb8!(groups, dst, even_odd::<N, L>(), |j| sum_lights!(
        weights,
        |l| transpose(&pixels[j], l),
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
// for linear output; the sRGB loop at six was a little slower (docs/performance.md has the
// figures).

/// Planes per pass: at most this many input streams are read at a time.
pub(crate) const PASS_PLANES: usize = 4;

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
fn columns<const N: usize, const K: usize>(weights: &[[f32; N]; 3], from: usize) -> [[f32; K]; 3] {
    core::array::from_fn(|c| core::array::from_fn(|i| weights[c][from + i]))
}

/// Planes `from..from + K`.
#[inline]
fn sub<'a, T, const N: usize, const K: usize>(planes: &[&'a [T]; N], from: usize) -> [&'a [T]; K] {
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
    /// From 0.0 (`pixel::mat_vec`).
    Zero,
    /// From the first product (`pixel::mat_vec_for_encoding`).
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

/// Whether the planar linear loop writes with non-temporal stores from
/// [`STREAM_MIN_PIXELS`](super::STREAM_MIN_PIXELS) on: a folded set's above [`PASS_PLANES`]
/// planes (a light-group set's go in one pass, and write through the caches).
pub(crate) const fn streams<const N: usize, const L: usize>() -> bool {
    L == 1 && N > PASS_PLANES
}

/// The planar linear f32 loop in pairs of groups (16 pixels), light by light. A folded set
/// above [`PASS_PLANES`] planes in passes (see there); a light-group set in one pass.
///
/// With `stream` and above [`PASS_PLANES`] planes, the last pass too adds into the block's
/// sums, which are then copied to the three output planes one after the other with
/// non-temporal stores (`vmovntps`, [`stream_out`]). These write whole lines without first
/// reading them from memory, as ordinary stores do: at N = 8 that read is 12 of the 56
/// bytes per pixel that cross the memory bus. On the CPU measured (AMD Zen 3) this was
/// faster from memory at N = 6, 8 and 16; at N = 4, where one pass writes the output
/// directly, the extra copy made it slower, and copying the sums plane by plane with
/// ordinary stores was slower than the last pass's direct stores (docs/performance.md).
/// The output is then not in the caches, hence the caller's threshold.
///
/// Its pairs of groups start where most planes start a 32-byte boundary
/// ([`on_lines`](super::loops::on_lines)), after one pair at the planes' start. Returns how
/// many pixels it wrote (16 or more, or 0 below 16).
#[target_feature(enable = "avx2")]
pub(crate) fn linear_planar<const N: usize, const L: usize>(
    weights: &[[[f32; N]; 3]; L],
    planes: [[&[f32]; N]; L],
    out: [&mut [f32]; 3],
    stream: bool,
) -> usize {
    linear_from_lines(planes, out, 2 * LANES, 32, |planes, out, first| {
        linear_pairs(weights, planes, out, stream && !first)
    })
}

/// [`linear_planar`] over whole pairs of groups of eight pixels from the planes' start;
/// returns how many pixels it wrote (a multiple of 16).
#[target_feature(enable = "avx2")]
fn linear_pairs<const N: usize, const L: usize>(
    weights: &[[[f32; N]; 3]; L],
    planes: [[&[f32]; N]; L],
    out: [&mut [f32]; 3],
    stream: bool,
) -> usize {
    let planes: [[&[[f32; LANES]]; N]; L] =
        planes.map(|light| light.map(|p| p.as_chunks::<LANES>().0));
    let out = out.map(|o| o.as_chunks_mut::<{ 2 * LANES }>().0);
    let pairs = planes
        .as_flattened()
        .iter()
        .map(|p| p.len())
        .min()
        .unwrap_or(0)
        / 2;
    let pairs = out.iter().map(|o| o.len()).fold(pairs, usize::min);
    let [r, g, b] = out;
    let (r, g, b) = (&mut r[..pairs], &mut g[..pairs], &mut b[..pairs]);
    let (true, Some(weights), Some(planes)) = (streams::<N, L>(), weights.first(), planes.first())
    else {
        linear_last_pass(weights, &planes, 0, None, [r, g, b]);
        return pairs * 2 * LANES;
    };
    // From here on the output may be written with non-temporal stores: the fence follows them
    // on every way out.
    let _fence = stream.then_some(StoreFence);
    let mut sums = Sums::ZERO;
    let block = BLOCK_GROUPS / 2;
    let blocks = r
        .chunks_mut(block)
        .zip(g.chunks_mut(block))
        .zip(b.chunks_mut(block));
    let last = last_pass_from::<N>();
    for (k, ((r, g), b)) in blocks.enumerate() {
        let (first, groups) = (2 * k * block, 2 * r.len());
        add_passes(weights, planes, first, groups, Start::Zero, &mut sums);
        if stream {
            with_last_pass!(
                N - last,
                add_pass(
                    &columns(weights, last),
                    &sub(planes, last),
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
                linear_last_pass < _,
                1 > (
                    &[columns(weights, last)],
                    &[sub(planes, last)],
                    first,
                    Some(&sums),
                    [r, g, b]
                )
            );
        }
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

/// The planar linear loop's last pass (its only one up to [`PASS_PLANES`] planes, and a
/// light-group set's): pair k of `out` (16 pixels of each channel) from `sums` (pair k's
/// groups, 2k and 2k + 1), or from 0.0 without, plus the products of `planes` (with their
/// `weights`) for groups `first + 2k` and `first + 2k + 1`; light by light, each light's from
/// 0.0 and the lights added in order (`sums` is given with one light only).
///
/// Each step writes 64 bytes to the red plane, then 64 to green, then 64 to blue, a cache
/// line's worth at a time, rather than eight pixels of each plane in turn, which filled
/// every output line in two visits and was slower from memory on the CPU measured (AMD
/// Zen 3; docs/performance.md has the figures).
#[target_feature(enable = "avx2")]
fn linear_last_pass<const N: usize, const L: usize>(
    weights: &[[[f32; N]; 3]; L],
    planes: &[[&[[f32; LANES]]; N]; L],
    first: usize,
    sums: Option<&Sums>,
    out: [&mut [[f32; 2 * LANES]]; 3],
) {
    let [r, g, b] = out;
    for (k, ((r, g), b)) in r.iter_mut().zip(g.iter_mut()).zip(b.iter_mut()).enumerate() {
        let j = first + 2 * k;
        let mut halves = [[_mm256_setzero_ps(); 3]; 2];
        for (l, (weights, planes)) in weights.iter().zip(planes).enumerate() {
            // Both halves of each plane's 64-byte line together, plane after plane: planes
            // that lie 128 MiB and 4 KiB apart (consecutive allocations of 2²⁵ f32) are read
            // more slowly on the CPU measured (AMD Zen 3), and reading each line at once was
            // faster there from N = 8 up than reading all planes' first halves, then all
            // second halves.
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
            for (h, (half, s)) in halves.iter_mut().zip(&s).enumerate() {
                let start = match sums {
                    Some(sums) => sums.get(2 * k + h),
                    None => [_mm256_setzero_ps(); 3],
                };
                let c = add_products(weights, s, Some(start));
                *half = if l == 0 { c } else { add3(*half, c) };
            }
        }
        for (c, o) in [r, g, b].into_iter().enumerate() {
            for (h, half) in o.as_chunks_mut::<LANES>().0.iter_mut().enumerate() {
                // SAFETY: `half` is valid for writing 8 f32; no alignment requirement.
                unsafe { _mm256_storeu_ps(half.as_mut_ptr(), halves[h][c]) };
            }
        }
    }
}
