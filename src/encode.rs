//! A branch-free sRGB 8-bit encoder: one table lookup and one addition per value, correctly
//! rounded.
//!
//! For each code value k = 1..=255 the exact sRGB curve (IEC 61966-2-1, in f64) crosses the
//! rounding boundary k − ½ at one linear value; the smallest f32 at or above it is k's
//! *threshold*. An f32 in 2⁻¹³..=1 is split by its top bits (exponent and 7 mantissa bits) into
//! 1 665 segments, each narrower than the distance between two thresholds, so each holds at most
//! one. A segment's entry holds the code value at its start and, in 16 bits, how far into the
//! segment (in the f32's low 16 bits) its threshold lies, arranged so that adding the f32's
//! position carries into the code value exactly at the threshold. The table (2 048 entries,
//! 8 kB) is built by `const fn` from the formula, so no value in it was copied by hand;
//! `tests/planar.rs` recomputes every threshold with `libm::pow` in f64 and checks the encoder
//! against the exact curve for every f32 from 2⁻¹³ to 1.

/// Bits of 2⁻¹³, the lower clamp: the exact curve stays below ½ step up to 1.5e-4 > 2⁻¹³.
pub(crate) const LO_BITS: u32 = (127 - 13) << 23;
/// 2⁻¹³.
pub(crate) const LO: f32 = f32::from_bits(LO_BITS);
/// The top 16 bits of [`LO`] and of 1.0: an f32 clamped to `LO..=1` has its segment at
/// `(bits >> 16) − FIRST_TOP`. And since `LO_BITS · 2⁸` is a multiple of 2³², the position
/// term of [`lookup`], `(bits − LO_BITS) · 2⁸`, equals `bits · 2⁸` (mod 2³²): the vector paths
/// index by the top bits and add `bits << 8`, with no subtraction.
pub(crate) const FIRST_TOP: u32 = LO_BITS >> 16;
/// See [`FIRST_TOP`].
pub(crate) const LAST_TOP: u32 = 0x3f80_0000 >> 16;
const _: () =
    assert!(LO_BITS.wrapping_shl(8) == 0 && (LAST_TOP - FIRST_TOP) as usize == SEGMENTS - 1);
/// Segments per octave: 2⁷, indexed by the top 7 mantissa bits.
const PER_OCTAVE: usize = 128;
/// 13 octaves from 2⁻¹³ up to 1, and one segment for exactly 1.0.
const SEGMENTS: usize = 13 * PER_OCTAVE + 1;
/// Table entries: a power of two, so that masking the index keeps it in range without a check.
pub(crate) const TABLE_LEN: usize = 2048;

/// The largest difference, per channel in 8-bit steps, between the fast sRGB paths
/// ([`srgb8_from_linear`] and [`FoldedSet::encode_u8_planar_to_interleaved`](crate::FoldedSet::encode_u8_planar_to_interleaved)
/// with the sRGB curve and [`Clip`](crate::GamutMapping::Clip)) and the per-pixel
/// [`Display::encode_u8`](crate::Display::encode_u8): 0, since the per-pixel encoder uses the
/// same table ([`TransferFunction::encode_u8`](crate::TransferFunction::encode_u8)).
///
/// The fast encoder is the exact curve rounded to nearest: against the exact curve its error
/// is at most ½ step before rounding and 0 steps after, for every f32. Quantizing the f32
/// curve instead (`quantize_u8(TransferFunction::Srgb.encode(..))`, what the per-pixel
/// encoder did before) rounds twice: `tests/planar.rs` checks every f32 in 0..=1, and that form
/// differs on 268 of them, by 1 step. [`SRGB8_MAX_ERROR_DE76`] is what one step can cost in
/// colour.
pub const SRGB8_MAX_ERROR: u8 = 0;

/// The largest CIELAB ΔE*ab (CIE 1976, white of the sRGB display) between two 8-bit sRGB
/// colours that differ by at most [`SRGB8_MAX_ERROR`] (one step) in each channel, anywhere
/// in the cube. `tests/planar.rs` measures every such pair of the 256³ colours: at most 1.932
/// (sRGB 1, 25, 45 against 0, 26, 44: near black each step is a large part of the colour), and
/// 1.189 where only one channel differs.
pub const SRGB8_MAX_ERROR_DE76: f32 = 1.94;

/// `(k − ½) / 255` decoded with the exact sRGB curve, in f64: the linear value where the
/// encoded value crosses the boundary between code values k − 1 and k (k = 1..=255).
const fn boundary(k: usize) -> f64 {
    let v = (k as f64 - 0.5) / 255.0;
    if v <= 0.040_45 {
        v / 12.92
    } else {
        // ((v + 0.055) / 1.055)^2.4 = y² · (y²)^(1/5), the fifth root by Newton's method from
        // above (monotone, converged to the last bit well within 64 steps for y² ≥ 0.008).
        let y = (v + 0.055) / 1.055;
        let a = y * y;
        let mut r = 1.0f64;
        let mut i = 0;
        while i < 64 {
            let r4 = r * r * r * r;
            r = 0.8 * r + a / (5.0 * r4);
            i += 1;
        }
        a * r
    }
}

/// The smallest f32 at or above `t` (t positive and finite), as bits.
const fn ceil_f32_bits(t: f64) -> u32 {
    let f = t as f32;
    if (f as f64) < t {
        f.to_bits() + 1
    } else {
        f.to_bits()
    }
}

/// `THRESHOLDS[k]` (k = 1..=255): bits of the smallest f32 whose exact sRGB encoding rounds to
/// k or more. Index 0 is unused (0).
pub(crate) const THRESHOLDS: [u32; 256] = {
    let mut t = [0u32; 256];
    let mut k = 1;
    while k < 256 {
        t[k] = ceil_f32_bits(boundary(k));
        // Increasing, and all inside the table's range (checked when the crate compiles).
        assert!(t[k] > t[k - 1] && t[k] > LO_BITS && t[k] <= 0x3f80_0000);
        k += 1;
    }
    t
};

/// Segment s covers the f32 bits `LO_BITS + s · 2¹⁶ ..= LO_BITS + s · 2¹⁶ + 0xFFFF`. With
/// `code` the code value at its start and `t` the low 16 bits of the first f32 in it that
/// encodes to `code + 1` (2¹⁶ if none), its entry is
/// `code · 2²⁴ + (2¹⁶ − t mod 2¹⁶) · 2⁸ − s · 2²⁴` (mod 2³²). Adding `v · 2⁸` for
/// `v = bits − LO_BITS = s · 2¹⁶ + position` cancels the last term and carries into bit 24
/// exactly when `position ≥ t`, so the top byte of the sum is the code value. Entries past the
/// last segment repeat it (code 255): unreachable after the clamp of [`segment_bits`], but the
/// planar loop of `planar::scalar` clamps only at 2²⁷ − 1 and reads them.
pub(crate) static SEGMENT_TABLE: [u32; TABLE_LEN] = {
    let mut table = [0u32; TABLE_LEN];
    // Number of thresholds at or below the current segment's start.
    let mut code = 0usize;
    let mut s = 0;
    while s < TABLE_LEN {
        let seg = if s < SEGMENTS { s } else { SEGMENTS - 1 };
        let start = LO_BITS + ((seg as u32) << 16);
        let end = start + 0xFFFF;
        while code < 255 && THRESHOLDS[code + 1] <= start {
            code += 1;
        }
        let threshold = if code < 255 && THRESHOLDS[code + 1] <= end {
            // At most one threshold per segment (checked when the crate compiles).
            assert!(code + 2 > 255 || THRESHOLDS[code + 2] > end);
            THRESHOLDS[code + 1] - start
        } else {
            1 << 16
        };
        let carry_in = (0x1_0000 - threshold) & 0xFFFF;
        table[s] = ((code as u32) << 24)
            .wrapping_add(carry_in << 8)
            .wrapping_sub((s as u32) << 24);
        s += 1;
    }
    table
};

/// Linear light → 8-bit sRGB, correctly rounded: the exact sRGB curve (in f64) times 255,
/// rounded to nearest (halves up), for every f32. Branch-free: a clamp, a table lookup and a
/// comparison, so loops over it vectorize.
///
/// Input handling: NaN, negative values, −Inf and everything below 1.5e-4 (subnormals
/// included) give 0; values ≥ 1 (+Inf, huge) give 255. Never panics.
///
/// Within [`SRGB8_MAX_ERROR`] (1 step) of the per-pixel
/// [`TransferFunction::Srgb`](crate::TransferFunction::Srgb) encode quantized with
/// [`quantize_u8`](crate::quantize_u8), and equal to it almost everywhere.
///
/// ```
/// use spectral_quadrature::srgb8_from_linear;
/// assert_eq!(srgb8_from_linear(0.0), 0);
/// assert_eq!(srgb8_from_linear(0.215_860_5), 128); // sRGB 128 decodes to 0.2158605
/// assert_eq!(srgb8_from_linear(1.0), 255);
/// assert_eq!(srgb8_from_linear(f32::NAN), 0);
/// assert_eq!(srgb8_from_linear(f32::INFINITY), 255);
/// ```
#[inline]
pub fn srgb8_from_linear(x: f32) -> u8 {
    let bits = segment_bits(x);
    lookup(bits)
}

/// Clamps to 2⁻¹³..=1 (NaN → 2⁻¹³) and returns the f32 bits minus those of 2⁻¹³: the segment
/// in the bits from 16 up (at most 1 664), the position inside it in the low 16.
#[inline(always)]
pub(crate) fn segment_bits(x: f32) -> u32 {
    // Comparisons written so that NaN takes the `else` branch (maxps / minps semantics).
    let x = if x > LO { x } else { LO };
    let x = if x < 1.0 { x } else { 1.0 };
    x.to_bits().wrapping_sub(LO_BITS)
}

/// [`srgb8_from_linear`] for an `x` that is not NaN. A NaN gives 0 or 255 here, never a panic;
/// callers exclude it first.
///
/// On Arm this is [`srgb8_sat`], a clamp in integer arithmetic, where comparisons of floats
/// cost a transfer of flags from the FPU. Elsewhere (x86) the float clamp of [`segment_bits`]
/// is two branch-free `maxss`/`minss`, where the integer clamp compiled to branches.
#[inline(always)]
pub(crate) fn srgb8_not_nan(x: f32) -> u8 {
    if cfg!(target_arch = "arm") {
        srgb8_sat(x)
    } else {
        lookup(segment_bits(x))
    }
}

/// [`srgb8_from_linear`] for an `x` that is not NaN, clamped in integer arithmetic: on a
/// Cortex-M4F a saturating subtraction and a saturation (`qadd`, `usat`) and a bit-field extract
/// (`ubfx`) before the table.
///
/// An f32's bits read as an i32 are ordered as the f32 for every value but NaN. Their distance
/// above 2⁻¹³ (a saturating subtraction, so that negative values stay negative), clamped to
/// 0..=2²⁷ − 1, is what the lookup takes: below 2⁻¹³ (negative values, zeros, subnormals, −Inf)
/// it is 0, code 0; from 1.0 up (+Inf and huge values clamped at 2²⁷ − 1, about 8.0) it lands
/// in the segment of exactly 1.0 or past it, in the entries that repeat that segment (the
/// table has all 2¹¹ entries that 27 bits address), code 255. A NaN gives 0 or 255. The clamp
/// is written as two comparisons, which compile to `usat`; `i32::clamp` compiled to more.
#[inline(always)]
fn srgb8_sat(x: f32) -> u8 {
    let v = (x.to_bits() as i32).saturating_sub(LO_BITS as i32);
    let v = if v > 0 { v } else { 0 };
    let v = if v < (1 << 27) - 1 { v } else { (1 << 27) - 1 };
    lookup(v as u32)
}

/// The table entry for [`segment_bits`]' result `v`, to be added to `v << 8`.
#[inline(always)]
pub(crate) fn entry(v: u32) -> u32 {
    SEGMENT_TABLE[(v >> 16) as usize & (TABLE_LEN - 1)]
}

/// The table entry of an f32 in [`LO`]`..=1` from its top 16 bits, `top` (see [`FIRST_TOP`]):
/// `entry(bits − LO_BITS)`, without the mask.
///
/// # Safety
///
/// `top` must lie in `FIRST_TOP..=LAST_TOP` (it does for any f32 in `LO..=1`); then the index
/// `top − FIRST_TOP` is at most 1 664, inside the table.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(crate) unsafe fn entry_at_top(top: u32) -> u32 {
    debug_assert!((FIRST_TOP..=LAST_TOP).contains(&top));
    // SAFETY: `top − FIRST_TOP` ≤ LAST_TOP − FIRST_TOP = SEGMENTS − 1 < TABLE_LEN (the caller's
    // promise and the assertion next to `FIRST_TOP`).
    unsafe { *SEGMENT_TABLE.get_unchecked((top as usize).wrapping_sub(FIRST_TOP as usize)) }
}

/// The code value for [`segment_bits`]' result `v`: the top byte of `entry(v) + v · 2⁸`.
#[inline(always)]
pub(crate) fn lookup(v: u32) -> u8 {
    (entry(v).wrapping_add(v << 8) >> 24) as u8
}

/// Clamps to 0..=1 with NaN → 0.
#[inline]
pub(crate) fn clamp01(x: f32) -> f32 {
    if x > 0.0 {
        if x < 1.0 {
            x
        } else {
            1.0
        }
    } else {
        0.0
    }
}

/// An 8-bit encoder of the power law x^(1/γ), baked by the build script for each distinct γ
/// among the scene's displays (`tables::GAMMA_ENCODERS`): 255 thresholds, searched in 8
/// comparisons, so the result is the exact curve (in f64) times 255 rounded to nearest for
/// every f32, with no power function per value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct GammaEncoder8 {
    /// γ, as in [`TransferFunction::Gamma`](crate::TransferFunction::Gamma).
    pub(crate) gamma: f32,
    /// Entry k (1..=255): the bits of the smallest f32 x with x^(1/γ) · 255 ≥ k − ½ (in f64);
    /// entry 0 is 0. Non-decreasing.
    pub(crate) thresholds: [u32; 256],
}

impl GammaEncoder8 {
    /// The encoder of γ from its thresholds (`tables::GAMMA_ENCODERS` is made by this), or a
    /// compile-time error where they cannot be an encoder's: γ not finite and positive, entry 0
    /// not 0, or an entry below the one before. Crate-private and called only in constant
    /// evaluation, so it stops the build instead of returning an error. Unused where the scene
    /// bakes no power law.
    #[allow(dead_code)]
    pub(crate) const fn new(gamma: f32, thresholds: [u32; 256]) -> GammaEncoder8 {
        assert!(
            gamma.is_finite() && gamma > 0.0,
            "an 8-bit power-law encoder's gamma is not finite and positive"
        );
        assert!(
            thresholds[0] == 0,
            "an 8-bit power-law encoder's first threshold is not 0"
        );
        let mut k = 1;
        while k < 256 {
            assert!(
                thresholds[k] >= thresholds[k - 1],
                "an 8-bit power-law encoder's thresholds decrease"
            );
            k += 1;
        }
        GammaEncoder8 { gamma, thresholds }
    }

    /// The code value of `x` clamped to 0..=1 (NaN → 0): the number of thresholds at or below
    /// it. Branch-free binary search.
    #[inline]
    pub(crate) fn encode(&self, x: f32) -> u8 {
        let bits = clamp01(x).to_bits();
        let t = &self.thresholds;
        let mut k = 0usize;
        let mut step = 128;
        while step > 0 {
            // k + step ≤ 255: the index is in range.
            if t[(k + step) & 255] <= bits {
                k += step;
            }
            step /= 2;
        }
        k as u8
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `GammaEncoder8::new` gives a baked encoder back, and stops at thresholds that cannot be
    /// an encoder's.
    #[test]
    fn a_gamma_encoder_is_checked() {
        let baked = crate::tables::GAMMA_ENCODERS[0];
        assert_eq!(GammaEncoder8::new(baked.gamma, baked.thresholds), baked);
        let mut decreasing = baked.thresholds;
        decreasing[100] = decreasing[99] - 1;
        let mut first = baked.thresholds;
        first[0] = 1;
        for (gamma, thresholds, message) in [
            (baked.gamma, decreasing, "decrease"),
            (baked.gamma, first, "first threshold"),
            (f32::NAN, baked.thresholds, "gamma"),
            (0.0, baked.thresholds, "gamma"),
        ] {
            let panic = std::panic::catch_unwind(|| GammaEncoder8::new(gamma, thresholds))
                .expect_err(message);
            let text = panic.downcast_ref::<&str>().copied().unwrap_or_default();
            assert!(text.contains(message), "{text}");
        }
    }

    #[test]
    fn not_nan_form_equals_the_float_form() {
        let specials = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            f32::INFINITY,
            -f32::INFINITY,
            f32::MAX,
            f32::MIN,
        ];
        let small = [
            f32::from_bits(1),
            f32::MIN_POSITIVE,
            LO,
            f32::from_bits(LO_BITS - 1),
        ];
        let near_one = [
            f32::from_bits(0x3f7f_ffff),
            f32::from_bits(0x3f80_0001),
            2.0,
        ];
        for x in specials.into_iter().chain(small).chain(near_one) {
            assert_eq!(srgb8_not_nan(x), srgb8_from_linear(x), "{x:e}");
        }
        // Every 4099th f32 bit pattern of either sign that is not NaN (under Miri, which is
        // about a million times slower, every 4099 · 977th).
        let stride = if cfg!(miri) { 4099 * 977 } else { 4099 };
        for bits in (0..=u32::MAX).step_by(stride) {
            let x = f32::from_bits(bits);
            if !x.is_nan() {
                assert_eq!(srgb8_not_nan(x), srgb8_from_linear(x), "{x:e}");
            }
        }
    }

    /// `srgb8_sat` equals `srgb8_from_linear` on every f32 but NaN: all of them near the clamps,
    /// every segment of the table at both ends, and a stride through the rest. Under Miri, every
    /// `MIRI_STEP`th of each.
    #[test]
    fn saturating_clamp_equals_the_float_clamp() {
        const MIRI_STEP: usize = 4093;
        let step = if cfg!(miri) { MIRI_STEP } else { 1 };
        let same = |bits: u32| {
            let x = f32::from_bits(bits);
            if !x.is_nan() {
                assert_eq!(
                    srgb8_sat(x),
                    crate::srgb8_from_linear(x),
                    "{x:e} ({bits:#x})"
                );
            }
        };
        let one = 1.0f32.to_bits();
        for sign in [0, 0x8000_0000] {
            for bits in (0..0x20_0000)
                .chain(LO_BITS - 0x1_0000..LO_BITS + 0x1_0000)
                .step_by(step)
            {
                same(sign | bits);
            }
            for bits in (one - 0x1_0000..one + 0x1_0000).step_by(step) {
                same(sign | bits);
            }
            // Where bits − 2⁻¹³ reaches 2²⁷ (about 8.0), where it would wrap for negative
            // values, and the top (±Inf, NaN).
            for centre in [
                LO_BITS + (1 << 27),
                LO_BITS.wrapping_add(0x8000_0000),
                0x7f80_0000,
            ] {
                let top = centre.saturating_add(0x1_0000).min(0x7fff_ffff);
                for bits in (centre - 0x1_0000..=top).step_by(step) {
                    same(sign | bits);
                }
            }
        }
        for seg in (0..(1u32 << 15)).step_by(step.min(31)) {
            same(seg << 16);
            same((seg << 16) | 0xFFFF);
        }
        for bits in (0..=u32::MAX).step_by(997 * step) {
            same(bits);
        }
    }

    #[test]
    fn table_ends() {
        assert_eq!(lookup(0), 0);
        assert_eq!(lookup(0xFFFF), 0);
        assert_eq!(lookup(((SEGMENTS as u32) - 1) << 16), 255);
        assert_eq!(srgb8_from_linear(-0.0), 0);
        assert_eq!(srgb8_from_linear(f32::from_bits(0x3f7f_ffff)), 255);
    }
}
