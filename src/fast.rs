//! Fast transfer functions with micromath's approximations (feature `micromath`).

#![forbid(unsafe_code)]

use micromath::F32Ext;

use crate::encode::clamp01;
use crate::TransferFunction;

/// The largest difference between [`TransferFunction::encode_fast`] and
/// [`TransferFunction::encode`] for `Srgb` and `Gamma(γ)` with γ in 1.0..=3.0, in encoded units
/// (one 8-bit step is 1/255 = 0.0039). Asserted by the tests over about 12 million inputs in
/// 0..=1.
///
/// micromath's `powf` is a coarse approximation, so this bound is large: measured maxima are
/// 0.0858 for γ = 1.0, 0.0545 for 1.8, 0.0460 for 2.2, 0.0427 for 2.4, 0.0351 for 3.0 and
/// 0.0450 for sRGB (all near x ≈ 0.77), that is 9 to 22 steps of 8-bit output. Use
/// `encode_fast` for previews and indicators, not for final images.
pub const ENCODE_FAST_MAX_ERROR: f32 = 0.09;

impl TransferFunction {
    /// [`encode`](Self::encode) with micromath's `powf` approximation: faster, and within
    /// [`ENCODE_FAST_MAX_ERROR`] (a coarse 0.09) of the exact curve for sRGB and gammas 1 to 3.
    /// Lookup tables and `Linear` are exact already. Same input handling: NaN → exactly 0,
    /// ≤ 0 → exactly 0, ≥ 1 → exactly 1; output in 0..=1; never panics.
    pub fn encode_fast(&self, c: crate::Rgb, linear: f32) -> f32 {
        let x = clamp01(linear);
        if x == 0.0 || x == 1.0 {
            return x;
        }
        let e = match *self {
            TransferFunction::Srgb => {
                if x <= 0.003_130_8 {
                    12.92 * x
                } else {
                    1.055 * F32Ext::powf(x, 1.0 / 2.4) - 0.055
                }
            }
            TransferFunction::Gamma(g) if g.is_finite() && g > 0.0 => F32Ext::powf(x, 1.0 / g),
            _ => return self.encode(c, x),
        };
        clamp01(e)
    }
}
