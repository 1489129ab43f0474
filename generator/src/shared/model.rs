//! Shared wavelength sets by kernel quadrature, with the light folded into the weights.
//!
//! A renderer pays per distinct wavelength, and every channel can use every sample. So a shared
//! set has N distinct wavelengths λᵢ and a full 3×N matrix W with `XYZ ≈ W · [r(λ₁) … r(λ_N)]`,
//! where r is what the renderer samples: a reflectance under a known light L (the light is
//! folded into W, `F = x̄ȳz̄ · L · dλ`), or a radiance (L = 1).
//!
//! The model: r is a constant of unknown level plus a zero-mean Gaussian process whose
//! covariance is a Matérn 5/2 smoothness kernel plus a multiple of the training reflectances'
//! empirical covariance. For given nodes, W is the best linear unbiased estimate of `F r`
//! (universal kriging with a constant trend): it minimises the expected squared error of every
//! linear functional of XYZ, and it integrates a constant spectrum exactly, so the white of a
//! surface under L is exact. The nodes minimise the expected linearised CIELAB error
//! `tr(M Σ)`, Σ the 3×3 covariance of XYZ's error and `M = mean JᵀJ` over the training colours
//! (J = ∂Lab/∂XYZ at each, its white exact): greedy selection on the 1 nm grid, evenly spaced
//! and random starts, each refined by coordinate descent, the best kept.
//!
//! The kernel's length and the empirical covariance's weight ([`LENGTH_NM`],
//! [`EMPIRICAL_WEIGHT`]) maximise the leave-one-out likelihood of the training reflectances
//! ([`fit`]). The crate trains on the CIE test colour samples only and judges on the
//! ColorChecker, which no set ever sees.
//!
//! Method (a) for comparison, [`interpolatory_a`]: the A channel's Gauss nodes of order N, with
//! C1 and C2 integrated by interpolatory rules on those nodes.

use std::string::{String, ToString};
use std::vec::Vec;

use nalgebra::{DMatrix, DVector};

use super::evaluate::{self, Curve, EvalSet};
use super::quadrature::interpolatory_weights;
use super::sets::WavelengthSet;
use super::{Derivation, Error, LightProblem, SetNameProblem};

/// A stationary covariance on wavelength, `k(λ, μ) = σ² ρ(|λ − μ| / ℓ)` with unit σ² (the
/// scale cancels in the weights and in the node choice).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kernel {
    /// Matérn ν = 5/2: `(1 + √5 d + 5d²/3) e^{−√5 d}`, d = |λ − μ| / ℓ. Twice differentiable
    /// paths, like measured reflectances.
    Matern52 {
        /// ℓ in nm.
        length_nm: f64,
    },
}

impl Kernel {
    /// ρ at a distance in nm.
    pub fn at(&self, distance_nm: f64) -> f64 {
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
pub const NUGGET: f64 = 1e-6;

/// Random starts of coordinate descent, besides greedy selection and three even spreads.
pub const RANDOM_STARTS: usize = 12;

/// How far (1 nm grid steps) coordinate descent tries to move one node.
pub const MAX_MOVE: usize = 12;

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
    g: usize,
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
    allowed: Vec<bool>,
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
    /// equal-energy light).
    pub fn new(
        d: &Derivation,
        light_curve: Option<&Curve>,
        kernel: Kernel,
        training: &[Curve],
    ) -> Result<Problem, Error> {
        let light_error = |problem: LightProblem| Error::Light {
            name: light_curve.map_or_else(|| "equal energy".into(), |l| l.name.clone()),
            problem,
        };
        let reference = evaluate::full_integration(&d.observer, d.settings.range_nm, 1.0)?;
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
        let mut k = std::vec![0.0; g * g];
        for a in 0..g {
            for b in 0..g {
                k[a * g + b] = kernel.at(grid_nm[a] - grid_nm[b]);
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

    /// Recomputes `K Fᵀ` and `F K Fᵀ` after the covariance changed.
    fn update(&mut self) {
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
    pub fn with_covariance(mut self, spectra: &[Curve], weight: f64) -> Problem {
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

    /// `F s` for a spectrum on the grid.
    pub fn integrate(&self, s: &[f64]) -> [f64; 3] {
        [0, 1, 2].map(|c| self.f[c].iter().zip(s).map(|(a, b)| a * b).sum())
    }

    /// The folded weights (`w[c][i]`, for samples of r) at grid indices `nodes`, and the
    /// expected linearised CIELAB error `tr(M Σ)` (in ΔE² per unit kernel variance). `None`
    /// when the kriging system is singular.
    pub fn solve(&self, nodes: &[usize]) -> Option<([Vec<f64>; 3], f64)> {
        let n = nodes.len();
        if n == 0 {
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
    pub fn point_rows(&self, wavelengths_nm: &[f64]) -> Option<Vec<Vec<f64>>> {
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
    pub fn channel_rows(&self, channels: &[Curve]) -> Vec<Vec<f64>> {
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
    pub fn light_at(&self, nm: f64) -> f64 {
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
    pub fn solve_rows(&self, rows: &[Vec<f64>]) -> Option<([Vec<f64>; 3], f64)> {
        let n = rows.len();
        if n == 0 || rows.iter().any(|r| r.len() != self.g) {
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

    /// The expected error of [`solve`](Self::solve), infinite where it fails.
    pub fn objective(&self, nodes: &[usize]) -> f64 {
        self.solve(nodes).map_or(f64::INFINITY, |s| s.1)
    }

    /// Greedy selection of `n` allowed grid indices, each the one that most lowers the error.
    pub fn greedy(&self, n: usize) -> Vec<usize> {
        self.greedy_with(n, &|nodes| self.objective(nodes))
    }

    /// [`greedy`](Self::greedy) for any objective.
    fn greedy_with(&self, n: usize, objective: &dyn Fn(&[usize]) -> f64) -> Vec<usize> {
        let mut nodes: Vec<usize> = Vec::with_capacity(n);
        for _ in 0..n {
            let mut best = (f64::INFINITY, usize::MAX);
            for c in 0..self.g {
                if !self.allowed[c] || nodes.contains(&c) {
                    continue;
                }
                nodes.push(c);
                let o = objective(&nodes);
                nodes.pop();
                if o < best.0 {
                    best = (o, c);
                }
            }
            if best.1 == usize::MAX {
                break;
            }
            nodes.push(best.1);
        }
        nodes.sort_unstable();
        nodes
    }

    /// Coordinate descent: moves one node at a time by up to ±[`MAX_MOVE`] grid steps while that
    /// lowers the error. Returns the nodes (ascending) and their error.
    pub fn refine(&self, nodes: Vec<usize>) -> (Vec<usize>, f64) {
        self.refine_with(nodes, &|nodes| self.objective(nodes))
    }

    /// [`refine`](Self::refine) for any objective.
    fn refine_with(
        &self,
        mut nodes: Vec<usize>,
        objective: &dyn Fn(&[usize]) -> f64,
    ) -> (Vec<usize>, f64) {
        let mut current = objective(&nodes);
        for _ in 0..200 {
            let mut improved = false;
            for i in 0..nodes.len() {
                let start = nodes[i];
                let mut best = (current, start);
                for step in 1..=MAX_MOVE {
                    for c in [start.checked_sub(step), Some(start + step)]
                        .into_iter()
                        .flatten()
                    {
                        if c >= self.g || !self.allowed[c] || nodes.contains(&c) {
                            continue;
                        }
                        nodes[i] = c;
                        let o = objective(&nodes);
                        if o < best.0 * (1.0 - 1e-12) {
                            best = (o, c);
                        }
                    }
                }
                nodes[i] = best.1;
                if best.1 != start {
                    current = best.0;
                    improved = true;
                }
            }
            if !improved {
                break;
            }
        }
        nodes.sort_unstable();
        (nodes, current)
    }

    /// Evenly spaced allowed grid indices (a start for [`refine`](Self::refine)).
    fn spread(&self, n: usize, offset: f64) -> Vec<usize> {
        let allowed: Vec<usize> = (0..self.g).filter(|&c| self.allowed[c]).collect();
        let mut nodes: Vec<usize> = (0..n)
            .map(|i| {
                let t = (i as f64 + offset) / n as f64;
                allowed[((t * allowed.len() as f64) as usize).min(allowed.len() - 1)]
            })
            .collect();
        nodes.dedup();
        nodes
    }

    /// The best of greedy selection and evenly spaced starts, each refined by coordinate
    /// descent: `n` grid indices (ascending) and their error.
    pub fn optimize(&self, n: usize) -> (Vec<usize>, f64) {
        self.optimize_with(n, &|nodes| self.objective(nodes))
    }

    /// [`optimize`](Self::optimize) for any objective.
    fn optimize_with(&self, n: usize, objective: &dyn Fn(&[usize]) -> f64) -> (Vec<usize>, f64) {
        let mut starts = std::vec![self.greedy_with(n, objective)];
        for offset in [0.5, 0.25, 0.75] {
            let s = self.spread(n, offset);
            if s.len() == n {
                starts.push(s);
            }
        }
        // Random starts from a fixed LCG (deterministic output).
        let allowed: Vec<usize> = (0..self.g).filter(|&c| self.allowed[c]).collect();
        let mut state: u64 = 0x853c_49e6_748f_ea9b;
        for _ in 0..RANDOM_STARTS {
            let mut s: Vec<usize> = Vec::with_capacity(n);
            while s.len() < n.min(allowed.len()) {
                state = state
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                let c = allowed[((state >> 33) as usize) % allowed.len()];
                if !s.contains(&c) {
                    s.push(c);
                }
            }
            starts.push(s);
        }
        starts
            .into_iter()
            .map(|s| self.refine_with(s, objective))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap_or((Vec::new(), f64::INFINITY))
    }

    /// The set at grid indices `nodes` (ascending), with its weights and expected error;
    /// `None` when the kriging system is singular.
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

    /// The optimised shared set of `n` wavelengths ([`optimize`](Self::optimize)).
    pub fn shared(&self, n: usize) -> Result<Shared, Error> {
        let (nodes, _) = self.optimize(n);
        if nodes.len() != n {
            return Err(Error::Numerical(std::format!(
                "no shared set of {n} wavelengths: only {} grid points are usable",
                nodes.len()
            )));
        }
        self.set_at(&nodes).ok_or_else(|| {
            Error::Numerical(std::format!(
                "no shared set of {n} wavelengths: the kriging system is singular"
            ))
        })
    }
}

/// The result of [`fit`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fit {
    /// The Matérn 5/2 length, nm.
    pub length_nm: f64,
    /// The weight of the empirical covariance.
    pub weight: f64,
    /// The leave-one-out log likelihood (up to a constant).
    pub log_likelihood: f64,
}

/// The lengths [`fit`] searches for the crate's sets, nm.
pub const FIT_LENGTHS_NM: [f64; 9] = [40.0, 45.0, 50.0, 55.0, 60.0, 65.0, 70.0, 75.0, 80.0];

/// The empirical-covariance weights [`fit`] searches for the crate's sets.
pub const FIT_WEIGHTS: [f64; 11] = [
    0.0, 10.0, 20.0, 30.0, 50.0, 70.0, 100.0, 150.0, 200.0, 300.0, 1000.0,
];

/// White noise added to the kernel in [`fit`] (relative to its variance): reflectance data are
/// given to about 1 % of their spread, so the likelihood should not chase finer detail.
pub const FIT_NOISE: f64 = 1e-4;

/// The Matérn length of the crate's sets, nm: [`fit`] on the CIE test colour samples over
/// [`FIT_LENGTHS_NM`] × [`FIT_WEIGHTS`] (the tests re-run the fit).
pub const LENGTH_NM: f64 = 60.0;

/// The empirical-covariance weight of the crate's sets, fitted with [`LENGTH_NM`].
pub const EMPIRICAL_WEIGHT: f64 = 70.0;

/// The kernel length and empirical-covariance weight that maximise the leave-one-out likelihood
/// of `training`: each reflectance predicted by a Gaussian with the other reflectances' mean and
/// covariance `σ²(k + α S₋ₖ + ηI)` (σ² profiled, η = [`FIT_NOISE`]), on a 5 nm grid of
/// `range_nm`. `None` with fewer than 3 spectra or when no candidate is positive definite.
pub fn fit(
    training: &[Curve],
    range_nm: [f64; 2],
    lengths_nm: &[f64],
    weights: &[f64],
) -> Option<Fit> {
    let n = training.len();
    if n < 3 {
        return None;
    }
    let mut grid = Vec::new();
    let mut nm = range_nm[0];
    while nm <= range_nm[1] + 1e-9 {
        grid.push(nm);
        nm += 5.0;
    }
    let dim = grid.len();
    let ys: Vec<DVector<f64>> = training
        .iter()
        .map(|r| DVector::from_iterator(dim, grid.iter().map(|&nm| r.at(nm))))
        .collect();
    // Per held-out spectrum: its residual from the others' mean, and the others' empirical
    // covariance. Neither depends on the kernel or the weight.
    let held_out: Vec<(DVector<f64>, DMatrix<f64>)> = (0..n)
        .map(|h| {
            let others: Vec<&DVector<f64>> = (0..n).filter(|&i| i != h).map(|i| &ys[i]).collect();
            let m = others.len() as f64;
            let mean = others.iter().fold(DVector::zeros(dim), |acc, y| acc + *y) / m;
            let mut scatter = DMatrix::<f64>::zeros(dim, dim);
            for y in &others {
                let dev = *y - &mean;
                scatter += &dev * dev.transpose() / m;
            }
            (&ys[h] - &mean, scatter)
        })
        .collect();
    let mut best: Option<Fit> = None;
    for &length_nm in lengths_nm {
        let kernel = Kernel::Matern52 { length_nm };
        let mut k = DMatrix::<f64>::from_fn(dim, dim, |i, j| kernel.at(grid[i] - grid[j]));
        for i in 0..dim {
            k[(i, i)] += FIT_NOISE;
        }
        for &weight in weights {
            if let Some(ll) = loo_log_likelihood(&k, &held_out, weight) {
                if best.is_none_or(|b| ll > b.log_likelihood) {
                    best = Some(Fit {
                        length_nm,
                        weight,
                        log_likelihood: ll,
                    });
                }
            }
        }
    }
    best
}

/// The leave-one-out log likelihood (σ² profiled) of residuals `e` under covariances
/// `k + α S` (see [`fit`]).
fn loo_log_likelihood(
    k: &DMatrix<f64>,
    held_out: &[(DVector<f64>, DMatrix<f64>)],
    alpha: f64,
) -> Option<f64> {
    let mut quad = 0.0;
    let mut logdet = 0.0;
    for (e, scatter) in held_out {
        let chol = (k + scatter * alpha).cholesky()?;
        logdet += 2.0 * chol.l().diagonal().iter().map(|v| v.ln()).sum::<f64>();
        quad += e.dot(&chol.solve(e));
    }
    let count = (held_out.len() * k.nrows()) as f64;
    Some(-0.5 * count * (quad / count).ln() - 0.5 * logdet)
}

/// The training reflectances of the crate's sets: the CIE test colour samples (never the
/// ColorChecker, on which the report and the tests judge them).
pub const TRAINING_FILE: &str = "data/reflectance_cie_tcs.csv";

/// Shared-set sizes the catalog builds: `KQ_3` … `KQ_32`.
pub const SIZES: core::ops::RangeInclusive<usize> = 3..=32;

/// The crate's problem for a light given by name (a built-in illuminant: `C`, `D65`, `F11`,
/// `LED_B1`, …), or for radiances (`None`): [`Kernel::Matern52`] of [`LENGTH_NM`] plus
/// [`EMPIRICAL_WEIGHT`] times the covariance of [`TRAINING_FILE`].
pub fn problem(d: &Derivation, light: Option<&str>) -> Result<Problem, Error> {
    let range = d.settings.range_nm;
    let curve = match light {
        Some(name) => Some(
            evaluate::builtin_illuminant(&d.settings.data_dir, name, range).map_err(|_| {
                Error::Light {
                    name: name.into(),
                    problem: LightProblem::NotBuiltIn {
                        valid: super::catalog::builtin_lights()
                            .into_iter()
                            .map(String::from)
                            .collect(),
                    },
                }
            })?,
        ),
        None => None,
    };
    problem_for(d, curve.as_ref())
}

/// [`problem`] for a light given as a curve (a user's measured light; `None`: radiances): the
/// same kernel, prior and training, so a light read from a copy of a built-in illuminant's
/// file gives the built-in light's sets to the last digit.
pub fn problem_for(d: &Derivation, light: Option<&Curve>) -> Result<Problem, Error> {
    let tcs = evaluate::Spectra::builtin(&d.settings.data_dir, TRAINING_FILE)
        .and_then(|s| s.curves(d.settings.range_nm))?;
    Ok(Problem::new(
        d,
        light,
        Kernel::Matern52 {
            length_nm: LENGTH_NM,
        },
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
    /// The expected linearised CIELAB error of [`Problem::solve`].
    pub expected_error: f64,
}

impl Shared {
    /// The set as the report measures it, on radiances `r · L`: the folded weights divided by
    /// the light at each wavelength, so that applied to `r · L` it equals the folded set
    /// applied to r.
    pub fn eval_set(&self, name: &str, family: &str) -> EvalSet {
        EvalSet {
            name: name.into(),
            family: family.into(),
            orders: None,
            wavelengths_nm: self.wavelengths_nm.clone(),
            xyz_weights: self.xyz_weights.clone().map(|row| {
                row.iter()
                    .zip(&self.light_at_nodes)
                    .map(|(v, l)| v / l)
                    .collect()
            }),
        }
    }

    /// The set as the runtime bakes it: AC1C2 rows (Eq. 9 applied to the folded XYZ weights).
    pub fn wavelength_set(&self, d: &Derivation, name: &str) -> WavelengthSet {
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
            weights: super::display::fold(&d.opponent.xyz_to_ac1c2, &self.xyz_weights, 1.0),
            light: self.light.clone(),
            sensor: None,
        }
    }
}

/// A set as the report and the planner measure it, on radiances: its AC1C2 weights taken to XYZ
/// and, for a set with `light` folded in (the curve the set was fitted for), divided by that
/// light at each wavelength, as [`Shared::eval_set`] does, so that applied to `r · L` it equals
/// the folded set applied to r. `light` `None`: a set for radiances, taken as it is.
pub fn eval_on_radiance(
    d: &Derivation,
    set: &WavelengthSet,
    family: &str,
    light: Option<&Curve>,
) -> Result<EvalSet, Error> {
    let mut eval = EvalSet::from_set(set, family, &d.opponent.ac1c2_to_xyz);
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

/// The shared set of `n` wavelengths for a built-in light (`None`: radiances). To build
/// several sizes for one light, set up [`problem`] once and call [`Problem::shared`].
///
/// This runs the node search ([`Problem::optimize`]), which costs seconds at Cargo's default
/// build-script opt-level 0; [`cached_or_optimize`] takes the nodes from [`CACHE_FILE`] where it
/// can.
pub fn optimize(d: &Derivation, light: Option<&str>, n: usize) -> Result<Shared, Error> {
    problem(d, light)?.shared(n)
}

/// The shared sets' node cache, a file in the data directory: the nodes [`Problem::optimize`]
/// found for each set in [`CACHED`], with a fingerprint of everything the search depends on.
/// `cargo run --release -p spectral-quadrature-tools --bin tables -- --shared-cache` writes it,
/// and a test re-runs every search and checks that it finds the same nodes (or worse ones).
pub const CACHE_FILE: &str = "data/shared_nodes.csv";

/// The sets whose nodes [`CACHE_FILE`] holds: radiances and the lights C, D65, A and F11, at 4, 6
/// and 8 wavelengths (the default scene's sets and the example scenes' among them).
pub const CACHED: [(Option<&str>, usize); 15] = [
    (None, 4),
    (None, 6),
    (None, 8),
    (Some("C"), 4),
    (Some("C"), 6),
    (Some("C"), 8),
    (Some("D65"), 4),
    (Some("D65"), 6),
    (Some("D65"), 8),
    (Some("A"), 4),
    (Some("A"), 6),
    (Some("A"), 8),
    (Some("F11"), 4),
    (Some("F11"), 6),
    (Some("F11"), 8),
];

/// The catalog name of a shared set: `KQ_<n>` or `KQ_<light>_<n>`.
pub fn set_name(light: Option<&str>, n: usize) -> String {
    match light {
        Some(l) => std::format!("KQ_{l}_{n}"),
        None => std::format!("KQ_{n}"),
    }
}

/// One line of [`CACHE_FILE`].
#[derive(Debug, Clone, PartialEq)]
pub struct CacheEntry {
    /// The set's name ([`set_name`]).
    pub name: String,
    /// [`fingerprint`] of the inputs the nodes were found with.
    pub fingerprint: String,
    /// The nodes in nm, ascending, on the 1 nm grid.
    pub wavelengths_nm: Vec<f64>,
    /// The line in the file.
    pub line: u64,
}

/// A SHA-256 over everything the node search for `light` depends on besides its code: the
/// observer table, the range, the training reflectances, the light's file, and the kernel and
/// search constants. A cached entry is used only while its fingerprint matches.
pub fn fingerprint(d: &Derivation, light: Option<&str>) -> Result<String, Error> {
    let read = |label: &str| super::read_data(&d.settings.data_dir, label);
    let mut text = std::format!(
        "observer {} {}\nrange {:?}\ntraining {}\nkernel matern52 {LENGTH_NM} empirical {EMPIRICAL_WEIGHT} nugget {NUGGET}\nsearch starts {RANDOM_STARTS} move {MAX_MOVE}\n",
        d.observer.file,
        d.observer.sha256,
        d.settings.range_nm,
        super::sha256_hex(&read(TRAINING_FILE)?),
    );
    if let Some(l) = light {
        let label = std::format!("data/illuminant_{l}.csv");
        text += &std::format!("light {l} {}\n", super::sha256_hex(&read(&label)?));
    }
    Ok(super::sha256_hex(text.as_bytes()))
}

/// Reads [`CACHE_FILE`] from `data_dir`: no file is an empty cache; a malformed one is an error
/// naming the file and line.
pub fn read_cache(data_dir: &std::path::Path) -> Result<Vec<CacheEntry>, super::DataError> {
    let path = super::data_path(data_dir, CACHE_FILE);
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(super::read_error(CACHE_FILE, &path, &e)),
    };
    parse_cache(CACHE_FILE, &text)
}

/// Parses the text of a node cache (see [`CACHE_FILE`]); `file` labels errors.
pub fn parse_cache(file: &str, text: &str) -> Result<Vec<CacheEntry>, super::DataError> {
    let err = |line: u64, message: String| super::DataError {
        file: file.into(),
        line,
        message,
    };
    let mut out: Vec<CacheEntry> = Vec::new();
    let mut header = false;
    for (i, raw) in text.lines().enumerate() {
        let line = i as u64 + 1;
        let l = raw.trim();
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        if !header {
            if l != "name,fingerprint,wavelengths_nm" {
                return Err(err(
                    line,
                    std::format!(
                        "expected the header name,fingerprint,wavelengths_nm, found {l:?}"
                    ),
                ));
            }
            header = true;
            continue;
        }
        let fields: Vec<&str> = l.split(',').collect();
        let [name, fingerprint, nodes] = fields[..] else {
            return Err(err(
                line,
                std::format!(
                    "expected 3 fields (name,fingerprint,wavelengths_nm), found {}",
                    fields.len()
                ),
            ));
        };
        let wavelengths_nm = nodes
            .split_whitespace()
            .map(|v| match v.parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(x),
                _ => Err(err(line, std::format!("{name}: {v:?} is not a wavelength"))),
            })
            .collect::<Result<Vec<f64>, _>>()?;
        if wavelengths_nm.is_empty() || wavelengths_nm.windows(2).any(|w| w[0] >= w[1]) {
            return Err(err(
                line,
                std::format!("{name}: the wavelengths must be strictly increasing"),
            ));
        }
        if out.iter().any(|e| e.name == name) {
            return Err(err(line, std::format!("{name} appears twice")));
        }
        out.push(CacheEntry {
            name: name.into(),
            fingerprint: fingerprint.into(),
            wavelengths_nm,
            line,
        });
    }
    Ok(out)
}

/// The text of [`CACHE_FILE`] for `entries`.
pub fn write_cache(entries: &[CacheEntry]) -> String {
    let mut s = String::from(
        "# Generated by `cargo run --release -p spectral-quadrature-tools --bin tables -- --shared-cache > data/shared_nodes.csv`.\n# The nodes (nm) the shared-set search found; the build reuses an entry while its fingerprint matches the inputs.\nname,fingerprint,wavelengths_nm\n",
    );
    for e in entries {
        let nodes: Vec<String> = e
            .wavelengths_nm
            .iter()
            .map(|v| std::format!("{v}"))
            .collect();
        s += &std::format!("{},{},{}\n", e.name, e.fingerprint, nodes.join(" "));
    }
    s
}

/// The shared set of `n` wavelengths for a built-in light (`None`: radiances): the nodes from
/// [`CACHE_FILE`] when it has the set with a matching [`fingerprint`] (only the weights are
/// computed then), otherwise [`optimize`]'s search.
pub fn cached_or_optimize(d: &Derivation, light: Option<&str>, n: usize) -> Result<Shared, Error> {
    let name = set_name(light, n);
    let cache = read_cache(&d.settings.data_dir)?;
    let Some(entry) = cache.iter().find(|e| e.name == name) else {
        return optimize(d, light, n);
    };
    if entry.fingerprint != fingerprint(d, light)? || entry.wavelengths_nm.len() != n {
        return optimize(d, light, n);
    }
    let p = problem(d, light)?;
    let nodes = entry
        .wavelengths_nm
        .iter()
        .map(|&nm| {
            p.grid_nm
                .iter()
                .position(|&g| (g - nm).abs() < 1e-9)
                .filter(|&i| p.allowed[i])
                .ok_or_else(|| {
                    Error::Data(super::DataError {
                        file: CACHE_FILE.into(),
                        line: entry.line,
                        message: std::format!("{name}: {nm} nm is not a usable grid wavelength"),
                    })
                })
        })
        .collect::<Result<Vec<usize>, Error>>()?;
    p.set_at(&nodes).ok_or_else(|| {
        Error::Numerical("the kriging system is singular".into()).at(CACHE_FILE, entry.line)
    })
}

/// The cache entry for one set, by a fresh search ([`Problem::optimize`]).
pub fn cache_entry(d: &Derivation, light: Option<&str>, n: usize) -> Result<CacheEntry, Error> {
    let s = optimize(d, light, n)?;
    Ok(CacheEntry {
        name: set_name(light, n),
        fingerprint: fingerprint(d, light)?,
        wavelengths_nm: s.wavelengths_nm,
        line: 0,
    })
}

/// Method (a): the A channel's Gauss rule of order `n` (its nodes and A weights), with C1 and C2
/// integrated on the same nodes by interpolatory rules (the integral of the interpolating
/// polynomial), so that all three channels share `n` wavelengths.
pub fn interpolatory_a(d: &Derivation, n: usize, name: &str) -> Result<WavelengthSet, Error> {
    let problem = |problem: SetNameProblem| Error::SetName {
        name: name.into(),
        problem,
    };
    let r = d.rules[0].get(n.wrapping_sub(1)).ok_or_else(|| {
        problem(SetNameProblem::OrderNotDerived {
            channel: 0,
            order: n,
            max: d.settings.max_order,
        })
    })?;
    if !r.is_defined() {
        return Err(problem(SetNameProblem::RuleUndefined {
            channel: 0,
            order: n,
            status: r.status.as_str(),
            reason: r.reason.clone(),
        }));
    }
    Ok(WavelengthSet {
        name: name.into(),
        doc: std::format!(
            "The A channel's Gauss rule of order {n}, with C1 and C2 integrated by interpolatory rules on its nodes."
        ),
        wavelengths_nm: r.nodes_nm.clone(),
        weights: [
            r.weights.clone(),
            interpolatory_weights(&d.measures[1], &r.nodes_nm),
            interpolatory_weights(&d.measures[2], &r.nodes_nm),
        ],
        light: None,
        sensor: None,
    })
}
