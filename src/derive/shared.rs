//! Shared wavelength sets by kernel quadrature: N distinct wavelengths and a full 3×N XYZ weight
//! matrix fitted for all three channels at once to training spectra (optimal linear estimation).
//!
//! Given training radiances `s_k` on the 1 nm reference grid, their exact tristimulus
//! `t_k = F s_k` (F: the full 1 nm integration), and node indices on that grid, the weights W
//! minimise the *linearised CIELAB* error
//!
//! `Σ_k ‖J_k (W s_k − t_k) + H_k (W w_k − t_w,k)‖² + μ ‖W − W₀‖²`
//!
//! where `J_k = ∂Lab/∂XYZ` and `H_k = ∂Lab/∂white` at the exact colour and white, `w_k` is the
//! sample's white (its illuminant) integrated by the same set, `W₀` the box-filter weights of
//! the nodes' bands (∫ x̄ȳz̄ over each node's band) and `μ` a small ridge. To first order this is
//! the sum of squared ΔE*ab, with the white integrated by the set as in [`super::evaluate`].
//! Nodes: greedy selection on the 1 nm grid (add the node that most lowers the objective), then
//! coordinate descent moving each node by ±1..±5 nm until no move helps.

use std::string::String;
use std::vec::Vec;

use super::evaluate::{self, Curve, EvalSet};
use super::Derivation;

/// The default ridge μ relative to the mean diagonal of the CIELAB part of the normal matrix.
pub const RIDGE: f64 = 1e-6;

/// Weight (per training spectrum, in squared ΔE per squared relative error) of the residuals
/// that pin each XYZ row's scale: the anchor white integrated exactly.
pub const ANCHOR_WEIGHT: f64 = 1e6;

/// How far (grid steps, 1 nm) coordinate descent moves one node at a time.
pub const MAX_MOVE: usize = 5;

/// A shared set: distinct wavelengths (ascending) and XYZ weights for dλ in nm.
#[derive(Debug, Clone, PartialEq)]
pub struct SharedSet {
    /// `SHARED_<n>`.
    pub name: String,
    /// Distinct wavelengths in nm, ascending.
    pub wavelengths_nm: Vec<f64>,
    /// `xyz_weights[c][i]`: X, Y, Z rows.
    pub xyz_weights: [Vec<f64>; 3],
}

impl SharedSet {
    /// The set as the evaluation measures it (family `shared`).
    pub fn to_eval_set(&self) -> EvalSet {
        EvalSet {
            name: self.name.clone(),
            family: "shared".into(),
            orders: None,
            wavelengths_nm: self.wavelengths_nm.clone(),
            xyz_weights: self.xyz_weights.clone(),
        }
    }
}

/// The reference: every 1 nm of the derivation's range, weights x̄ȳz̄ · 1 nm.
pub fn reference_grid(d: &Derivation) -> Result<EvalSet, String> {
    evaluate::full_integration(&d.observer, d.settings.range_nm, 1.0)
}

fn light_on_grid(d: &Derivation, light: &Curve) -> Result<Vec<f64>, String> {
    let f = reference_grid(d)?;
    let v: Vec<f64> = f.wavelengths_nm.iter().map(|&l| light.at(l)).collect();
    let y: f64 = v.iter().zip(&f.xyz_weights[1]).map(|(a, b)| a * b).sum();
    Ok(v.iter().map(|x| x / y).collect())
}

/// Training radiances on the 1 nm reference grid: every reflectance times every illuminant,
/// each illuminant scaled so that its white has Y = 1 (illuminant-major order).
pub fn training_radiances(
    d: &Derivation,
    reflectances: &[Curve],
    illuminants: &[Curve],
) -> Vec<Vec<f64>> {
    let grid = reference_grid(d).expect("the derivation's range lies on its 1 nm table");
    let mut out = Vec::new();
    for light in illuminants {
        let l = light_on_grid(d, light).expect("1 nm grid");
        for r in reflectances {
            out.push(
                grid.wavelengths_nm
                    .iter()
                    .zip(&l)
                    .map(|(&nm, &e)| e * r.at(nm))
                    .collect(),
            );
        }
    }
    out
}

/// The white of each of [`training_radiances`]' spectra (its illuminant at Y = 1), in the same
/// order.
pub fn training_whites(
    d: &Derivation,
    reflectances: &[Curve],
    illuminants: &[Curve],
) -> Vec<Vec<f64>> {
    let mut out = Vec::new();
    for light in illuminants {
        let l = light_on_grid(d, light).expect("1 nm grid");
        for _ in reflectances {
            out.push(l.clone());
        }
    }
    out
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

/// ∂Lab/∂XYZ and ∂Lab/∂white (row-major 3×3) at `t` with white `w`.
fn lab_jacobians(t: [f64; 3], w: [f64; 3]) -> ([f64; 9], [f64; 9]) {
    let g = [0, 1, 2].map(|c| fprime(t[c] / w[c]) / w[c]);
    let h = [0, 1, 2].map(|c| -fprime(t[c] / w[c]) * t[c] / (w[c] * w[c]));
    let m = |v: [f64; 3]| {
        [
            0.0,
            116.0 * v[1],
            0.0,
            500.0 * v[0],
            -500.0 * v[1],
            0.0,
            0.0,
            200.0 * v[1],
            -200.0 * v[2],
        ]
    };
    (m(g), m(h))
}

fn mat_vec(m: &[f64; 9], v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|r| m[3 * r] * v[0] + m[3 * r + 1] * v[1] + m[3 * r + 2] * v[2])
}

/// The precomputed fitting problem for one training set: Gram blocks for every pair of 1 nm
/// candidates, so that any node set's weights cost one small solve.
#[derive(Debug, Clone)]
pub struct Trainer {
    grid_nm: Vec<f64>,
    /// x̄ȳz̄ · 1 nm on the grid.
    f: [Vec<f64>; 3],
    g: usize,
    /// `gram[a * g + b]` (3×3, row-major p, q): Σ_k Σ_r C_ka[r][p] C_kb[r][q].
    gram: Vec<[f64; 9]>,
    /// `rhs[a]`: Σ_k C_kaᵀ c_k.
    rhs: Vec<[f64; 3]>,
    /// Trace of each diagonal block of the CIELAB part (before the anchor).
    lab_trace: Vec<f64>,
    /// The ridge μ relative to the mean diagonal of the CIELAB part of the normal matrix
    /// ([`RIDGE`] by default).
    pub ridge: f64,
}

impl Trainer {
    /// Precomputes the problem. `whites[k]` is the white of `training[k]` (integrated by the set
    /// as CIELAB's white); `None`: an equal-energy white of Y = 1, held exact.
    pub fn new(
        d: &Derivation,
        training: &[Vec<f64>],
        whites: Option<&[Vec<f64>]>,
    ) -> Result<Trainer, String> {
        let reference = reference_grid(d)?;
        let g = reference.wavelengths_nm.len();
        let f = reference.xyz_weights.clone();
        let integrate = |s: &[f64]| -> [f64; 3] {
            [0, 1, 2].map(|c| f[c].iter().zip(s).map(|(a, b)| a * b).sum())
        };
        let unit = integrate(&std::vec![1.0; g]);
        let ee_white = unit.map(|v| v / unit[1]);
        // c_mat[a][k]: C_ka = s_k(a) J_k + w_k(a) H_k; c_vec[k] = J_k t_k + H_k t_w.
        let mut c_mat: Vec<Vec<[f64; 9]>> = std::vec![Vec::with_capacity(training.len()); g];
        let mut c_vec: Vec<[f64; 3]> = Vec::with_capacity(training.len());
        for (k, s) in training.iter().enumerate() {
            if s.len() != g {
                return Err(std::format!(
                    "training spectrum {k} has {} values; the 1 nm grid has {g}",
                    s.len()
                ));
            }
            let t = integrate(s);
            let (white, tw) = match whites {
                Some(w) => {
                    let w = w.get(k).ok_or("fewer whites than training spectra")?;
                    (Some(w), integrate(w))
                }
                None => (None, ee_white),
            };
            let (j, h) = lab_jacobians(t, tw);
            let jt = mat_vec(&j, t);
            let ht = mat_vec(&h, tw);
            c_vec.push([0, 1, 2].map(|r| jt[r] + if white.is_some() { ht[r] } else { 0.0 }));
            for a in 0..g {
                let mut m = [0.0; 9];
                for (e, v) in m.iter_mut().enumerate() {
                    *v = s[a] * j[e] + white.map_or(0.0, |w| w[a] * h[e]);
                }
                c_mat[a].push(m);
            }
        }
        let mut gram = std::vec![[0.0; 9]; g * g];
        for a in 0..g {
            for b in a..g {
                let mut acc = [0.0; 9];
                for (ca, cb) in c_mat[a].iter().zip(&c_mat[b]) {
                    for p in 0..3 {
                        for q in 0..3 {
                            acc[3 * p + q] +=
                                ca[p] * cb[q] + ca[3 + p] * cb[3 + q] + ca[6 + p] * cb[6 + q];
                        }
                    }
                }
                gram[a * g + b] = acc;
                gram[b * g + a] = [0, 1, 2, 3, 4, 5, 6, 7, 8].map(|e| acc[3 * (e % 3) + e / 3]);
            }
        }
        let mut rhs: Vec<[f64; 3]> = c_mat
            .iter()
            .map(|cs| {
                let mut v = [0.0; 3];
                for (m, c) in cs.iter().zip(&c_vec) {
                    for (p, x) in v.iter_mut().enumerate() {
                        *x += m[p] * c[0] + m[3 + p] * c[1] + m[6 + p] * c[2];
                    }
                }
                v
            })
            .collect();
        // CIELAB with the white integrated by the set ignores a scale per XYZ row, so the
        // linearised error has that null space (J t + H t_w = 0). The anchor pins it: the mean
        // white (equal energy without whites) integrated exactly, with a heavy weight.
        let anchor: Vec<f64> = match whites {
            Some(w) if !w.is_empty() => (0..g)
                .map(|a| w.iter().map(|s| s[a]).sum::<f64>() / w.len() as f64)
                .collect(),
            _ => std::vec![1.0 / unit[1]; g],
        };
        let lab_trace: Vec<f64> = (0..g)
            .map(|a| {
                let b = &gram[a * g + a];
                b[0] + b[4] + b[8]
            })
            .collect();
        let ta = integrate(&anchor);
        let omega2 = ANCHOR_WEIGHT * training.len().max(1) as f64;
        for a in 0..g {
            for c in 0..3 {
                rhs[a][c] += omega2 * anchor[a] / ta[c];
                for b in 0..g {
                    gram[a * g + b][4 * c] += omega2 * anchor[a] * anchor[b] / (ta[c] * ta[c]);
                }
            }
        }
        Ok(Trainer {
            grid_nm: reference.wavelengths_nm,
            f,
            g,
            gram,
            rhs,
            lab_trace,
            ridge: RIDGE,
        })
    }

    /// Box-filter prior: each grid point's x̄ȳz̄ · 1 nm goes to the nearest node.
    fn prior(&self, nodes: &[usize]) -> Vec<f64> {
        let mut w0 = std::vec![0.0; 3 * nodes.len()];
        for a in 0..self.g {
            let (i, _) = nodes
                .iter()
                .enumerate()
                .map(|(i, &n)| (i, n.abs_diff(a)))
                .min_by_key(|x| x.1)
                .unwrap_or((0, 0));
            for c in 0..3 {
                w0[3 * i + c] += self.f[c][a];
            }
        }
        w0
    }

    /// The weights (`w[3i + c]`) for grid indices `nodes`, and the objective without its
    /// constant term (lower is better).
    fn solve(&self, nodes: &[usize]) -> Option<(Vec<f64>, f64)> {
        let m = 3 * nodes.len();
        let mut a = std::vec![0.0; m * m];
        let mut b = std::vec![0.0; m];
        for (i, &ni) in nodes.iter().enumerate() {
            for (j, &nj) in nodes.iter().enumerate() {
                let blk = &self.gram[ni * self.g + nj];
                for p in 0..3 {
                    for q in 0..3 {
                        a[(3 * i + p) * m + 3 * j + q] = blk[3 * p + q];
                    }
                }
            }
            b[3 * i..3 * i + 3].copy_from_slice(&self.rhs[ni]);
        }
        let mu = self.ridge * nodes.iter().map(|&n| self.lab_trace[n]).sum::<f64>() / m as f64;
        let w0 = self.prior(nodes);
        for i in 0..m {
            a[i * m + i] += mu;
            b[i] += mu * w0[i];
        }
        let w = cholesky_solve(&mut a, &b, m)?;
        // Σ‖B w − c‖² + μ‖w − w0‖² = const − wᵀ b at the optimum.
        let obj = -w.iter().zip(&b).map(|(x, y)| x * y).sum::<f64>();
        Some((w, obj))
    }

    fn objective(&self, nodes: &[usize]) -> f64 {
        self.solve(nodes).map_or(f64::INFINITY, |s| s.1)
    }

    /// Greedy selection of `n` grid indices.
    pub fn greedy(&self, n: usize) -> Vec<usize> {
        let mut nodes: Vec<usize> = Vec::with_capacity(n);
        for _ in 0..n.min(self.g) {
            let mut best = (f64::INFINITY, 0);
            for c in 0..self.g {
                if nodes.contains(&c) {
                    continue;
                }
                nodes.push(c);
                let o = self.objective(&nodes);
                nodes.pop();
                if o < best.0 {
                    best = (o, c);
                }
            }
            nodes.push(best.1);
        }
        nodes
    }

    /// Coordinate descent: moves each node by up to ±[`MAX_MOVE`] grid steps while that lowers
    /// the objective.
    pub fn refine(&self, mut nodes: Vec<usize>) -> Vec<usize> {
        let mut current = self.objective(&nodes);
        for _ in 0..50 {
            let mut improved = false;
            for i in 0..nodes.len() {
                let start = nodes[i];
                let mut best = (current, start);
                for step in 1..=MAX_MOVE {
                    for c in [start.checked_sub(step), Some(start + step)]
                        .into_iter()
                        .flatten()
                    {
                        if c >= self.g || nodes.contains(&c) {
                            continue;
                        }
                        nodes[i] = c;
                        let o = self.objective(&nodes);
                        if o < best.0 - 1e-12 * best.0.abs() {
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
        nodes
    }

    /// The set for grid indices `nodes` (any order, distinct).
    pub fn set(&self, nodes: &[usize]) -> SharedSet {
        let mut nodes = nodes.to_vec();
        nodes.sort_unstable();
        let w = self
            .solve(&nodes)
            .map(|s| s.0)
            .unwrap_or_else(|| self.prior(&nodes));
        SharedSet {
            name: std::format!("SHARED_{}", nodes.len()),
            wavelengths_nm: nodes.iter().map(|&i| self.grid_nm[i]).collect(),
            xyz_weights: [0, 1, 2].map(|c| (0..nodes.len()).map(|i| w[3 * i + c]).collect()),
        }
    }

    /// Greedy selection, coordinate descent, weights.
    pub fn optimize(&self, n: usize) -> SharedSet {
        let nodes = self.refine(self.greedy(n));
        self.set(&nodes)
    }
}

/// Solves the symmetric positive definite system `a x = b` (`a` row-major m×m, overwritten).
fn cholesky_solve(a: &mut [f64], b: &[f64], m: usize) -> Option<Vec<f64>> {
    for j in 0..m {
        let mut s = a[j * m + j];
        for k in 0..j {
            s -= a[j * m + k] * a[j * m + k];
        }
        if s <= 0.0 || !s.is_finite() {
            return None;
        }
        let l = s.sqrt();
        a[j * m + j] = l;
        for i in j + 1..m {
            let mut s = a[i * m + j];
            for k in 0..j {
                s -= a[i * m + k] * a[j * m + k];
            }
            a[i * m + j] = s / l;
        }
    }
    let mut y = b.to_vec();
    for i in 0..m {
        for k in 0..i {
            y[i] -= a[i * m + k] * y[k];
        }
        y[i] /= a[i * m + i];
    }
    for i in (0..m).rev() {
        for k in i + 1..m {
            y[i] -= a[k * m + i] * y[k];
        }
        y[i] /= a[i * m + i];
    }
    Some(y)
}

/// A shared set of `n` wavelengths fitted to `training` (radiances on the 1 nm grid of the
/// derivation's range), the white of CIELAB taken as equal energy at Y = 1 and exact (see
/// [`Trainer::new`] with whites for the sample's own white integrated by the set). Panics if the
/// derivation's observer has no 1 nm table over its range or a spectrum is not on that grid.
pub fn optimize(d: &Derivation, training: &[Vec<f64>], n: usize) -> SharedSet {
    Trainer::new(d, training, None)
        .expect("training spectra on the 1 nm grid")
        .optimize(n)
}

/// As [`optimize`], with `whites[k]` the white of `training[k]`, integrated by the set.
pub fn optimize_with_whites(
    d: &Derivation,
    training: &[Vec<f64>],
    whites: &[Vec<f64>],
    n: usize,
) -> SharedSet {
    Trainer::new(d, training, Some(whites))
        .expect("training spectra on the 1 nm grid")
        .optimize(n)
}
