//! Two peers that build spectra from a few smooth spectra of given colours, each derived here
//! by its paper's recipe on the crate's observer: the smoothest spectra (least squares of first
//! differences) in [0, 1] whose white-balanced sRGB under D65 is the given colour, solved with
//! the box programme of the crate's upsampling ([`spectral_quadrature_generator::upsampling::nearest_in_box`]).
//!
//! - [`MallettYuksel`]: Mallett and Yuksel (2019), *Spectral Primary Decomposition for
//!   Rendering with sRGB Reflectance*: three basis spectra, red, green and blue, that sum to 1
//!   at every wavelength (so white is 1) and whose colours are the sRGB primaries; a colour is
//!   `r·B_r + g·B_g + b·B_b`, in [0, 1] for every RGB in the cube. Knots every 10 nm, linear in
//!   between.
//! - [`Smits`]: Smits (1999), *An RGB-to-Spectrum Conversion for Reflectances*: white, cyan,
//!   magenta, yellow, red, green and blue spectra of 10 piecewise-constant bins over
//!   380-720 nm (the last bin held beyond); a colour is the smallest channel's white, plus the
//!   secondary and primary that make up the rest.

use spectral_quadrature_generator::upsampling::nearest_in_box;
use spectral_quadrature_generator::Derivation;

use crate::Error;

/// How knot values make a spectrum.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Knots {
    /// Linear between knots, the end values held beyond.
    Linear,
    /// Each wavelength takes the nearest knot's value.
    Nearest,
}

/// The weight of knot `j` at `nm`.
fn basis(knots: &[f64], kind: Knots, j: usize, nm: f64) -> f64 {
    let k = knots.len();
    match kind {
        Knots::Nearest => {
            let nearest = (0..k)
                .min_by(|&a, &b| (knots[a] - nm).abs().total_cmp(&(knots[b] - nm).abs()))
                .unwrap_or(0);
            f64::from(u8::from(nearest == j))
        }
        Knots::Linear => {
            if nm <= knots[0] {
                return f64::from(u8::from(j == 0));
            }
            if nm >= knots[k - 1] {
                return f64::from(u8::from(j == k - 1));
            }
            let i = knots.partition_point(|&l| l <= nm) - 1;
            let t = (nm - knots[i]) / (knots[i + 1] - knots[i]);
            if j == i {
                1.0 - t
            } else if j == i + 1 {
                t
            } else {
                0.0
            }
        }
    }
}

/// The value at `nm` of a spectrum given by knot values.
fn value(knots: &[f64], kind: Knots, values: &[f64], nm: f64) -> f64 {
    (0..knots.len())
        .map(|j| basis(knots, kind, j, nm) * values[j])
        .sum()
}

/// The smoothest spectra (one per target colour) on `knots`, in [0, 1], with the targets'
/// white-balanced sRGB under D65; `sum_to_one`: the spectra also sum to 1 at every knot.
fn smoothest(
    d: &Derivation,
    knots: &[f64],
    kind: Knots,
    targets: &[[f64; 3]],
    sum_to_one: bool,
) -> Result<Vec<Vec<f64>>, Error> {
    let (grid, w) = super::srgb_weights(d)?;
    let k = knots.len();
    let s = targets.len();
    // The colour of knot j's basis function, per channel.
    let h: Vec<[f64; 3]> = (0..k)
        .map(|j| {
            [0, 1, 2].map(|c| {
                grid.iter()
                    .zip(&w[c])
                    .map(|(&nm, wc)| wc * basis(knots, kind, j, nm))
                    .sum::<f64>()
            })
        })
        .collect();
    let mut rows = Vec::new();
    let mut rhs = Vec::new();
    for (t, target) in targets.iter().enumerate() {
        for c in 0..3 {
            let mut row = vec![0.0; k * s];
            for j in 0..k {
                row[t * k + j] = h[j][c];
            }
            let norm = row.iter().map(|v| v * v).sum::<f64>().sqrt();
            rows.push(row.iter().map(|v| v / norm).collect::<Vec<f64>>());
            rhs.push(target[c] / norm);
        }
    }
    if sum_to_one {
        for j in 0..k {
            let mut row = vec![0.0; k * s];
            for t in 0..s {
                row[t * k + j] = 1.0;
            }
            let norm = (s as f64).sqrt();
            rows.push(row.iter().map(|v| v / norm).collect());
            rhs.push(1.0 / norm);
        }
    }
    // Smoothness: first differences, weighted well below the colours (which must hold) and well
    // above the pull toward the previous iterate (which only breaks ties).
    const SMOOTHNESS: f64 = 3e-3;
    for t in 0..s {
        for j in 0..k - 1 {
            let mut row = vec![0.0; k * s];
            row[t * k + j] = -SMOOTHNESS;
            row[t * k + j + 1] = SMOOTHNESS;
            rows.push(row);
            rhs.push(0.0);
        }
    }
    // Proximal iterations: each pulls toward the previous solution, so the pull fades and the
    // smoothest spectra remain.
    let mut u: Vec<f64> = targets
        .iter()
        .flat_map(|t| {
            let mean = if sum_to_one {
                1.0 / s as f64
            } else {
                (t[0] + t[1] + t[2]) / 3.0
            };
            std::iter::repeat_n(mean, k)
        })
        .collect();
    for _ in 0..3 {
        u = nearest_in_box(&u, &rows, &rhs)?.x;
    }
    Ok((0..s).map(|t| u[t * k..(t + 1) * k].to_vec()).collect())
}

/// Mallett and Yuksel's three basis spectra, derived for sRGB under D65.
#[derive(Debug, Clone)]
pub struct MallettYuksel {
    /// Knots, nm.
    pub knots: Vec<f64>,
    /// The red, green and blue basis spectra at the knots.
    pub basis: [Vec<f64>; 3],
}

impl MallettYuksel {
    /// Derives the basis on knots every 10 nm over the derivation's range.
    pub fn srgb(d: &Derivation) -> Result<MallettYuksel, Error> {
        let [lo, hi] = d.settings.range_nm;
        let n = ((hi - lo) / 10.0).round() as usize;
        let knots: Vec<f64> = (0..=n).map(|i| lo + 10.0 * i as f64).collect();
        let targets = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let b = smoothest(d, &knots, Knots::Linear, &targets, true)?;
        Ok(MallettYuksel {
            knots,
            basis: [b[0].clone(), b[1].clone(), b[2].clone()],
        })
    }

    /// The spectrum of `rgb` (clamped to [0, 1]) at `wavelengths_nm`.
    pub fn at(&self, rgb: [f64; 3], wavelengths_nm: &[f64]) -> Vec<f64> {
        let t = rgb.map(|v| v.clamp(0.0, 1.0));
        wavelengths_nm
            .iter()
            .map(|&nm| {
                (0..3)
                    .map(|c| t[c] * value(&self.knots, Knots::Linear, &self.basis[c], nm))
                    .sum()
            })
            .collect()
    }
}

/// Smits' seven spectra, derived for sRGB under D65.
#[derive(Debug, Clone)]
pub struct Smits {
    /// The bins' centres, nm: 10 over 380-720 nm.
    pub knots: Vec<f64>,
    /// White, cyan, magenta, yellow, red, green, blue at the bins.
    pub spectra: [Vec<f64>; 7],
}

impl Smits {
    /// Derives the seven spectra.
    pub fn srgb(d: &Derivation) -> Result<Smits, Error> {
        let knots: Vec<f64> = (0..10).map(|i| 380.0 + 340.0 * i as f64 / 9.0).collect();
        let targets = [
            [1.0, 1.0, 1.0],
            [0.0, 1.0, 1.0],
            [1.0, 0.0, 1.0],
            [1.0, 1.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let mut spectra: [Vec<f64>; 7] = Default::default();
        for (slot, t) in spectra.iter_mut().zip(targets) {
            *slot = smoothest(d, &knots, Knots::Nearest, &[t], false)?.remove(0);
        }
        Ok(Smits { knots, spectra })
    }

    /// The spectrum of `rgb` (clamped to [0, 1]) at `wavelengths_nm`, by Smits' rule.
    pub fn at(&self, rgb: [f64; 3], wavelengths_nm: &[f64]) -> Vec<f64> {
        let [r, g, b] = rgb.map(|v| v.clamp(0.0, 1.0));
        let [white, cyan, magenta, yellow, red, green, blue] = [0, 1, 2, 3, 4, 5, 6];
        // (weight, spectrum) pairs.
        let parts: [(f64, usize); 3] = if r <= g && r <= b {
            if g <= b {
                [(r, white), (g - r, cyan), (b - g, blue)]
            } else {
                [(r, white), (b - r, cyan), (g - b, green)]
            }
        } else if g <= r && g <= b {
            if r <= b {
                [(g, white), (r - g, magenta), (b - r, blue)]
            } else {
                [(g, white), (b - g, magenta), (r - b, red)]
            }
        } else if r <= g {
            [(b, white), (r - b, yellow), (g - r, green)]
        } else {
            [(b, white), (g - b, yellow), (r - g, red)]
        };
        wavelengths_nm
            .iter()
            .map(|&nm| {
                parts
                    .iter()
                    .map(|&(w, k)| w * value(&self.knots, Knots::Nearest, &self.spectra[k], nm))
                    .sum()
            })
            .collect()
    }
}
