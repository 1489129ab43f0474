//! The per-pixel path: one pixel's samples to `[A, C1, C2]`, XYZ, linear RGB or encoded RGB.
//!
//! Each channel is a sum of products in index order, in f32; every batch and planar loop
//! computes the same sums in the same order, so all paths give these functions' bits.

#![forbid(unsafe_code)]

use crate::{FoldedSet, WavelengthSet};

/// The f32 error budget of an N-term weighted sum whose terms have absolute sum `abs_sum`
/// (`Σ |w_i · s_i|`): `(N + 1) · f32::EPSILON · abs_sum + N · 2⁻¹⁵⁰`. This is the stated accuracy
/// of [`WavelengthSet::ac1c2`] and [`FoldedSet::linear_rgb`] against the exact f64 sum; the tests
/// assert it. Computed in f64; `abs_sum` NaN or infinite gives NaN or infinity.
pub fn f32_budget(n: usize, abs_sum: f64) -> f64 {
    const HALF_SUBNORMAL: f64 = 7.006_492_321_624_085e-46; // 2^-150
    (n as f64 + 1.0) * f64::from(f32::EPSILON) * abs_sum + n as f64 * HALF_SUBNORMAL
}

impl<const N: usize> WavelengthSet<N> {
    /// `[A, C1, C2]` from samples of a spectrum at [`wavelengths_nm`](Self::wavelengths_nm):
    /// the 3×N product `weights · samples`, in f32.
    ///
    /// Never panics. Each output is a plain sum of products over all N samples, so IEEE rules
    /// apply: a NaN sample makes every channel NaN, and an infinite sample makes every channel
    /// ±Inf or NaN (NaN where its weight is 0, since 0 · ∞ = NaN, or where infinities of both
    /// signs meet); subnormal and negative samples are used as they are; products or sums beyond
    /// `f32::MAX` overflow to ±Inf. With N = 0 (no samples) it is `[0.0, 0.0, 0.0]`.
    ///
    /// # Accuracy
    /// For finite samples whose products do not overflow, each channel is within
    /// [`f32_budget`](crate::f32_budget)`(N, Σ_i |w_i · s_i|)` of the exact sum with the f64
    /// weights of the derivation: the weights' rounding to f32 (½ ε each), N products (½ ε
    /// each) and N − 1 additions (½ ε each, times the running sum), ε = `f32::EPSILON`, plus
    /// N half-units of the smallest subnormal for products that underflow.
    ///
    /// The budget is absolute (relative to Σ|w_i · s_i|) and holds for every finite input with
    /// Σ|w_i · s_i| · (1 + (N + 1)ε) < `f32::MAX`: ±`f32::MAX` in some samples, subnormals,
    /// mixtures of 1e38 and 1e-45, and samples that make C1 or C2 cancel. Under cancellation the
    /// relative error of a signed channel can be large (tests/extremes.rs measures up to 7e3 for
    /// C1 at the rounding level, and at most 0.35 of the budget over 194 985 extreme inputs).
    /// Beyond that bound a channel may overflow to ±Inf or NaN.
    #[inline]
    pub fn ac1c2(&self, samples: &[f32; N]) -> [f32; 3] {
        mat_vec(self.weights_ref(), samples)
    }

    /// `[X, Y, Z]` from samples: [`ac1c2`](Self::ac1c2) followed by
    /// [`AC1C2_TO_XYZ`](crate::tables::AC1C2_TO_XYZ). XYZ are in the units of the weights (dλ in
    /// nm): a spectrum of constant 1 has Y ≈ [`UNIT_SPECTRUM_Y`](crate::tables::UNIT_SPECTRUM_Y).
    /// IEEE arithmetic, as [`ac1c2`](Self::ac1c2); `[0.0, 0.0, 0.0]` with N = 0.
    #[inline]
    pub fn xyz(&self, samples: &[f32; N]) -> [f32; 3] {
        crate::xyz_from_ac1c2(self.ac1c2(samples))
    }
}

impl<const N: usize> FoldedSet<N> {
    /// Linear RGB from samples at [`wavelengths_nm`](Self::wavelengths_nm).
    ///
    /// Never panics. IEEE arithmetic, as [`WavelengthSet::ac1c2`]: a NaN sample makes every channel
    /// NaN, an infinite one makes every channel ±Inf or NaN, subnormal and negative samples are
    /// used as they are, products or sums beyond `f32::MAX` overflow to ±Inf. Out-of-gamut colours
    /// have channels below 0 or above 1; see [`Display::map_gamut`](crate::Display::map_gamut).
    /// With N = 0 (no samples) it is `[0.0, 0.0, 0.0]`.
    ///
    /// # Accuracy
    /// As [`WavelengthSet::ac1c2`]: each channel within
    /// [`f32_budget`](crate::f32_budget)`(N, Σ_i |w_i · s_i|)` of the exact product with the f64
    /// folded weights. The colour matrices were multiplied into the weights in f64, so they add
    /// no f32 error of their own.
    #[inline]
    pub fn linear_rgb(&self, samples: &[f32; N]) -> [f32; 3] {
        mat_vec(self.weights_ref(), samples)
    }

    /// Linear RGB of a reflectance under a light, for a set for radiances
    /// ([`Samples::Radiance`](crate::Samples::Radiance)): [`linear_rgb`](Self::linear_rgb) of
    /// the products `reflectance[i] · light[i]`. `light` is a light's samples at this set's nodes
    /// as the scene bakes them, `tables::lights::<LIGHT>_AT_<SET>`: fitted so that a reflectance
    /// of 1 gives the light's own white at Y = 1 (the white a folded set for that light gives),
    /// and so that a spiky light's lines between the nodes are accounted for, which the light's
    /// values at the nodes would miss. Relighting one material under several lights is one call
    /// per light with the same `reflectance` (for example an RGB texel upsampled by the set's
    /// map, [`Upsampling::reflectance`](crate::Upsampling::reflectance)).
    ///
    /// For a set with a light folded in, the product is a reflectance under two lights: not a
    /// meaningful colour. Never panics; IEEE arithmetic as [`linear_rgb`](Self::linear_rgb)
    /// (a NaN in either argument makes every channel NaN, an infinity ±Inf or NaN, a product
    /// beyond `f32::MAX` overflows).
    #[inline]
    pub fn linear_rgb_under(&self, light: &[f32; N], reflectance: &[f32; N]) -> [f32; 3] {
        self.linear_rgb(&core::array::from_fn(|i| reflectance[i] * light[i]))
    }

    /// Samples → gamut-mapped, encoded 8-bit RGB with the set's [`display`](Self::display).
    /// NaN anywhere → black; see [`Display::encode_u8`](crate::Display::encode_u8). With N = 0,
    /// the display's encoding of black (`[0, 0, 0]` for every built-in transfer function).
    ///
    /// The bytes of `self.display().encode_u8(mapping, self.linear_rgb(samples))`. Each channel's
    /// sum starts from its first product instead of 0.0 (one addition less), which differs
    /// only where the sum is an exact zero (−0.0 instead of +0.0, and both encode to 0). On
    /// x86-64, the sRGB curve with `Clip` runs with the three channels in one SSE2 register:
    /// the same f32 operations, so the same bytes.
    #[inline]
    pub fn encode_u8(&self, mapping: crate::GamutMapping, samples: &[f32; N]) -> [u8; 3] {
        // x86-64: the product and the encoder with the channels in the lanes of one SSE2
        // register (the same operations, so the same bytes; see `simd`).
        #[cfg(target_arch = "x86_64")]
        if self.display_ref().is_srgb_clip(mapping) {
            return crate::simd::sse2::encode_srgb8(self.weights_ref(), samples);
        }
        self.display_ref()
            .encode_u8(mapping, mat_vec_for_encoding(self.weights_ref(), samples))
    }

    /// As [`encode_u8`](Self::encode_u8), 16 bits (N = 0 included).
    #[inline]
    pub fn encode_u16(&self, mapping: crate::GamutMapping, samples: &[f32; N]) -> [u16; 3] {
        self.display_ref()
            .encode_u16(mapping, self.linear_rgb(samples))
    }
}

/// `weights · samples` for a 3×N matrix, accumulated in index order in f32.
///
/// One pass over the samples with the three rows side by side (each row's sum is still
/// 0 + w₀s₀ + w₁s₁ + … in that order): where the loop is not unrolled (opt-level "s" on a
/// microcontroller) its overhead is paid N times instead of 3N.
#[inline]
pub(crate) fn mat_vec<const N: usize>(weights: &[[f32; N]; 3], samples: &[f32; N]) -> [f32; 3] {
    let [w0, w1, w2] = weights;
    let (mut a, mut b, mut c) = (0.0f32, 0.0f32, 0.0f32);
    for i in 0..N {
        let s = samples[i];
        a += w0[i] * s;
        b += w1[i] * s;
        c += w2[i] * s;
    }
    [a, b, c]
}

/// [`mat_vec`] starting each sum from its first product instead of 0.0: one addition less on
/// each channel's chain, and the same value except that an exact zero may come out as −0.0
/// where `mat_vec` gives +0.0 (0.0 + (−0.0) = +0.0). Every encoder maps both zeros to code 0,
/// so the encoded colour is the same.
#[inline]
pub(crate) fn mat_vec_for_encoding<const N: usize>(
    weights: &[[f32; N]; 3],
    samples: &[f32; N],
) -> [f32; 3] {
    if N == 0 {
        return [0.0; 3];
    }
    let [w0, w1, w2] = weights;
    let s = samples[0];
    let (mut a, mut b, mut c) = (w0[0] * s, w1[0] * s, w2[0] * s);
    for i in 1..N {
        let s = samples[i];
        a += w0[i] * s;
        b += w1[i] * s;
        c += w2[i] * s;
    }
    [a, b, c]
}
