//! The planar loops (sRGB 8-bit and linear f32) and the interleaved sRGB 8-bit loop at N = 4
//! for x86-64 CPUs with AVX-512 (`avx512f`, `avx512bw` and `avx512vbmi`, detected at run time):
//! sixteen pixels per register, the code values computed by a polynomial, exact because every
//! value it cannot vouch for is encoded again by the per-pixel function.
//!
//! # Why a polynomial
//!
//! The table encoder (`encode::SEGMENT_TABLE`) costs a load per value, and vector registers
//! reach memory only through gathers, which are slow on the CPU measured (AMD Zen 4); the AVX2
//! loops' scalar loads are faster, but those loops are bound by them. AVX-512 has 32
//! registers, mask registers and three-input logic, enough to keep a polynomial's constants and
//! the weights in registers, so here the vector units do the work and the table is read only
//! for the few values near a rounding boundary. docs/performance.md has the figures.
//!
//! # The encoder, and why it is exact
//!
//! For x clamped to 0..=1, in units of 2⁻¹⁶ of a code value and biased by W ([`WINDOW`]):
//!
//! - below [`LINEAR_BELOW`], y = 2¹⁶ · (255 · 12.92 · x + ½) + W;
//! - above, with x = 2ᵉ · m (m in 1..2), y = 2¹⁶ · 255 · 1.055 · 2^(5e/12) · P(m) +
//!   2¹⁶ · (½ − 255 · 0.055) + W, where P is the degree-5 polynomial through m^(5/12) at the six
//!   Chebyshev nodes of 1..2 ([`P`]), and the factor in e a lookup in a 16-entry register
//!   ([`SCALE`]).
//!
//! y is truncated to an integer i. Let F be 2¹⁶ times the exact curve (in f64) times 255 plus
//! ½, so that the correctly rounded code value is ⌊F / 2¹⁶⌋. Where |i − (F + W)| < W, i lies in
//! F..F + 2W; then if i's low 16 bits are 2W or more, i / 2¹⁶ is that code value (a carry past
//! the code value would leave fewer than 2W in them). Lanes whose low bits are below 2W are
//! *flagged*, and their pixels are encoded again, one by one, by the per-pixel function. The
//! unit tests measure |i − (F + W)| at 24.7 at most (W = 32) on 17 million f32 from 0 to 1, and
//! run every f32 from 0 to 1 through the encoder, checking every unflagged value against the
//! table: none differs, and 0.022 % of those f32 are flagged.
//!
//! NaN is flagged too: the clamp keeps it (`max(0, x)` and `min(1, x)` return their second
//! operand when either is NaN), the linear branch is taken (an ordered comparison is false),
//! and the truncation of NaN is `0x8000_0000`, whose low 16 bits are 0. A flagged pixel with
//! a NaN channel is black, as in the per-pixel function. ±Inf, huge and negative values clamp.
//!
//! The 3×N product is computed as everywhere else (the same f32 operations in the same order
//! as `pixel::mat_vec_for_encoding`, no FMA), so every byte equals the per-pixel function's.
//!
//! # Memory
//!
//! The planar loops ask for each plane's samples [`NEAR`] groups ahead into the first-level
//! cache and [`FAR`] groups ahead into the second, and read every plane at once at every width
//! (the AVX2 loops go four planes at a time above four planes). The planar loops start their
//! groups where most planes start a 64-byte line ([`on_lines`](super::loops::on_lines)), so
//! that each line is read once.

use core::arch::x86_64::*;
use core::hint::black_box;

use super::loops::{linear_from_lines, srgb8_from_lines, StoreFence};

cpufeatures::new!(cpu_avx512, "avx512f", "avx512bw", "avx512vbmi");

/// Pixels per AVX-512 register.
pub(crate) const LANES: usize = 16;

/// Whether this CPU (and its operating system) supports the AVX-512 subsets these loops use:
/// `cpuid` and `xgetbv` on the first call, a cached flag afterwards.
#[inline]
pub(crate) fn available() -> bool {
    cpu_avx512::get()
}

// --- The encoder's constants -------------------------------------------------------------------

/// The bias W of the encoder's output, in units of 2⁻¹⁶ of a code value, and half its flagging
/// window: a lane is flagged where the low 16 bits of its output are below 2W. The test
/// `the_encoders_error_stays_inside_its_window` measures the output's error against the exact
/// curve at 24.7 at most (it must stay below W) on 17 million f32 from 0 to 1, and
/// `the_vector_encoder_is_exact_where_it_does_not_flag` checks every unflagged f32 from 0 to 1
/// against the table. A power of two, so that the window is one mask.
pub(crate) const WINDOW: i32 = 32;
const _: () = assert!(WINDOW.count_ones() == 1 && 2 * WINDOW < 1 << 16);

/// Below this the sRGB curve is linear (12.92 · x), at and above it the power law.
const LINEAR_BELOW: f32 = 0.003_130_8;

/// 2¹⁶: the encoder's output unit is 2⁻¹⁶ of a code value.
const UNIT: f64 = 65_536.0;

/// √a by Newton's method from above (a ≥ 1): monotone, converged to the last bit well within
/// 64 steps for a ≤ 8.
const fn sqrt(a: f64) -> f64 {
    let mut r = a;
    let mut i = 0;
    while i < 64 {
        r = 0.5 * (r + a / r);
        i += 1;
    }
    r
}

/// a^(1/12) by Newton's method from above (1 ≤ a ≤ 2¹¹): monotone, converged to the last bit
/// well within 200 steps.
const fn root12(a: f64) -> f64 {
    let mut r = a;
    let mut i = 0;
    while i < 200 {
        let r2 = r * r;
        let r4 = r2 * r2;
        let r11 = r4 * r4 * r2 * r;
        r = (11.0 * r + a / r11) / 12.0;
        i += 1;
    }
    r
}

/// m^(5/12) for m in 1..=2.
const fn pow_5_12(m: f64) -> f64 {
    let m2 = m * m;
    root12(m2 * m2 * m)
}

/// The coefficients of P, c₀ to c₅ (P(m) = c₀ + c₁m + … + c₅m⁵): the polynomial of degree 5
/// through m^(5/12) at the Chebyshev nodes 1.5 + 0.5 · cos((2k + 1)π/12), k = 0..6, by Newton's
/// divided differences in f64, then expanded and rounded to f32. Its largest error on 1..2 is
/// 1.8 · 10⁻⁶ (0.00036 of a code value in the top octave); the test of the whole encoder bounds
/// what reaches the output.
const P: [f32; 6] = {
    // cos(π/12), cos(3π/12), cos(5π/12), and their negatives.
    let (s2, s6) = (sqrt(2.0), sqrt(6.0));
    let c = [(s6 + s2) / 4.0, s2 / 2.0, (s6 - s2) / 4.0];
    let t = [c[0], c[1], c[2], -c[2], -c[1], -c[0]];
    let mut x = [0.0f64; 6];
    let mut d = [0.0f64; 6];
    let mut k = 0;
    while k < 6 {
        x[k] = 1.5 + 0.5 * t[k];
        d[k] = pow_5_12(x[k]);
        k += 1;
    }
    // Divided differences: d[k] becomes f[x₀, …, x_k].
    let mut j = 1;
    while j < 6 {
        let mut k = 5;
        while k >= j {
            d[k] = (d[k] - d[k - 1]) / (x[k] - x[k - j]);
            k -= 1;
        }
        j += 1;
    }
    // Newton form to power basis: p = d₅; p = p · (m − x_k) + d_k for k = 4 down to 0.
    let mut p = [0.0f64; 6];
    p[0] = d[5];
    let mut k = 5;
    while k > 0 {
        k -= 1;
        // p ← p · (m − x_k) + d_k, coefficients low to high.
        let mut i = 5;
        while i > 0 {
            p[i] = p[i - 1] - x[k] * p[i];
            i -= 1;
        }
        p[0] = d[k] - x[k] * p[0];
    }
    let mut out = [0.0f32; 6];
    let mut i = 0;
    while i < 6 {
        out[i] = p[i] as f32;
        i += 1;
    }
    out
};

/// 2¹⁶ · 255 · 1.055 · 2^(5e/12) at index (e + 127) mod 16, for the exponents e = −9..=0 of
/// the power law's range (LINEAR_BELOW ≈ 1.6 · 2⁻⁹ up to 1.0); the other entries are never
/// used (0). `vpermps` takes the low four bits of the index, so the exponent field of the
/// f32, shifted down, is the index as it stands.
const SCALE: [f32; 16] = {
    let mut s = [0.0f32; 16];
    let mut biased = 118;
    while biased <= 127 {
        // 5e = 12q + r with 0 ≤ r < 12: 2^(5e/12) = 2^q · 2^(r/12).
        let five_e = 5 * (biased as i32 - 127);
        let q = five_e.div_euclid(12);
        let r = five_e.rem_euclid(12);
        let mut v = root12((1u32 << r) as f64);
        let mut n = 0;
        while n < -q {
            v /= 2.0;
            n += 1;
        }
        s[biased & 15] = (UNIT * 255.0 * 1.055 * v) as f32;
        biased += 1;
    }
    s
};

/// The power law's constant term with the bias: 2¹⁶ · (½ − 255 · 0.055) + W.
const POWER_C: f32 = (UNIT * (0.5 - 255.0 * 0.055) + WINDOW as f64) as f32;
/// The linear segment's slope, 2¹⁶ · 255 · 12.92, and constant term with the bias, 2¹⁶ · ½ + W.
const LINEAR_A: f32 = (UNIT * 255.0 * 12.92) as f32;
const LINEAR_B: f32 = (UNIT * 0.5 + WINDOW as f64) as f32;

/// Byte indices for `vpermt2b` that interleave three channels' code values (byte 2 of each
/// 32-bit lane) into `r, g, b, r, …`: first red and green (bytes 3p and 3p + 1), then blue into
/// bytes 3p + 2 of that. Bytes 48..64 are left as they fall.
const PICK_RG: [u8; 64] = {
    let mut t = [0u8; 64];
    let mut p = 0;
    while p < LANES {
        t[3 * p] = (4 * p + 2) as u8;
        t[3 * p + 1] = (64 + 4 * p + 2) as u8;
        t[3 * p + 2] = (3 * p + 2) as u8;
        p += 1;
    }
    t
};
/// See [`PICK_RG`].
const PICK_B: [u8; 64] = {
    let mut t = [0u8; 64];
    let mut i = 0;
    while i < 64 {
        t[i] = i as u8;
        i += 1;
    }
    let mut p = 0;
    while p < LANES {
        t[3 * p + 2] = (64 + 4 * p + 2) as u8;
        p += 1;
    }
    t
};

/// The encoder's constants in registers (built once per call of a loop).
#[derive(Clone, Copy)]
struct Encoder {
    zero: __m512,
    one: __m512,
    mantissa: __m512i,
    one_bits: __m512i,
    scale: __m512,
    p: [__m512; 6],
    power_c: __m512,
    linear_a: __m512,
    linear_b: __m512,
    linear_below: __m512,
    /// The bits of a lane's output that must not all be 0 for it to go unflagged.
    unflagged: __m512i,
    pick_rg: __m512i,
    pick_b: __m512i,
}

impl Encoder {
    #[inline]
    #[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
    fn new() -> Encoder {
        // SAFETY: each array is 64 bytes, valid for reading; no alignment requirement.
        let (scale, pick_rg, pick_b) = unsafe {
            (
                _mm512_loadu_ps(SCALE.as_ptr()),
                _mm512_loadu_si512(PICK_RG.as_ptr().cast()),
                _mm512_loadu_si512(PICK_B.as_ptr().cast()),
            )
        };
        let mut p = [_mm512_setzero_ps(); 6];
        for (p, c) in p.iter_mut().zip(P) {
            *p = _mm512_set1_ps(c);
        }
        Encoder {
            zero: _mm512_setzero_ps(),
            one: _mm512_set1_ps(1.0),
            mantissa: _mm512_set1_epi32(0x007f_ffff),
            one_bits: _mm512_set1_epi32(0x3f80_0000),
            scale,
            p,
            power_c: _mm512_set1_ps(POWER_C),
            linear_a: _mm512_set1_ps(LINEAR_A),
            linear_b: _mm512_set1_ps(LINEAR_B),
            linear_below: _mm512_set1_ps(LINEAR_BELOW),
            unflagged: _mm512_set1_epi32(0xFFFF & !(2 * WINDOW - 1)),
            pick_rg,
            pick_b,
        }
    }

    /// The outputs i of the three channels of sixteen pixels (see the module's documentation)
    /// and the mask of the lanes flagged in any channel. The channels go through each step
    /// side by side.
    #[inline]
    #[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
    fn outputs(&self, rgb: [__m512; 3]) -> ([__m512i; 3], __mmask16) {
        let mut x = rgb;
        for x in &mut x {
            // NaN stays NaN: `vmaxps` and `vminps` return the second operand when either is NaN.
            *x = _mm512_min_ps(self.one, _mm512_max_ps(self.zero, *x));
        }
        let mut m = x;
        let mut s = x;
        for c in 0..3 {
            let bits = _mm512_castps_si512(x[c]);
            // (bits & mantissa) | one_bits: the mantissa as an f32 in 1..2.
            let mb = _mm512_ternarylogic_epi32::<0xEA>(bits, self.mantissa, self.one_bits);
            m[c] = _mm512_castsi512_ps(mb);
            // The exponent field, whose low four bits index SCALE.
            s[c] = _mm512_permutexvar_ps(_mm512_srli_epi32::<23>(bits), self.scale);
        }
        let mut p = [self.p[5]; 3];
        for k in (0..5).rev() {
            for c in 0..3 {
                p[c] = _mm512_fmadd_ps(p[c], m[c], self.p[k]);
            }
        }
        let mut out = [_mm512_setzero_si512(); 3];
        let mut flagged = 0;
        for c in 0..3 {
            let power = _mm512_fmadd_ps(s[c], p[c], self.power_c);
            let linear = _mm512_fmadd_ps(x[c], self.linear_a, self.linear_b);
            // Ordered: false for NaN, which then takes the linear branch and stays NaN.
            let is_power = _mm512_cmp_ps_mask::<_CMP_GE_OQ>(x[c], self.linear_below);
            let y = _mm512_mask_mov_ps(linear, is_power, power);
            out[c] = _mm512_cvttps_epi32(y);
            flagged |= _mm512_testn_epi32_mask(out[c], self.unflagged);
        }
        (out, flagged)
    }

    /// Sixteen pixels' 48 bytes `r, g, b, …` (in the first 48 bytes of the register) and the
    /// mask of the pixels to encode again.
    #[inline]
    #[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
    fn encode(&self, rgb: [__m512; 3]) -> (__m512i, __mmask16) {
        let ([r, g, b], flagged) = self.outputs(rgb);
        let rg = _mm512_permutex2var_epi8(r, self.pick_rg, g);
        (_mm512_permutex2var_epi8(rg, self.pick_b, b), flagged)
    }
}

/// Writes the first 48 bytes of `bytes` to `dst`.
#[inline]
#[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
fn store48(bytes: __m512i, dst: &mut [u8; 3 * LANES]) {
    let (lo, hi) = dst.split_at_mut(32);
    // SAFETY: `lo` is 32 bytes and `hi` 16: the stores write exactly those (no alignment
    // requirement).
    unsafe {
        _mm256_storeu_si256(lo.as_mut_ptr().cast(), _mm512_castsi512_si256(bytes));
        _mm_storeu_si128(
            hi.as_mut_ptr().cast(),
            _mm512_extracti32x4_epi32::<2>(bytes),
        );
    }
}

/// Encodes the `flagged` pixels of a group again, one by one, with the per-pixel function
/// (`sse2::encode_srgb8_groups`, the bytes of
/// [`LightGroupSet::encode_u8`](crate::LightGroupSet::encode_u8), and with one light those of
/// [`FoldedSet::encode_u8`](crate::FoldedSet::encode_u8)): pixel p's samples are `sample(p)`,
/// light by light.
#[cold]
#[inline(never)]
fn encode_again<const N: usize, const L: usize>(
    weights: &[[[f32; N]; 3]; L],
    flagged: __mmask16,
    sample: impl Fn(usize) -> [[f32; N]; L],
    dst: &mut [u8; 3 * LANES],
) {
    let mut left = flagged;
    while left != 0 {
        let p = left.trailing_zeros() as usize;
        left &= left - 1;
        let px = super::sse2::encode_srgb8_groups(weights, &sample(p));
        dst[3 * p..3 * p + 3].copy_from_slice(&px);
    }
}

/// Encodes sixteen pixels' linear values into `dst`; returns the mask of the pixels the caller
/// must encode again ([`encode_again`]).
#[inline]
#[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
fn encode_into(enc: &Encoder, rgb: [__m512; 3], dst: &mut [u8; 3 * LANES]) -> __mmask16 {
    let (bytes, flagged) = enc.encode(rgb);
    store48(bytes, dst);
    flagged
}

// --- Products ------------------------------------------------------------------------------------

/// The weights, each broadcast to a register, light by light.
#[inline]
#[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
fn broadcast<const N: usize, const L: usize>(
    weights: &[[[f32; N]; 3]; L],
) -> [[[__m512; N]; 3]; L] {
    let mut w = [[[_mm512_setzero_ps(); N]; 3]; L];
    for (w, light) in w.iter_mut().zip(weights) {
        for (w, row) in w.iter_mut().zip(light) {
            for (w, v) in w.iter_mut().zip(row) {
                *w = _mm512_set1_ps(*v);
            }
        }
    }
    w
}

/// `a + b`, channel by channel.
#[inline]
#[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
fn add3(a: [__m512; 3], b: [__m512; 3]) -> [__m512; 3] {
    [
        _mm512_add_ps(a[0], b[0]),
        _mm512_add_ps(a[1], b[1]),
        _mm512_add_ps(a[2], b[2]),
    ]
}

/// `weights · samples` for sixteen pixels, each channel from its first product with the others
/// added in index order: `pixel::mat_vec_for_encoding`, lane by lane.
#[inline]
#[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
fn products<const N: usize>(w: &[[__m512; N]; 3], s: &[__m512; N]) -> [__m512; 3] {
    let mut out = [_mm512_setzero_ps(); 3];
    for (acc, row) in out.iter_mut().zip(w) {
        for (i, (w, s)) in row.iter().zip(s).enumerate() {
            let p = _mm512_mul_ps(*w, *s);
            *acc = if i == 0 { p } else { _mm512_add_ps(*acc, p) };
        }
    }
    out
}

/// [`products`] with each weight read from `weights` at its multiplication (a broadcast
/// memory operand of the `vmulps`), not held in a register; group j of `planes`, light by
/// light, each light's product added to the lights before it in order (with one light, that
/// light's product).
///
/// The planar sRGB loop passes `weights` through [`black_box`] at every group, so that the
/// compiler cannot move these reads out of the loop. Moved out, the 3·N broadcast weights (12
/// at N = 4) compete for the 32 vector registers with the encoder's 18 constants and the next
/// group's products, and the compiler keeps some of them on the stack, reloading the
/// encoder's constants and the next group's products at every group. Read at their use, the
/// weights cost one load each from the first-level cache, which the load ports take beside
/// the vector work. `black_box` changes only where the weights are read, not their values:
/// were it to stop hiding them, the loop would give the same bytes.
#[inline]
#[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
fn products_of<const N: usize, const L: usize>(
    weights: &[[[f32; N]; 3]; L],
    planes: &[[&[[f32; LANES]]; N]; L],
    j: usize,
) -> [__m512; 3] {
    let mut rgb = [_mm512_setzero_ps(); 3];
    for (l, (light, planes)) in weights.iter().zip(planes).enumerate() {
        let s = load_group(planes, j);
        let mut out = [_mm512_setzero_ps(); 3];
        for (acc, row) in out.iter_mut().zip(light) {
            for (i, (w, s)) in row.iter().zip(&s).enumerate() {
                let p = _mm512_mul_ps(_mm512_set1_ps(*w), *s);
                *acc = if i == 0 { p } else { _mm512_add_ps(*acc, p) };
            }
        }
        rgb = if l == 0 { out } else { add3(rgb, out) };
    }
    rgb
}

// --- Memory ---------------------------------------------------------------------------------

/// How far ahead the planar loops ask for their samples, in groups of sixteen pixels (one
/// 64-byte line per plane): [`NEAR`] groups ahead into the first-level cache and [`FAR`]
/// groups ahead into the second. On the CPU measured (AMD Zen 4) the far requests made the
/// planar sRGB loop faster from memory, and nearer (64 groups) or farther (256, 512) ones did
/// no better; the near ones alone, at 4 to 32 groups, differed little (docs/performance.md has
/// the figures).
const NEAR: usize = 8;
/// See [`NEAR`].
const FAR: usize = 128;

/// Asks for group `j + NEAR` of each plane into the first-level cache (with `near`) and group
/// `j + FAR` into the second. Hints: any address is allowed, and nothing is read here.
#[inline]
#[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
fn prefetch<const N: usize, const L: usize>(
    planes: &[[&[[f32; LANES]]; N]; L],
    j: usize,
    near: bool,
) {
    for p in planes.as_flattened() {
        // `_mm_prefetch` is a safe function from Rust 1.91 and unsafe before it (the crate's
        // rust-version is 1.89): the block is needed there and redundant here.
        // SAFETY: a prefetch reads nothing and faults on no address (`wrapping_add` forms the
        // address without the in-bounds requirement of `add`).
        #[allow(unused_unsafe)]
        unsafe {
            if near {
                _mm_prefetch::<_MM_HINT_T0>(p.as_ptr().wrapping_add(j + NEAR).cast());
            }
            _mm_prefetch::<_MM_HINT_T1>(p.as_ptr().wrapping_add(j + FAR).cast());
        }
    }
}

/// Group j of each plane (every plane longer than j), sample i in register i.
#[inline]
#[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
fn load_group<const N: usize>(planes: &[&[[f32; LANES]]; N], j: usize) -> [__m512; N] {
    let mut s = [_mm512_setzero_ps(); N];
    for (s, p) in s.iter_mut().zip(planes) {
        debug_assert!(j < p.len());
        // SAFETY: every caller passes a j below the length of every plane, and `p[j]` is
        // valid for reading 16 f32 (no alignment requirement).
        *s = unsafe { _mm512_loadu_ps(p.get_unchecked(j).as_ptr()) };
    }
    s
}

// --- The loops ------------------------------------------------------------------------------

/// The planar sRGB 8-bit loop: `planes[l][i]` (light by light; one light for a folded set)
/// and `out` (3 bytes per pixel). Returns how many pixels it wrote (16 or more, or 0 below
/// 16); the caller encodes the rest.
///
/// The groups of sixteen pixels start where most planes start a 64-byte line
/// ([`on_lines`](super::loops::on_lines)), after one group at the planes' start.
#[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
pub(crate) fn encode_srgb8_planar<const N: usize, const L: usize>(
    weights: &[[[f32; N]; 3]; L],
    planes: [[&[f32]; N]; L],
    out: &mut [u8],
) -> usize {
    srgb8_from_lines(planes, out, LANES, 64, |planes, out| {
        encode_srgb8_groups(weights, planes, out)
    })
}

/// The planar sRGB 8-bit loop over whole groups of sixteen pixels from the planes' start.
/// Returns how many pixels it wrote (a multiple of 16).
///
/// All planes are read at once, at every width. The AVX2 loop goes through the planes four at
/// a time above four planes, with partial sums on the stack; on the CPU measured (AMD Zen 4)
/// the same passes before this loop were slower from memory at N = 6, 8 and 16 than one pass
/// (docs/performance.md has the figures).
///
/// Each step computes the next group's products before it encodes the current group. The
/// encoder's steps depend one on another (the clamp, the five steps of the polynomial, the
/// code values, the interleave); the next group's products do not depend on them, and written
/// first they are ready to fill the vector pipes while that chain runs, instead of waiting
/// behind it in program order. The weights are read at their use ([`products_of`]), which
/// leaves the registers to the encoder's constants and the next group's products. On the CPU
/// measured (AMD Zen 4) each of the two made the loop faster, in cache and from memory
/// (docs/performance.md has the figures).
#[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
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
    if groups == 0 {
        return 0;
    }
    let enc = Encoder::new();
    let mut next = products_of(black_box(weights), &planes, 0);
    for (j, dst) in dst[..groups].iter_mut().enumerate() {
        prefetch(&planes, j, true);
        let rgb = next;
        if j + 1 < groups {
            next = products_of(black_box(weights), &planes, j + 1);
        }
        let flagged = encode_into(&enc, rgb, dst);
        if flagged != 0 {
            let sample = |p: usize| planes.map(|light| light.map(|plane| plane[j][p]));
            encode_again(weights, flagged, sample, dst);
        }
    }
    groups * LANES
}

/// The widths N of the interleaved loop [`encode_srgb8_batch`]; the AVX2 loop takes the others.
pub(crate) const BATCH_WIDTHS: [usize; 1] = [4];

/// The interleaved sRGB 8-bit loop of a folded set (N samples per pixel, pixel after pixel, in
/// `samples`) over whole groups of sixteen pixels, for the widths of [`BATCH_WIDTHS`] (returns
/// 0 for others): the pixels of a group in four loads, turned into one register per sample by
/// eight shuffles.
#[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
pub(crate) fn encode_srgb8_batch<const N: usize>(
    weights: &[[f32; N]; 3],
    samples: &[f32],
    out: &mut [u8],
) -> usize {
    if !BATCH_WIDTHS.contains(&N) {
        return 0;
    }
    let (pixels, _) = samples.as_chunks::<{ 4 * LANES }>();
    let (dst, _) = out.as_chunks_mut::<{ 3 * LANES }>();
    let groups = pixels.len().min(dst.len());
    let enc = Encoder::new();
    let [w] = broadcast(core::array::from_ref(weights));
    for (px, dst) in pixels[..groups].iter().zip(&mut dst[..groups]) {
        let s = transpose4(px);
        let mut samples = [_mm512_setzero_ps(); N];
        samples.copy_from_slice(&s[..N]);
        let flagged = encode_into(&enc, products(&w, &samples), dst);
        if flagged != 0 {
            let sample = |p: usize| [core::array::from_fn(|i| px[N * p + i])];
            encode_again(core::array::from_ref(weights), flagged, sample, dst);
        }
    }
    groups * LANES
}

/// Sixteen pixels of four samples (64 f32, pixel by pixel) → one register per sample, lane p
/// holding pixel p.
#[inline]
#[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
fn transpose4(px: &[f32; 4 * LANES]) -> [__m512; 4] {
    let (rows, _) = px.as_chunks::<LANES>();
    let mut r = [_mm512_setzero_ps(); 4];
    for (r, row) in r.iter_mut().zip(rows) {
        // SAFETY: `row` is valid for reading 16 f32; no alignment requirement.
        *r = unsafe { _mm512_loadu_ps(row.as_ptr()) };
    }
    // Row k holds pixels 4k..4k + 4. Samples 0 and 1 of pixels 0..8 (from rows 0 and 1), and
    // samples 2 and 3, likewise for rows 2 and 3; then the halves joined.
    let lo = _mm512_setr_epi32(0, 4, 8, 12, 16, 20, 24, 28, 1, 5, 9, 13, 17, 21, 25, 29);
    let hi = _mm512_setr_epi32(2, 6, 10, 14, 18, 22, 26, 30, 3, 7, 11, 15, 19, 23, 27, 31);
    let a = _mm512_permutex2var_ps(r[0], lo, r[1]);
    let b = _mm512_permutex2var_ps(r[0], hi, r[1]);
    let c = _mm512_permutex2var_ps(r[2], lo, r[3]);
    let d = _mm512_permutex2var_ps(r[2], hi, r[3]);
    [
        _mm512_shuffle_f32x4::<0b01_00_01_00>(a, c),
        _mm512_shuffle_f32x4::<0b11_10_11_10>(a, c),
        _mm512_shuffle_f32x4::<0b01_00_01_00>(b, d),
        _mm512_shuffle_f32x4::<0b11_10_11_10>(b, d),
    ]
}

/// Up to this many planes the planar linear loop asks for its samples into the first-level
/// cache too. At N = 16, on the CPU measured (AMD Zen 4), the linear loop was faster without
/// those requests (the sRGB loop, the other way round, keeps them): sixteen planes at one
/// offset within a page compete for one set of the 8-way first-level cache, and lines asked
/// for early are evicted before their use (docs/performance.md has the runs, with this
/// constant at 16 and at 8).
const NEAR_LINEAR_PLANES: usize = 8;

/// The planar linear f32 loop: `planes[i]` and the three output planes. Returns how many
/// pixels it wrote (16 or more, or 0 below 16), its groups starting where most planes start
/// a 64-byte line ([`on_lines`](super::loops::on_lines)), after one group at the planes'
/// start. Each channel is summed from 0.0 in index order, as `pixel::mat_vec`, so the bits
/// are those of [`FoldedSet::linear_rgb`](crate::FoldedSet::linear_rgb).
///
/// One pass over all planes, the samples asked for ahead as in the sRGB loop, but above
/// [`NEAR_LINEAR_PLANES`] planes only into the second-level cache. With `stream`,
/// each output plane is written with non-temporal stores ([`StreamedPlane`]), which skip
/// reading the output's lines from memory before writing them; its lines are then not in the
/// caches. On the CPU measured (AMD Zen 4), over images far larger than the caches, ordinary
/// stores reached the planar streaming bound (which writes with ordinary stores) at N = 4 and
/// 8 and came close to it at N = 16, and the non-temporal ones took less time than those at
/// N = 4, 8 and 16 (docs/performance.md has the runs).
#[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
pub(crate) fn linear_planar<const N: usize, const L: usize>(
    weights: &[[[f32; N]; 3]; L],
    planes: [[&[f32]; N]; L],
    out: [&mut [f32]; 3],
    stream: bool,
) -> usize {
    linear_from_lines(planes, out, LANES, 64, |planes, out, first| {
        linear_groups(weights, planes, out, stream && !first)
    })
}

/// [`linear_planar`] over whole groups of sixteen pixels from the planes' start.
#[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
fn linear_groups<const N: usize, const L: usize>(
    weights: &[[[f32; N]; 3]; L],
    planes: [[&[f32]; N]; L],
    out: [&mut [f32]; 3],
    stream: bool,
) -> usize {
    let planes: [[&[[f32; LANES]]; N]; L] =
        planes.map(|light| light.map(|p| p.as_chunks::<LANES>().0));
    let out = out.map(|o| o.as_chunks_mut::<LANES>().0);
    let groups = planes
        .as_flattened()
        .iter()
        .map(|p| p.len())
        .fold(out.iter().map(|o| o.len()).min().unwrap_or(0), usize::min);
    let [r, g, b] = out.map(|o| &mut o[..groups]);
    let w = broadcast(weights);
    let zero = _mm512_setzero_ps();
    // Each light's product from 0.0 (`pixel::mat_vec`), the lights added in order.
    let rgb = |j: usize| {
        prefetch(&planes, j, N * L <= NEAR_LINEAR_PLANES);
        let mut rgb = [zero; 3];
        for (l, (w, planes)) in w.iter().zip(&planes).enumerate() {
            let s = load_group(planes, j);
            let mut acc = [zero; 3];
            for (acc, row) in acc.iter_mut().zip(w) {
                for (w, s) in row.iter().zip(&s) {
                    *acc = _mm512_add_ps(*acc, _mm512_mul_ps(*w, *s));
                }
            }
            rgb = if l == 0 { acc } else { add3(rgb, acc) };
        }
        rgb
    };
    if stream {
        // The fence follows the non-temporal stores on every way out of this block.
        let _fence = StoreFence;
        let mut out = [r, g, b].map(|o| StreamedPlane::new(o));
        for j in 0..groups {
            for (o, v) in out.iter_mut().zip(rgb(j)) {
                o.push(j, v);
            }
        }
        for o in out {
            o.finish();
        }
    } else {
        for (j, ((r, g), b)) in r.iter_mut().zip(g.iter_mut()).zip(b.iter_mut()).enumerate() {
            for (o, v) in [r, g, b].into_iter().zip(rgb(j)) {
                // SAFETY: `o` is valid for writing 16 f32; no alignment requirement.
                unsafe { _mm512_storeu_ps(o.as_mut_ptr(), v) };
            }
        }
    }
    groups * LANES
}

/// One output plane written with non-temporal stores (`vmovntps`), which need whole 64-byte
/// lines: each group's sixteen values are held until the next group's, and the sixteen that
/// fill the plane's next line go out together. The floats before its first 64-byte boundary
/// and after its last whole line are written with ordinary (masked) stores.
struct StreamedPlane<'a> {
    out: &'a mut [[f32; LANES]],
    /// Floats from the plane's start to its first 64-byte boundary, 0..16.
    skip: usize,
    /// Lanes `skip..16` of the held group, then lanes `0..skip` of the next: a line's values.
    pick: __m512i,
    /// The last group pushed.
    held: __m512,
}

impl<'a> StreamedPlane<'a> {
    #[inline]
    #[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
    fn new(out: &'a mut [[f32; LANES]]) -> StreamedPlane<'a> {
        // f32 are 4-byte aligned, so the distance to the boundary is a whole number of floats.
        let skip = out.as_ptr().cast::<f32>().align_offset(64) % LANES;
        let lanes = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
        StreamedPlane {
            out,
            skip,
            pick: _mm512_add_epi32(lanes, _mm512_set1_epi32(skip as i32)),
            held: _mm512_setzero_ps(),
        }
    }

    /// Mask of lanes `0..skip`.
    #[inline]
    fn head(&self) -> __mmask16 {
        ((1u32 << self.skip) - 1) as __mmask16
    }

    /// Group j's values (groups in order from 0): group 0's floats before the first boundary
    /// go out with an ordinary store; from group 1 on, the line from `skip + 16 · (j − 1)`.
    #[inline]
    #[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
    fn push(&mut self, j: usize, v: __m512) {
        let base = self.out.as_mut_ptr().cast::<f32>();
        if j == 0 {
            // SAFETY: the masked store writes lanes 0..skip (skip < 16) of group 0, inside the
            // plane; no alignment requirement.
            unsafe { _mm512_mask_storeu_ps(base, self.head(), v) };
        } else {
            let line = _mm512_permutex2var_ps(self.held, self.pick, v);
            debug_assert!(self.skip + LANES * j <= LANES * self.out.len());
            // SAFETY: floats skip + 16(j − 1) .. skip + 16j lie inside the plane, since group j
            // exists and skip < 16, and their start is the plane's first 64-byte boundary plus
            // a multiple of 64 bytes, the alignment `vmovntps` needs.
            unsafe { _mm512_stream_ps(base.add(self.skip + LANES * (j - 1)), line) };
        }
        self.held = v;
    }

    /// The last group's floats after the last whole line, with an ordinary store.
    #[inline]
    #[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
    fn finish(self) {
        let Some(last) = self.out.len().checked_sub(1) else {
            return;
        };
        let rest = !self.head();
        // SAFETY: the masked store writes lanes skip..16 of the last group, inside the plane;
        // no alignment requirement.
        unsafe { _mm512_mask_storeu_ps(self.out[last].as_mut_ptr(), rest, self.held) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every f32 from 0 to 1 through the encoder: where it does not flag a value, its code
    /// value is the table's (the correctly rounded one). Also counts the flagged values.
    #[test]
    fn the_vector_encoder_is_exact_where_it_does_not_flag() {
        if !available() {
            crate::test_inputs::skipped(
                "avx512",
                "the AVX-512 encoder",
                "this CPU has no AVX-512 (F, BW, VBMI)",
            );
            return;
        }
        // SAFETY: the CPU has the features (checked above).
        let (flagged, wrong) = unsafe { every_f32_to_one() };
        assert_eq!(wrong, 0, "unflagged values with a wrong code value");
        // 0.022 % measured: a change that flags many more values is slower, not wrong; this
        // bound (0.05 %) notices it.
        assert!(flagged < 0x3f80_0001 / 2000, "{flagged} values flagged");
    }

    /// `f(first, outputs, flagged)` for every `stride`-th group of sixteen consecutive f32 from
    /// 0 up to 1 (the last group reaches a little past 1.0, `0x3f80_0000`: those clamp to 1), run
    /// through the encoder as the red channel.
    #[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
    fn for_groups_to_one(stride: u32, mut f: impl FnMut(u32, &[i32; LANES], __mmask16)) {
        let enc = Encoder::new();
        let lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
        let mut out = [0i32; LANES];
        let mut first = 0u32;
        while first <= 0x3f80_0000 {
            let x = _mm512_castsi512_ps(_mm512_add_epi32(_mm512_set1_epi32(first as i32), lane));
            let ([i, _, _], flagged) = enc.outputs([x, _mm512_setzero_ps(), _mm512_setzero_ps()]);
            // SAFETY: `out` is valid for writing 16 i32; no alignment requirement.
            unsafe { _mm512_storeu_si512(out.as_mut_ptr().cast(), i) };
            f(first, &out, flagged);
            first += stride * LANES as u32;
        }
    }

    #[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
    fn every_f32_to_one() -> (u64, u64) {
        let (mut flagged, mut wrong) = (0u64, 0u64);
        for_groups_to_one(1, |first, out, f| {
            for (l, i) in out.iter().enumerate() {
                let want = crate::srgb8_from_linear(f32::from_bits(first + l as u32));
                if f & (1 << l) != 0 {
                    flagged += 1;
                } else if (i >> 16) > 255 || (i >> 16) as u8 != want {
                    wrong += 1;
                }
            }
        });
        (flagged, wrong)
    }

    /// The encoder's error against the exact curve (in f64), in its output unit, on every 61st
    /// group of sixteen f32 from 0 to 1 (17 million values): below W − 1, the margin the
    /// argument in the module's documentation needs. (The exhaustive test above checks the
    /// consequence on every f32.)
    #[test]
    fn the_encoders_error_stays_inside_its_window() {
        if !available() {
            crate::test_inputs::skipped(
                "avx512",
                "the AVX-512 encoder",
                "this CPU has no AVX-512 (F, BW, VBMI)",
            );
            return;
        }
        // SAFETY: the CPU has the features (checked above).
        let worst = unsafe { largest_error(61) };
        std::eprintln!("largest error: {worst:.2} (window {WINDOW})");
        assert!(worst <= f64::from(WINDOW - 1), "{worst}");
    }

    #[target_feature(enable = "avx512f,avx512bw,avx512vbmi")]
    fn largest_error(stride: u32) -> f64 {
        let mut worst = 0.0f64;
        for_groups_to_one(stride, |first, out, _| {
            for (l, i) in out.iter().enumerate() {
                let x = f64::from(f32::from_bits(first + l as u32).min(1.0));
                let curve = if x < f64::from(LINEAR_BELOW) {
                    12.92 * x
                } else {
                    1.055 * libm::pow(x, 1.0 / 2.4) - 0.055
                };
                let f = UNIT * (255.0 * curve + 0.5) + f64::from(WINDOW);
                worst = worst.max((f64::from(*i) - f).abs());
            }
        });
        worst
    }

    #[test]
    fn the_constants_are_what_their_formulas_give() {
        // P against libm: the interpolant's values at its own nodes are m^(5/12) (f32 rounding
        // of the coefficients: within 1e-6), and its largest error on 1..2 is 1.8e-6.
        let p = |m: f64| {
            P.iter()
                .rev()
                .fold(0.0f64, |acc, c| acc * m + f64::from(*c))
        };
        let mut worst = 0.0f64;
        for k in 0..=10_000 {
            let m = 1.0 + f64::from(k) / 10_000.0;
            worst = worst.max((p(m) - libm::pow(m, 5.0 / 12.0)).abs());
        }
        assert!(worst < 2.0e-6, "{worst}");
        for biased in 118..=127i32 {
            let e = f64::from(biased - 127);
            let want = UNIT * 255.0 * 1.055 * libm::pow(2.0, 5.0 * e / 12.0);
            assert_eq!(SCALE[(biased & 15) as usize], want as f32, "e = {e}");
        }
    }
}
