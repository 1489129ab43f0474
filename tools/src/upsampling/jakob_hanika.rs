//! Jakob and Hanika (2019), *A Low-Dimensional Function Space for Efficient Spectral
//! Upsampling*: a reflectance `s(λ) = S(c₀x² + c₁x + c₂)`, x = (λ − 360 nm) / 470 nm and
//! `S(z) = ½ + z / (2√(1 + z²))`, whose three coefficients are fitted per colour so that its
//! CIELAB under the colour space's illuminant (D65 for sRGB) matches the colour's. pbrt-v4's
//! `rgb2spec_opt` fits them by Gauss-Newton on the CIELAB residual with a central-difference
//! Jacobian (step 1e-4), at most 15 iterations, stopping below a squared residual of 1e-6,
//! scaling the coefficients back when one exceeds 200, and walks each colour in from a
//! neighbouring one already fitted; it stores the coefficients on a 64³ table that renderers
//! interpolate. Here each colour is fitted directly, walking in from the grey of the same mean
//! in 8 steps with the same Gauss-Newton iteration: the method's own accuracy, without the
//! table's interpolation.

use nalgebra::{Matrix3, Vector3};
use spectral_quadrature_generator::Derivation;
use spectral_quadrature_math::lab_from_xyz;
use spectral_quadrature_spectra::Curve;

use crate::Error;

/// The fit, precomputed for one display under D65: sRGB as pbrt-v4 uses it.
#[derive(Debug, Clone)]
pub struct JakobHanika {
    /// The 1 nm grid, nm.
    grid_nm: Vec<f64>,
    /// White-balanced RGB of a unit reflectance at each grid point, rows R, G, B.
    rgb_weights: [Vec<f64>; 3],
    /// RGB → XYZ of the display, for CIELAB.
    rgb_to_xyz: [[f64; 3]; 3],
}

/// The sigmoid that keeps the spectrum in (0, 1).
pub fn sigmoid(z: f64) -> f64 {
    if z.is_infinite() {
        return if z > 0.0 { 1.0 } else { 0.0 };
    }
    0.5 + z / (2.0 * (1.0 + z * z).sqrt())
}

/// The spectrum of coefficients `c` at `nm`.
pub fn spectrum(c: [f64; 3], nm: f64) -> f64 {
    let x = (nm - 360.0) / 470.0;
    sigmoid((c[0] * x + c[1]) * x + c[2])
}

impl JakobHanika {
    /// For sRGB under D65 on the derivation's observer, every 1 nm.
    pub fn srgb(d: &Derivation) -> Result<JakobHanika, Error> {
        let (_, m) = d.display("SRGB")?;
        let (grid_nm, rgb_weights) = super::srgb_weights(d)?;
        Ok(JakobHanika {
            grid_nm,
            rgb_weights,
            rgb_to_xyz: m.rgb_to_xyz,
        })
    }

    fn lab(&self, rgb: [f64; 3]) -> [f64; 3] {
        let m = &self.rgb_to_xyz;
        let xyz = |v: [f64; 3]| [0, 1, 2].map(|r| (0..3).map(|k| m[r][k] * v[k]).sum::<f64>());
        lab_from_xyz(xyz(rgb), xyz([1.0; 3]))
    }

    /// The white-balanced RGB of the spectrum of coefficients `c`.
    pub fn rgb(&self, c: [f64; 3]) -> [f64; 3] {
        let s: Vec<f64> = self.grid_nm.iter().map(|&nm| spectrum(c, nm)).collect();
        [0, 1, 2].map(|k| self.rgb_weights[k].iter().zip(&s).map(|(w, v)| w * v).sum())
    }

    fn residual(&self, c: [f64; 3], target: [f64; 3]) -> [f64; 3] {
        let (a, b) = (self.lab(target), self.lab(self.rgb(c)));
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }

    /// rgb2spec_opt's Gauss-Newton from `c` toward `target`.
    fn gauss_newton(&self, target: [f64; 3], c: &mut [f64; 3]) {
        const STEP: f64 = 1e-4;
        for _ in 0..15 {
            let r = self.residual(*c, target);
            let mut j = Matrix3::zeros();
            for k in 0..3 {
                let (mut lo, mut hi) = (*c, *c);
                lo[k] -= STEP;
                hi[k] += STEP;
                let (r0, r1) = (self.residual(lo, target), self.residual(hi, target));
                for row in 0..3 {
                    j[(row, k)] = (r1[row] - r0[row]) / (2.0 * STEP);
                }
            }
            let Some(x) = j.lu().solve(&Vector3::new(r[0], r[1], r[2])) else {
                return;
            };
            for k in 0..3 {
                c[k] -= x[k];
            }
            let max = c[0].max(c[1]).max(c[2]);
            if max > 200.0 {
                for v in c.iter_mut() {
                    *v *= 200.0 / max;
                }
            }
            if r.iter().map(|v| v * v).sum::<f64>() < 1e-6 {
                return;
            }
        }
    }

    /// The coefficients for white-balanced linear `rgb` (clamped to [0, 1]).
    pub fn fit(&self, rgb: [f64; 3]) -> [f64; 3] {
        let t = rgb.map(|v| v.clamp(0.0, 1.0));
        let mean = (t[0] + t[1] + t[2]) / 3.0;
        // The grey of the same mean: a flat spectrum, the sigmoid's inverse at that level.
        let g = mean.clamp(1e-4, 1.0 - 1e-4);
        let z = (2.0 * g - 1.0) / (1.0 - (2.0 * g - 1.0).powi(2)).sqrt();
        let mut c = [0.0, 0.0, z];
        const STEPS: usize = 8;
        for s in 1..=STEPS {
            let f = s as f64 / STEPS as f64;
            let step = [0, 1, 2].map(|k| mean + f * (t[k] - mean));
            self.gauss_newton(step, &mut c);
        }
        c
    }

    /// The fitted spectrum of `rgb` at `wavelengths_nm`.
    pub fn at(&self, rgb: [f64; 3], wavelengths_nm: &[f64]) -> Vec<f64> {
        let c = self.fit(rgb);
        wavelengths_nm.iter().map(|&nm| spectrum(c, nm)).collect()
    }
}

/// A curve of the fitted spectrum on the 1 nm grid, for plots.
pub fn curve(jh: &JakobHanika, rgb: [f64; 3], name: &str) -> Curve {
    let c = jh.fit(rgb);
    Curve {
        name: name.into(),
        wavelengths: jh.grid_nm.clone(),
        values: jh.grid_nm.iter().map(|&nm| spectrum(c, nm)).collect(),
    }
}
