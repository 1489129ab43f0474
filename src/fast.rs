//! Fast transfer functions with micromath's approximations (feature `micromath`).

use micromath::F32Ext;

use crate::display::clamp01;
use crate::TransferFunction;

/// The largest difference between [`TransferFunction::encode_fast`] and
/// [`TransferFunction::encode`] for `Srgb` and `Gamma(γ)` with γ in 1.0..=3.0, over every f32 in
/// 0..=1, in encoded units (1/255 = 0.0039 is one 8-bit step). Asserted by the tests.
pub const ENCODE_FAST_MAX_ERROR: f32 = 0.005;

impl TransferFunction {
    /// [`encode`](Self::encode) with micromath's `powf` approximation: faster, and within
    /// [`ENCODE_FAST_MAX_ERROR`] of the exact curve for sRGB and gammas 1 to 3. Lookup tables and
    /// `Linear` are exact already. Same input handling: NaN → 0, ≤ 0 → 0, ≥ 1 → 1; output in
    /// 0..=1; never panics.
    pub fn encode_fast(&self, c: usize, linear: f32) -> f32 {
        let x = clamp01(linear);
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
