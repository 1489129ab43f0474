//! The model behind the shared sets: a prior on the spectra a renderer samples (a Matérn 5/2
//! kernel plus the training reflectances' empirical covariance, [`Kernel`], [`LENGTH_NM`],
//! [`EMPIRICAL_WEIGHT`]), the light folded into the weights, and the linearised CIELAB metric.
//! For given samples (wavelengths, or any linear readings such as a sensor's channels)
//! [`Problem`] gives the best weights and their expected error; [`problem`] sets it up for the
//! crate's sets.

use std::string::{String, ToString};
use std::vec::Vec;

use nalgebra::DMatrix;

use crate::base::error::{Error, LightProblem};
use crate::derivation::derive::Derivation;
use crate::derivation::display;
use crate::derivation::sets::WavelengthSet;
use spectral_quadrature_spectra::{builtin_illuminant, builtin_lights, Curve, EvalSet, Spectra};

/// A stationary covariance on wavelength, `k(λ, μ) = σ² ρ(|λ − μ| / ℓ)` with unit σ² (the
/// scale cancels in the weights and in the node choice).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Kernel {
    /// Matérn ν = 5/2: `(1 + √5 d + 5d²/3) e^{−√5 d}`, d = |λ − μ| / ℓ. Twice differentiable
    /// paths, like measured reflectances.
    Matern52 {
        /// ℓ in nm.
        length_nm: f64,
    },
}

impl Kernel {
    /// ρ at a distance in nm.
    pub(crate) fn at(&self, distance_nm: f64) -> f64 {
        match *self {
            Kernel::Matern52 { length_nm } => {
                let d = 5f64.sqrt() * distance_nm.abs() / length_nm;
                (1.0 + d + d * d / 3.0) * (-d).exp()
            }
        }
    }
}

/// The nugget (white noise added to the kernel's diagonal, relative to its variance): keeps the
/// kriging system well conditioned when two nodes are 1 nm apart. 1e-6 is far below the
/// reflectance measurement noise of the data (about 1e-3) and far above f64 rounding.
pub(crate) const NUGGET: f64 = 1e-6;

/// The Matérn length of the crate's sets, nm: the maximum of the leave-one-out likelihood of the
/// CIE test colour samples over a grid of lengths and empirical-covariance weights (the unit
/// tests re-run the fit).
pub const LENGTH_NM: f64 = 60.0;

/// The empirical-covariance weight of the crate's sets, fitted with [`LENGTH_NM`].
pub const EMPIRICAL_WEIGHT: f64 = 70.0;

/// The training reflectances of the crate's sets: the CIE test colour samples (never the
/// ColorChecker, on which the report and the tests judge them).
pub const TRAINING_FILE: &str = "data/reflectance_cie_tcs.csv";

/// The precomputed problem for one light, kernel and metric: any node set's weights and
/// expected error then cost one (N+1)×(N+1) solve.
#[derive(Debug, Clone)]
pub struct Problem {
    /// The 1 nm grid, nm.
    pub grid_nm: Vec<f64>,
    /// The light on the grid, scaled to the luminance of an equal-energy spectrum of 1 (all
    /// ones for radiances).
    pub light: Vec<f64>,
    /// The light's name, `None` for radiances.
    pub light_name: Option<String>,
    /// The number of grid points.
    pub(super) g: usize,
    /// The prior covariance on the grid (row-major G×G): the kernel, plus any empirical
    /// covariance added by [`with_covariance`](Self::with_covariance).
    k: Vec<f64>,
    /// x̄ȳz̄ · L · dλ on the grid.
    f: [Vec<f64>; 3],
    /// `K Fᵀ` per grid point.
    kf: Vec<[f64; 3]>,
    /// `F K Fᵀ`.
    fkf: [[f64; 3]; 3],
    /// `F 1`: the white.
    f1: [f64; 3],
    /// The linearised CIELAB metric.
    metric: [[f64; 3]; 3],
    /// Grid points a node may take (where the light is not negligible).
    pub(super) allowed: Vec<bool>,
}

fn fprime(u: f64) -> f64 {
    const D: f64 = 6.0 / 29.0;
    if u > D * D * D {
        let c = u.cbrt();
        1.0 / (3.0 * c * c)
    } else {
        1.0 / (3.0 * D * D)
    }
}

/// `JᵀJ` for J = ∂Lab/∂XYZ at `t` with white `w` (held fixed).
fn lab_metric(t: [f64; 3], w: [f64; 3]) -> [[f64; 3]; 3] {
    let g = [0, 1, 2].map(|c| fprime(t[c] / w[c]) / w[c]);
    let j = [
        [0.0, 116.0 * g[1], 0.0],
        [500.0 * g[0], -500.0 * g[1], 0.0],
        [0.0, 200.0 * g[1], -200.0 * g[2]],
    ];
    let mut m = [[0.0; 3]; 3];
    for (p, row) in m.iter_mut().enumerate() {
        for (q, v) in row.iter_mut().enumerate() {
            *v = (0..3).map(|r| j[r][p] * j[r][q]).sum();
        }
    }
    m
}

impl Problem {
    /// Sets up the problem on the derivation's 1 nm reference grid. `light`: the light folded
    /// into the weights (`None`: the renderer samples radiance). `training`: reflectances whose
    /// colours under the light define the CIELAB metric (for radiances, their colours under an
    /// equal-energy light). `kernel` `None`: the light alone, no prior (see
    /// [`light_only`](Self::light_only)).
    pub(crate) fn new(
        d: &Derivation,
        light_curve: Option<&Curve>,
        kernel: Option<Kernel>,
        training: &[Curve],
    ) -> Result<Problem, Error> {
        let light_error = |problem: LightProblem| Error::Light {
            name: light_curve.map_or_else(|| "equal energy".into(), |l| l.name.clone()),
            problem,
        };
        let reference = d.observer.full_integration(d.settings.range_nm, 1.0)?;
        let grid_nm = reference.wavelengths_nm.clone();
        let g = grid_nm.len();
        let raw: Vec<f64> = match light_curve {
            Some(l) => grid_nm.iter().map(|&nm| l.at(nm)).collect(),
            None => std::vec![1.0; g],
        };
        if raw.iter().any(|v| !v.is_finite() || *v < 0.0) {
            return Err(light_error(LightProblem::Negative));
        }
        // Scale the light to the luminance of an equal-energy spectrum of 1, so that a folded
        // set gives a reflectance of 1 the Y a radiance set gives a radiance of 1.
        let y: f64 = raw
            .iter()
            .zip(&reference.xyz_weights[1])
            .map(|(a, b)| a * b)
            .sum();
        let unit: f64 = reference.xyz_weights[1].iter().sum();
        if y <= 0.0 || !y.is_finite() {
            return Err(light_error(LightProblem::NoLuminance));
        }
        let light: Vec<f64> = raw.iter().map(|v| v * unit / y).collect();
        let peak = light.iter().cloned().fold(0.0, f64::max);
        let allowed = light.iter().map(|&v| v > 1e-4 * peak).collect();
        let f: [Vec<f64>; 3] = [0, 1, 2].map(|c| {
            reference.xyz_weights[c]
                .iter()
                .zip(&light)
                .map(|(a, b)| a * b)
                .collect::<Vec<f64>>()
        });
        let mut k = Vec::new();
        if let Some(kernel) = kernel {
            k = std::vec![0.0; g * g];
            for a in 0..g {
                for b in 0..g {
                    k[a * g + b] = kernel.at(grid_nm[a] - grid_nm[b]);
                }
            }
        }
        let f1 = [0, 1, 2].map(|c| f[c].iter().sum::<f64>());
        let mut metric = [[0.0; 3]; 3];
        for r in training {
            let t = [0, 1, 2].map(|c| {
                grid_nm
                    .iter()
                    .zip(&f[c])
                    .map(|(&nm, w)| r.at(nm) * w)
                    .sum::<f64>()
            });
            let m = lab_metric(t, f1);
            for p in 0..3 {
                for q in 0..3 {
                    metric[p][q] += m[p][q] / training.len() as f64;
                }
            }
        }
        if training.is_empty() {
            metric = lab_metric([0.18 * f1[0], 0.18 * f1[1], 0.18 * f1[2]], f1);
        }
        let mut p = Problem {
            grid_nm,
            light,
            light_name: light_curve.map(|c| c.name.clone()),
            g,
            k,
            f,
            kf: Vec::new(),
            fkf: [[0.0; 3]; 3],
            f1,
            metric,
            allowed,
        };
        p.update();
        Ok(p)
    }

    /// `x̄ȳz̄ · L · dλ` on the grid: XYZ of a reflectance under this problem's light is
    /// `Σ_g f[c][g] r(λ_g)`.
    pub(super) fn folded_cmfs(&self) -> &[Vec<f64>; 3] {
        &self.f
    }

    /// XYZ of a perfect white under this problem's light (`F 1`).
    pub(super) fn white(&self) -> [f64; 3] {
        self.f1
    }

    /// The light's part of a problem alone: its grid, scaled light, folded observer and white,
    /// without the prior (no kernel matrix, which costs G² kernel values and products: what a
    /// build script at opt-level 0 need not pay to fit a light group's weights at cached nodes).
    /// Its [`solve`](Self::solve) and [`objective`](Self::objective) find nothing.
    pub(crate) fn light_only(d: &Derivation, light: &Curve) -> Result<Problem, Error> {
        Problem::new(d, Some(light), None, &[])
    }

    /// Whether the problem has its prior (not [`light_only`](Self::light_only)).
    fn has_prior(&self) -> bool {
        self.k.len() == self.g * self.g
    }

    /// Recomputes `K Fᵀ` and `F K Fᵀ` after the covariance changed.
    fn update(&mut self) {
        if !self.has_prior() {
            return;
        }
        let g = self.g;
        self.kf = (0..g)
            .map(|a| [0, 1, 2].map(|c| (0..g).map(|b| self.k[a * g + b] * self.f[c][b]).sum()))
            .collect();
        for p in 0..3 {
            for q in 0..3 {
                self.fkf[p][q] = (0..g).map(|a| self.f[p][a] * self.kf[a][q]).sum();
            }
        }
    }

    /// Adds `weight` times the empirical covariance of `spectra` (about their mean) to the
    /// prior.
    pub(crate) fn with_covariance(mut self, spectra: &[Curve], weight: f64) -> Problem {
        if !self.has_prior() {
            return self;
        }
        let g = self.g;
        let rows: Vec<Vec<f64>> = spectra
            .iter()
            .map(|c| self.grid_nm.iter().map(|&nm| c.at(nm)).collect())
            .collect();
        let n = rows.len().max(1) as f64;
        let mean: Vec<f64> = (0..g)
            .map(|a| rows.iter().map(|r| r[a]).sum::<f64>() / n)
            .collect();
        for r in &rows {
            let dev: Vec<f64> = r.iter().zip(&mean).map(|(x, m)| x - m).collect();
            for a in 0..g {
                for b in 0..g {
                    self.k[a * g + b] += weight * dev[a] * dev[b] / n;
                }
            }
        }
        self.update();
        self
    }

    /// The folded weights (`w[c][i]`, for samples of r) at grid indices `nodes`, and the
    /// expected linearised CIELAB error `tr(M Σ)` (in ΔE² per unit kernel variance). `None`
    /// when the kriging system is singular.
    pub(crate) fn solve(&self, nodes: &[usize]) -> Option<([Vec<f64>; 3], f64)> {
        let n = nodes.len();
        if n == 0 || !self.has_prior() {
            return None;
        }
        let mut a = DMatrix::<f64>::zeros(n + 1, n + 1);
        for (i, &ni) in nodes.iter().enumerate() {
            for (j, &nj) in nodes.iter().enumerate() {
                a[(i, j)] = self.k[ni * self.g + nj];
            }
            a[(i, i)] += NUGGET;
            a[(i, n)] = 1.0;
            a[(n, i)] = 1.0;
        }
        let mut b = DMatrix::<f64>::zeros(n + 1, 3);
        for (i, &ni) in nodes.iter().enumerate() {
            for c in 0..3 {
                b[(i, c)] = self.kf[ni][c];
            }
        }
        for c in 0..3 {
            b[(n, c)] = self.f1[c];
        }
        self.finish(a, b)
    }

    /// Solves the kriging system `a x = b` ((N+1)×(N+1), (N+1)×3) and forms the weights and the
    /// expected error.
    fn finish(&self, a: DMatrix<f64>, b: DMatrix<f64>) -> Option<([Vec<f64>; 3], f64)> {
        let n = a.nrows() - 1;
        let x = a.clone().lu().solve(&b)?;
        // Σ = FKFᵀ − W Kf − Kfᵀ Wᵀ + W K_XX Wᵀ (the nugget belongs to the samples' model).
        let w = x.rows(0, n).transpose(); // 3×n
        let kxx = a.view((0, 0), (n, n));
        let kfx = b.rows(0, n); // n×3
        let wk = &w * kfx;
        let wkw = &w * kxx * w.transpose();
        let mut obj = 0.0;
        for p in 0..3 {
            for q in 0..3 {
                let s = self.fkf[p][q] - wk[(p, q)] - wk[(q, p)] + wkw[(p, q)];
                obj += self.metric[q][p] * s;
            }
        }
        if !obj.is_finite() {
            return None;
        }
        let weights: [Vec<f64>; 3] = [0, 1, 2].map(|c| (0..n).map(|i| w[(c, i)]).collect());
        Some((weights, obj))
    }

    /// Rows of point samples at `wavelengths_nm` on the grid: each the linear interpolation
    /// between its two nearest grid points (a grid point itself is one 1). `None` for a
    /// wavelength outside the grid or not finite.
    pub(crate) fn point_rows(&self, wavelengths_nm: &[f64]) -> Option<Vec<Vec<f64>>> {
        let (first, last) = (self.grid_nm[0], self.grid_nm[self.g - 1]);
        wavelengths_nm
            .iter()
            .map(|&nm| {
                if !(nm >= first && nm <= last) {
                    return None;
                }
                let mut row = std::vec![0.0; self.g];
                let i = self.grid_nm.partition_point(|&l| l < nm);
                if self.grid_nm[i] == nm {
                    row[i] = 1.0;
                } else {
                    let t = (nm - self.grid_nm[i - 1]) / (self.grid_nm[i] - self.grid_nm[i - 1]);
                    row[i - 1] = 1.0 - t;
                    row[i] = t;
                }
                Some(row)
            })
            .collect()
    }

    /// Rows of channel readings: a channel's reading is `∫ S(λ) L(λ) r(λ) dλ`, S its
    /// sensitivity and L this problem's light (ones for radiances), on the 1 nm grid.
    pub(crate) fn channel_rows(&self, channels: &[Curve]) -> Vec<Vec<f64>> {
        channels
            .iter()
            .map(|c| {
                self.grid_nm
                    .iter()
                    .zip(&self.light)
                    .map(|(&nm, l)| c.at(nm) * l)
                    .collect()
            })
            .collect()
    }

    /// The light on the grid at `nm`, linearly interpolated ([`point_rows`](Self::point_rows)).
    pub(crate) fn light_at(&self, nm: f64) -> f64 {
        self.point_rows(&[nm]).map_or(f64::NAN, |r| {
            r[0].iter().zip(&self.light).map(|(h, l)| h * l).sum()
        })
    }

    /// [`solve`](Self::solve) for samples that are any linear functionals of r, given as rows
    /// on the grid (`sample_i = Σ_g rows[i][g] · r(λ_g)`): point samples ([`point_rows`](Self::point_rows))
    /// or channel readings ([`channel_rows`](Self::channel_rows)). A constant spectrum is
    /// integrated exactly (each sample's reading of 1 enters the constraint), and the nugget
    /// scales with that reading squared, so rows of grid points give exactly [`solve`](Self::solve)'s
    /// weights.
    pub(crate) fn solve_rows(&self, rows: &[Vec<f64>]) -> Option<([Vec<f64>; 3], f64)> {
        let n = rows.len();
        if n == 0 || !self.has_prior() || rows.iter().any(|r| r.len() != self.g) {
            return None;
        }
        let g = self.g;
        // H K, row by row (only the non-zero entries of H contribute).
        let hk: Vec<Vec<f64>> = rows
            .iter()
            .map(|h| {
                let mut out = std::vec![0.0; g];
                for (a, &ha) in h.iter().enumerate() {
                    if ha != 0.0 {
                        let k = &self.k[a * g..(a + 1) * g];
                        for (o, kv) in out.iter_mut().zip(k) {
                            *o += ha * kv;
                        }
                    }
                }
                out
            })
            .collect();
        let ones: Vec<f64> = rows.iter().map(|h| h.iter().sum()).collect();
        let mut a = DMatrix::<f64>::zeros(n + 1, n + 1);
        for i in 0..n {
            for j in 0..n {
                a[(i, j)] = rows[j]
                    .iter()
                    .zip(&hk[i])
                    .filter(|(h, _)| **h != 0.0)
                    .map(|(h, k)| h * k)
                    .sum();
            }
            a[(i, i)] += NUGGET * ones[i] * ones[i];
            a[(i, n)] = ones[i];
            a[(n, i)] = ones[i];
        }
        let mut b = DMatrix::<f64>::zeros(n + 1, 3);
        for (i, h) in rows.iter().enumerate() {
            for c in 0..3 {
                b[(i, c)] = h
                    .iter()
                    .zip(&self.kf)
                    .filter(|(h, _)| **h != 0.0)
                    .map(|(h, kf)| h * kf[c])
                    .sum();
            }
        }
        for c in 0..3 {
            b[(n, c)] = self.f1[c];
        }
        self.finish(a, b)
    }

    /// The expected linearised CIELAB error `tr(M Σ)` (in ΔE² per unit kernel variance) of the
    /// set at grid indices `nodes`, as [`set_at`](Self::set_at) gives it; infinite where the
    /// kriging system is singular.
    pub(crate) fn objective(&self, nodes: &[usize]) -> f64 {
        self.solve(nodes).map_or(f64::INFINITY, |s| s.1)
    }

    /// The set at grid indices `nodes` (ascending), with its weights and expected error;
    /// `None` when the kriging system is singular. What [`shared`](Self::shared) returns for
    /// the nodes it finds: a node cache keeps the nodes and refits here.
    pub fn set_at(&self, nodes: &[usize]) -> Option<Shared> {
        let (xyz_weights, expected_error) = self.solve(nodes)?;
        Some(Shared {
            light: self.light_name.clone(),
            wavelengths_nm: nodes.iter().map(|&i| self.grid_nm[i]).collect(),
            light_at_nodes: nodes.iter().map(|&i| self.light[i]).collect(),
            xyz_weights,
            expected_error,
        })
    }
}

/// The crate's problem for a light given by name (a built-in illuminant: `C`, `D65`, `F11`,
/// `LED_B1`, …), or for radiances (`None`): [`Kernel::Matern52`] of [`LENGTH_NM`] plus
/// [`EMPIRICAL_WEIGHT`] times the covariance of [`TRAINING_FILE`].
pub(crate) fn problem(d: &Derivation, light: Option<&str>) -> Result<Problem, Error> {
    let range = d.settings.range_nm;
    let curve = match light {
        Some(name) => Some(
            builtin_illuminant(&d.settings.data_dir, name, range).map_err(|_| Error::Light {
                name: name.into(),
                problem: LightProblem::NotBuiltIn {
                    valid: builtin_lights().into_iter().map(String::from).collect(),
                },
            })?,
        ),
        None => None,
    };
    problem_for(d, curve.as_ref())
}

/// `problem` for a light given as a curve (a user's measured light; `None`: radiances): the
/// same kernel, prior and training, so a light read from a copy of a built-in illuminant's
/// file gives the built-in light's sets to the last digit.
pub fn problem_for(d: &Derivation, light: Option<&Curve>) -> Result<Problem, Error> {
    let tcs = Spectra::builtin(&d.settings.data_dir, TRAINING_FILE)
        .and_then(|s| s.curves(d.settings.range_nm))?;
    Ok(Problem::new(
        d,
        light,
        Some(Kernel::Matern52 {
            length_nm: LENGTH_NM,
        }),
        &tcs,
    )?
    .with_covariance(&tcs, EMPIRICAL_WEIGHT))
}

/// A shared set: its wavelengths and folded weights, and what it was optimised for.
#[derive(Debug, Clone, PartialEq)]
pub struct Shared {
    /// The light folded into the weights, `None` for radiances.
    pub light: Option<String>,
    /// The wavelengths in nm, ascending.
    pub wavelengths_nm: Vec<f64>,
    /// The light at each wavelength, scaled as [`Problem::light`] (ones for radiances).
    pub light_at_nodes: Vec<f64>,
    /// Folded XYZ weights `w[c][i]` for samples of r (reflectance under the light, or radiance).
    pub xyz_weights: [Vec<f64>; 3],
    /// The expected linearised CIELAB error `tr(M Σ)`, in ΔE² per unit kernel variance
    /// (`Problem::objective`).
    pub expected_error: f64,
}

impl Shared {
    /// The set as the runtime bakes it: AC1C2 rows (Eq. 9 applied to the folded XYZ weights).
    pub(crate) fn wavelength_set(&self, d: &Derivation, name: &str) -> WavelengthSet {
        let n = self.wavelengths_nm.len();
        let what = match &self.light {
            Some(l) => std::format!("samples are reflectances under illuminant {l}, folded into the weights (a reflectance of 1 has the Y of a radiance of 1)"),
            None => "samples are radiances".to_string(),
        };
        WavelengthSet {
            name: name.into(),
            doc: std::format!(
                "Shared set by kernel quadrature: {n} wavelengths for all three channels; {what}. Trained on the CIE test colour samples."
            ),
            wavelengths_nm: self.wavelengths_nm.clone(),
            weights: display::fold(&d.opponent.xyz_to_ac1c2, &self.xyz_weights, 1.0),
            light: self.light.clone(),
            sensor: None,
        }
    }
}

/// A set as the report and the planner measure it, on radiances: its AC1C2 weights taken to XYZ
/// and, for a set with `light` folded in (the curve the set was fitted for), divided by that
/// light at each wavelength, so that applied to `r · L` it equals
/// the folded set applied to r. `light` `None`: a set for radiances, taken as it is.
pub fn eval_on_radiance(
    d: &Derivation,
    set: &WavelengthSet,
    family: &str,
    light: Option<&Curve>,
) -> Result<EvalSet, Error> {
    let mut eval = d.eval_set(set, family);
    if let Some(l) = light {
        let p = problem_for(d, Some(l))?;
        for row in eval.xyz_weights.iter_mut() {
            for (w, nm) in row.iter_mut().zip(&set.wavelengths_nm) {
                *w /= p.light_at(*nm);
            }
        }
    }
    Ok(eval)
}
