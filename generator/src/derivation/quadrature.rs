//! Gaussian quadrature with a (possibly signed) sampled weight function (Eq. 12-16).
//!
//! The weight function w(λ) is known on a grid, so the inner product of Eq. 14 is the discrete
//! sum ⟨g, h⟩ = Σ_j g(x_j) h(x_j) w(λ_j) dλ. The orthogonal polynomials come from the three-term
//! recurrence of Eq. 16 evaluated on that grid (the discretized Stieltjes procedure), in the
//! scaled variable x = (λ − centre) / half-width ∈ [−1, 1], never in raw nanometres.

use std::string::String;
use std::vec::Vec;

use nalgebra::{DMatrix, SymmetricEigen};

/// A discrete measure: point masses `mass[j] = w(λ_j) dλ` at `x[j]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Measure {
    /// Grid wavelengths in nm.
    pub wavelengths: Vec<f64>,
    /// The scaled abscissae, (λ − centre) / half_width.
    pub x: Vec<f64>,
    /// Point masses w(λ_j) dλ, in the units of w times nm.
    pub mass: Vec<f64>,
    /// Centre of the range in nm.
    pub centre: f64,
    /// Half the width of the range in nm.
    pub half_width: f64,
}

impl Measure {
    /// The measure of weight function `w` (one value per grid wavelength) for a grid of step
    /// `step` nm, scaled to the range `range_nm`.
    pub fn new(wavelengths: &[f64], w: &[f64], step: f64, range_nm: [f64; 2]) -> Measure {
        let centre = 0.5 * (range_nm[0] + range_nm[1]);
        let half_width = 0.5 * (range_nm[1] - range_nm[0]);
        Measure {
            wavelengths: wavelengths.to_vec(),
            x: wavelengths
                .iter()
                .map(|l| (l - centre) / half_width)
                .collect(),
            mass: w.iter().map(|v| v * step).collect(),
            centre,
            half_width,
        }
    }

    /// The scaled variable of a wavelength.
    pub fn to_x(&self, nm: f64) -> f64 {
        (nm - self.centre) / self.half_width
    }

    /// The wavelength of a scaled abscissa.
    pub fn to_nm(&self, x: f64) -> f64 {
        self.centre + self.half_width * x
    }
}

/// A norm |⟨P_k, P_k⟩| below this fraction of Σ |w| P_k² is indistinguishable from zero: the
/// signed sum has cancelled to within the rounding of its terms and of P_k itself (f64 epsilon
/// 2.2e-16 times the grid size and the growth of rounding in the recurrence, with margin).
pub const VANISHING_NORM: f64 = 1e-10;

/// A node whose imaginary part (in the scaled variable) exceeds this is complex. Eigenvalues of
/// a non-symmetric tridiagonal matrix near a double root carry about √ε ≈ 1.5e-8 of rounding
/// noise in their imaginary part; 1e-6 (2e-4 nm) is well above that and far below any spacing
/// that matters for a wavelength.
pub const COMPLEX_TOLERANCE: f64 = 1e-6;

/// The recurrence coefficients of Eq. 16 for the monic orthogonal polynomials:
/// P_{k+1} = (x − α_k) P_k − β_k P_{k−1}.
#[derive(Debug, Clone, PartialEq)]
pub struct Recurrence {
    /// α_k for k = 0..len.
    pub alpha: Vec<f64>,
    /// β_k for k = 0..len, with β_0 = ⟨P_0, P_0⟩ = ∫ w (the total mass).
    pub beta: Vec<f64>,
    /// ⟨P_k, P_k⟩, signed.
    pub norm: Vec<f64>,
    /// Σ |w| P_k², the size the signed norm is compared with.
    pub abs_norm: Vec<f64>,
    /// The first k whose norm vanished (then P_{k+1} and above do not exist), if any below the
    /// requested order.
    pub vanished_at: Option<usize>,
}

impl Recurrence {
    /// P_0(x), ..., P_{n}(x) by the recurrence (n ≤ number of coefficients).
    pub(crate) fn evaluate(&self, n: usize, x: f64) -> Vec<f64> {
        let mut p = Vec::with_capacity(n + 1);
        p.push(1.0);
        if n == 0 {
            return p;
        }
        p.push(x - self.alpha[0]);
        for k in 1..n {
            let next = (x - self.alpha[k]) * p[k] - self.beta[k] * p[k - 1];
            p.push(next);
        }
        p
    }

    /// P_n(x) and P_n'(x).
    pub(crate) fn value_and_derivative(&self, n: usize, x: f64) -> (f64, f64) {
        let (mut p0, mut p1) = (0.0, 1.0);
        let (mut d0, mut d1) = (0.0, 0.0);
        for k in 0..n {
            let b = if k == 0 { 0.0 } else { self.beta[k] };
            let p2 = (x - self.alpha[k]) * p1 - b * p0;
            let d2 = p1 + (x - self.alpha[k]) * d1 - b * d0;
            (p0, p1, d0, d1) = (p1, p2, d1, d2);
        }
        (p1, d1)
    }
}

/// The discretized Stieltjes procedure: α_k, β_k and the norms for k = 0..=order (so that the
/// rules of every order up to `order` can be formed), stopping where a norm vanishes.
pub fn stieltjes(measure: &Measure, order: usize) -> Recurrence {
    let n = measure.x.len();
    let mut rec = Recurrence {
        alpha: Vec::new(),
        beta: Vec::new(),
        norm: Vec::new(),
        abs_norm: Vec::new(),
        vanished_at: None,
    };
    let mut p_prev = std::vec![0.0; n];
    let mut p = std::vec![1.0; n];
    for k in 0..=order {
        let mut norm = 0.0;
        let mut abs_norm = 0.0;
        let mut moment = 0.0;
        for ((pj, m), x) in p.iter().zip(&measure.mass).zip(&measure.x) {
            let q = pj * pj;
            norm += m * q;
            abs_norm += m.abs() * q;
            moment += m * x * q;
        }
        rec.norm.push(norm);
        rec.abs_norm.push(abs_norm);
        if abs_norm.is_nan()
            || abs_norm <= 0.0
            || norm.abs() <= VANISHING_NORM * abs_norm
            || !norm.is_finite()
        {
            rec.vanished_at = Some(k);
            break;
        }
        let alpha = moment / norm;
        let beta = if k == 0 { norm } else { norm / rec.norm[k - 1] };
        rec.alpha.push(alpha);
        rec.beta.push(beta);
        let b = if k == 0 { 0.0 } else { beta };
        for ((pj, prev), x) in p.iter_mut().zip(p_prev.iter_mut()).zip(&measure.x) {
            let next = (x - alpha) * *pj - b * *prev;
            *prev = *pj;
            *pj = next;
        }
    }
    rec
}

/// Why a rule of some order is or is not usable.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Status {
    /// n real nodes inside the range.
    Defined,
    /// All nodes real, at least one outside the range.
    Outside,
    /// At least one pair of complex nodes.
    Complex,
    /// A norm ⟨P_k, P_k⟩ with k < n vanished: P_n does not exist.
    VanishingNorm,
}

impl Status {
    /// The name used in CSV output: `defined`, `outside`, `complex`, `vanishing-norm`.
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Defined => "defined",
            Status::Outside => "outside",
            Status::Complex => "complex",
            Status::VanishingNorm => "vanishing-norm",
        }
    }

    /// The name of the runtime enum variant (`spectral_quadrature::RuleStatus`).
    pub(crate) fn variant(self) -> &'static str {
        match self {
            Status::Defined => "Defined",
            Status::Outside => "Outside",
            Status::Complex => "Complex",
            Status::VanishingNorm => "VanishingNorm",
        }
    }
}

/// One channel's n-point rule, or why there is none.
#[derive(Debug, Clone, PartialEq)]
pub struct Rule {
    /// The number of nodes n.
    pub order: usize,
    /// The classification.
    pub status: Status,
    /// The real nodes in nm, ascending (for `Defined` and `Outside`; empty otherwise).
    pub nodes_nm: Vec<f64>,
    /// Weights for dλ in nm, one per node (for `Defined` and `Outside`).
    pub weights: Vec<f64>,
    /// The largest imaginary part of a node, in nm (0 for real nodes).
    pub max_imaginary_nm: f64,
    /// A sentence on why the rule is undefined, empty when defined.
    pub reason: String,
}

impl Rule {
    /// Whether the rule may be used.
    pub fn is_defined(&self) -> bool {
        self.status == Status::Defined
    }
}

/// The n-point Gauss rule of the measure: nodes are the eigenvalues of the Jacobi matrix; the
/// weights come from its eigenvectors (Golub-Welsch) where every β_k > 0, and from the
/// Christoffel numbers 1 / Σ_k P_k(x_i)² / ⟨P_k, P_k⟩ where the measure is indefinite.
pub fn gauss_rule(measure: &Measure, rec: &Recurrence, n: usize, range_nm: [f64; 2]) -> Rule {
    rule_from_recurrence(rec, n, |x| measure.to_nm(x), 1.0, range_nm)
}

/// [`gauss_rule`] for a recurrence in any variable: `to_nm` maps the variable to nm (affinely),
/// and `unit` is the length, in the variable, of one unit of the scaled variable; the complex
/// tolerance and the Newton step limit (both 1e-6 in the scaled variable) are multiplied by it.
/// The tools' stability study (`spectral_quadrature_tools::stability`) uses this to form rules
/// from a recurrence in raw nanometres.
pub fn rule_from_recurrence(
    rec: &Recurrence,
    n: usize,
    to_nm: impl Fn(f64) -> f64,
    unit: f64,
    range_nm: [f64; 2],
) -> Rule {
    let nm_per_unit = to_nm(1.0) - to_nm(0.0);
    let undefined = |status: Status, reason: String| Rule {
        order: n,
        status,
        nodes_nm: Vec::new(),
        weights: Vec::new(),
        max_imaginary_nm: 0.0,
        reason,
    };
    if n == 0 {
        return undefined(Status::VanishingNorm, "order 0 has no nodes".into());
    }
    if rec.alpha.len() < n {
        let k = rec.vanished_at.unwrap_or(rec.alpha.len());
        return undefined(
            Status::VanishingNorm,
            std::format!(
                "<P_{k}, P_{k}> vanishes (|norm| / sum |w| P_{k}^2 = {:.3e}), so P_{n} does not exist",
                rec.norm.get(k).zip(rec.abs_norm.get(k)).map_or(0.0, |(a, b)| (a / b).abs())
            ),
        );
    }
    let definite = rec.beta[1..n].iter().all(|&b| b > 0.0);
    let (mut xs, mut ws): (Vec<f64>, Vec<f64>);
    let mut max_imaginary = 0.0f64;
    if definite {
        let jacobi = DMatrix::from_fn(n, n, |i, j| {
            if i == j {
                rec.alpha[i]
            } else if i + 1 == j {
                rec.beta[j].sqrt()
            } else if j + 1 == i {
                rec.beta[i].sqrt()
            } else {
                0.0
            }
        });
        let eig = SymmetricEigen::new(jacobi);
        let mut pairs: Vec<(f64, f64)> = (0..n)
            .map(|i| {
                let v0 = eig.eigenvectors[(0, i)];
                (eig.eigenvalues[i], rec.beta[0] * v0 * v0)
            })
            .collect();
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
        xs = pairs.iter().map(|p| p.0).collect();
        ws = pairs.iter().map(|p| p.1).collect();
    } else {
        // Not symmetrizable when some β_k < 0. The product of the two off-diagonal entries is
        // all that fixes the characteristic polynomial, so put √|β_k| on both and the sign on
        // one: balanced, unlike the monic form (1 below, β_k above), whose eigenvalues lose
        // accuracy when |β_k| is large (C1's β_30 is about −6e4 in the scaled variable).
        let jacobi = DMatrix::from_fn(n, n, |i, j| {
            if i == j {
                rec.alpha[i]
            } else if j + 1 == i {
                rec.beta[i].abs().sqrt()
            } else if i + 1 == j {
                rec.beta[j].signum() * rec.beta[j].abs().sqrt()
            } else {
                0.0
            }
        });
        let eigenvalues = jacobi.complex_eigenvalues();
        max_imaginary = eigenvalues.iter().map(|z| z.im.abs()).fold(0.0, f64::max);
        if max_imaginary > COMPLEX_TOLERANCE * unit {
            let mut rule = undefined(
                Status::Complex,
                std::format!(
                    "complex nodes (largest imaginary part {:.3} nm)",
                    max_imaginary * nm_per_unit
                ),
            );
            rule.max_imaginary_nm = max_imaginary * nm_per_unit;
            return rule;
        }
        xs = eigenvalues.iter().map(|z| z.re).collect();
        xs.sort_by(f64::total_cmp);
        // Polish each real node with Newton steps on P_n evaluated by the recurrence.
        for x in xs.iter_mut() {
            for _ in 0..3 {
                let (p, d) = rec.value_and_derivative(n, *x);
                if d == 0.0 || !d.is_finite() {
                    break;
                }
                let step = p / d;
                if !step.is_finite() || step.abs() > 1e-6 * unit {
                    break;
                }
                *x -= step;
            }
        }
        ws = xs
            .iter()
            .map(|&x| {
                let p = rec.evaluate(n - 1, x);
                1.0 / p
                    .iter()
                    .zip(&rec.norm)
                    .map(|(pk, h)| pk * pk / h)
                    .sum::<f64>()
            })
            .collect();
    }
    let nodes_nm: Vec<f64> = xs.iter().map(|&x| to_nm(x)).collect();
    if !definite {
        ws.iter_mut()
            .for_each(|w| *w = if w.is_finite() { *w } else { f64::NAN });
    }
    real_rule(n, nodes_nm, ws, max_imaginary * nm_per_unit, range_nm)
}

/// A rule with real nodes, classified `Defined` when every node lies in the range and
/// `Outside` otherwise; a NaN node counts as outside, so no rule with one is ever `Defined`.
pub fn real_rule(
    order: usize,
    nodes_nm: Vec<f64>,
    weights: Vec<f64>,
    max_imaginary_nm: f64,
    range_nm: [f64; 2],
) -> Rule {
    let outside: Vec<f64> = nodes_nm
        .iter()
        .copied()
        .filter(|&l| !(l >= range_nm[0] && l <= range_nm[1]))
        .collect();
    let (status, reason) = if outside.is_empty() {
        (Status::Defined, String::new())
    } else {
        (
            Status::Outside,
            std::format!(
                "node(s) outside {}-{} nm: {}",
                range_nm[0],
                range_nm[1],
                outside
                    .iter()
                    .map(|l| std::format!("{l:.1}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        )
    };
    Rule {
        order,
        status,
        nodes_nm,
        weights,
        max_imaginary_nm,
        reason,
    }
}

/// The interpolatory weights of the measure at the given nodes (nm): w_i = ∫ ℓ_i(x) w dλ with the
/// Lagrange basis ℓ_i, so the rule is exact for polynomials of degree < n. Table 2's second row
/// uses these for the A channel on nodes borrowed from C1.
pub fn interpolatory_weights(measure: &Measure, nodes_nm: &[f64]) -> Vec<f64> {
    let xs: Vec<f64> = nodes_nm.iter().map(|&l| measure.to_x(l)).collect();
    (0..xs.len())
        .map(|i| {
            measure
                .x
                .iter()
                .zip(&measure.mass)
                .map(|(&x, &m)| {
                    let l: f64 = (0..xs.len())
                        .filter(|&k| k != i)
                        .map(|k| (x - xs[k]) / (xs[i] - xs[k]))
                        .product();
                    m * l
                })
                .sum()
        })
        .collect()
}
