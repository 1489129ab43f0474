//! Why the derivation computes its rules the way it does, and how close each classification is
//! to flipping.
//!
//! [`quadrature`](spectral_quadrature_generator::quadrature) forms the rules from the discretized Stieltjes recurrence
//! in the scaled variable x = (λ − centre) / half-width, nodes from the Jacobi matrix and weights
//! by Golub-Welsch or as Christoffel numbers. This module implements the textbook alternatives
//! and measures where each departs from that method:
//!
//! * [`vandermonde_weights`]: weights from the moment equations V^T w = m (LU solve), in the
//!   scaled variable, and [`vandermonde_weights_nm`] with powers of λ in nm;
//! * [`raw_nm_recurrence`]: the same recurrence and rules with x = λ in nanometres;
//! * [`monomial_roots`]: the roots of P_n expanded in the monomial basis, from the eigenvalues
//!   of its companion matrix, in the scaled variable, and [`monomial_roots_nm`] in nm.
//!
//! [`compare`] tabulates their node and weight errors order by order against the chosen rules
//! (with each rule's [`moment_residual`], which needs no reference) and [`breakdown_order`]
//! finds the first order at which each fails a [`Tolerance`]. [`margins`] says, for every order,
//! how far the quantity that decided its [`Status`] lies from the threshold that would change
//! it, and [`CLEAR_MARGIN`] says when that distance is clear. [`perturbed_derivation`] reruns
//! the derivation on the observer perturbed at the rounding level of the CIE tables, to check
//! that classifications with a clear margin do not flip. `tests/stability.rs` records the
//! measured breakdown orders and margins.

use std::string::String;
use std::vec::Vec;

use nalgebra::{DMatrix, DVector};

use spectral_quadrature_generator::quadrature::{
    gauss_rule, interpolatory_weights, real_rule, rule_from_recurrence, stieltjes, Measure,
    Recurrence, Rule, Status, COMPLEX_TOLERANCE, VANISHING_NORM,
};
use spectral_quadrature_generator::{derive_with, Derivation, Error, Observer, Settings};

/// Channel names in the order of the derivation's arrays.
pub const CHANNELS: [&str; 3] = ["A", "C1", "C2"];

// ---------------------------------------------------------------------------------------------
// The alternatives
// ---------------------------------------------------------------------------------------------

/// The monomial moments m_k = Σ_j mass_j x_j^k, k = 0..count, in the scaled variable.
pub fn monomial_moments(measure: &Measure, count: usize) -> Vec<f64> {
    moments(&measure.x, &measure.mass, count)
}

fn moments(points: &[f64], mass: &[f64], count: usize) -> Vec<f64> {
    let mut power: Vec<f64> = std::vec![1.0; points.len()];
    let mut out = Vec::with_capacity(count);
    for _ in 0..count {
        out.push(power.iter().zip(mass).map(|(p, m)| p * m).sum());
        for (p, x) in power.iter_mut().zip(points) {
            *p *= x;
        }
    }
    out
}

/// The textbook unstable weights: solve V^T w = m with V_ik = x_i^k (k = 0..n) and the monomial
/// moments m (scaled variable), by LU with partial pivoting. In exact arithmetic these are the
/// interpolatory weights of the nodes, so the Gauss weights at Gauss nodes; in f64 the
/// Vandermonde matrix's condition number grows exponentially with n. All NaN if LU finds the
/// matrix singular.
pub fn vandermonde_weights(measure: &Measure, nodes_nm: &[f64]) -> Vec<f64> {
    let xs: Vec<f64> = nodes_nm.iter().map(|&l| measure.to_x(l)).collect();
    vandermonde_solve(&xs, moments(&measure.x, &measure.mass, xs.len()))
}

/// [`vandermonde_weights`] with the monomials in raw nanometres, V_ik = λ_i^k and
/// m_k = Σ mass λ^k: the powers span 380^k to 770^k, so the columns' scales differ by about
/// 575^k and the conditioning is far worse than in the scaled variable.
pub fn vandermonde_weights_nm(measure: &Measure, nodes_nm: &[f64]) -> Vec<f64> {
    vandermonde_solve(
        nodes_nm,
        moments(&measure.wavelengths, &measure.mass, nodes_nm.len()),
    )
}

fn vandermonde_solve(xs: &[f64], moments: Vec<f64>) -> Vec<f64> {
    let n = xs.len();
    if n == 0 {
        return Vec::new();
    }
    let vt = DMatrix::from_fn(n, n, |k, i| xs[i].powi(k as i32));
    match vt.lu().solve(&DVector::from_vec(moments)) {
        Some(w) => w.iter().copied().collect(),
        None => std::vec![f64::NAN; n],
    }
}

/// The recurrence and rules of [`raw_nm_recurrence`].
#[derive(Debug, Clone, PartialEq)]
pub struct RawNmRecurrence {
    /// α_k, β_k and the norms of the monic polynomials in λ (nm): α_k in nm, β_k (k ≥ 1) in nm².
    pub recurrence: Recurrence,
    /// `rules[n - 1]`: the rule of order n, n = 1..=order.
    pub rules: Vec<Rule>,
}

/// The derivation's recurrence and rules with the variable left in nanometres (x = λ, not
/// scaled): P_k are monic in λ, so they and their norms grow like (half-width / 2)^k ≈ 97.5^k
/// (not 575^k: the recurrence subtracts α_k ≈ 575 nm at every step, so it centres itself), and
/// the Jacobi matrix carries α_k ≈ 575 nm on its diagonal. Rules are formed exactly as
/// [`gauss_rule`] forms them (Golub-Welsch where every β_k > 0, otherwise eigenvalues of the
/// monic Jacobi matrix, Newton polish and Christoffel numbers), with the complex tolerance and
/// Newton step limit converted to nm (× half-width) so that the classification thresholds are
/// the same as the scaled method's.
pub fn raw_nm_recurrence(measure: &Measure, order: usize) -> RawNmRecurrence {
    let recurrence = raw_nm_recurrence_only(measure, order);
    let range_nm = range_of(measure);
    let rules = (1..=order)
        .map(|n| rule_from_recurrence(&recurrence, n, |x| x, measure.half_width, range_nm))
        .collect();
    RawNmRecurrence { recurrence, rules }
}

/// The monomial coefficients c_0..=c_n (lowest first, c_n = 1) of the monic P_n of a recurrence,
/// expanded with P_{k+1} = (x − α_k) P_k − β_k P_{k−1}.
pub fn monomial_coefficients(rec: &Recurrence, n: usize) -> Vec<f64> {
    let mut prev: Vec<f64> = Vec::new();
    let mut p: Vec<f64> = std::vec![1.0];
    for k in 0..n {
        let b = if k == 0 { 0.0 } else { rec.beta[k] };
        let mut next = std::vec![0.0; k + 2];
        for (j, c) in p.iter().enumerate() {
            next[j + 1] += c;
            next[j] -= rec.alpha[k] * c;
        }
        for (j, c) in prev.iter().enumerate() {
            next[j] -= b * c;
        }
        prev = p;
        p = next;
    }
    p
}

/// The order-n rule from the roots of P_n in the monomial basis: P_n's coefficients in the
/// **scaled** variable (the fair comparison: in nm they would also carry 575^k, see
/// [`monomial_roots_nm`]) are expanded from the derivation's own recurrence
/// ([`monomial_coefficients`]), so only the change of basis and the root finding differ from
/// [`gauss_rule`]. The roots are the eigenvalues of the companion matrix (nalgebra's
/// `complex_eigenvalues`, which does not balance), not polished. Classified as [`gauss_rule`]
/// does (complex above [`COMPLEX_TOLERANCE`], outside the range, defined); the weights are the
/// interpolatory weights at these roots ([`interpolatory_weights`], a stable formula), so their
/// error is what the node error causes.
pub fn monomial_roots(measure: &Measure, order: usize) -> Rule {
    let rec = stieltjes(measure, order);
    companion_rule(
        measure,
        &rec,
        order,
        |x| measure.to_nm(x),
        measure.half_width,
    )
}

/// [`monomial_roots`] in raw nanometres: P_n(λ)'s monomial coefficients expanded from
/// [`raw_nm_recurrence`]'s coefficients (c_0 is of order 575^n), roots from the companion
/// matrix in nm, the complex tolerance converted to nm (× half-width).
pub fn monomial_roots_nm(measure: &Measure, order: usize) -> Rule {
    let rec = raw_nm_recurrence_only(measure, order);
    companion_rule(measure, &rec, order, |x| x, 1.0)
}

/// The recurrence of [`raw_nm_recurrence`] without its rules.
fn raw_nm_recurrence_only(measure: &Measure, order: usize) -> Recurrence {
    stieltjes(&raw_measure(measure), order)
}

fn raw_measure(measure: &Measure) -> Measure {
    Measure {
        wavelengths: measure.wavelengths.clone(),
        x: measure.wavelengths.clone(),
        mass: measure.mass.clone(),
        centre: 0.0,
        half_width: 1.0,
    }
}

/// The rule from the companion matrix of P_n's monomial coefficients; `to_nm` maps the
/// recurrence's variable to nm and `nm_per_unit` is the length of one of its units in nm.
fn companion_rule(
    measure: &Measure,
    rec: &Recurrence,
    order: usize,
    to_nm: impl Fn(f64) -> f64,
    nm_per_unit: f64,
) -> Rule {
    let range_nm = range_of(measure);
    if order == 0 || rec.alpha.len() < order {
        return undefined_rule(
            order,
            Status::VanishingNorm,
            "a norm vanishes below this order".into(),
        );
    }
    let c = monomial_coefficients(rec, order);
    let n = order;
    let companion = DMatrix::from_fn(n, n, |i, j| {
        if j == n - 1 {
            -c[i]
        } else if i == j + 1 {
            1.0
        } else {
            0.0
        }
    });
    let roots = companion.complex_eigenvalues();
    let max_imaginary_nm = roots.iter().map(|z| z.im.abs()).fold(0.0, f64::max) * nm_per_unit;
    if exceeds(max_imaginary_nm, COMPLEX_TOLERANCE * measure.half_width) {
        let mut rule = undefined_rule(
            n,
            Status::Complex,
            std::format!("complex roots (largest imaginary part {max_imaginary_nm:.3} nm)"),
        );
        rule.max_imaginary_nm = max_imaginary_nm;
        return rule;
    }
    let mut nodes_nm: Vec<f64> = roots.iter().map(|z| to_nm(z.re)).collect();
    nodes_nm.sort_by(f64::total_cmp);
    let weights = interpolatory_weights(measure, &nodes_nm);
    real_rule(n, nodes_nm, weights, max_imaginary_nm, range_nm)
}

/// `v > limit`, or `v` is NaN: a failure whenever the value is not known to be within the limit.
fn exceeds(v: f64, limit: f64) -> bool {
    v > limit || v.is_nan()
}

/// `v > limit` and not NaN: a margin counts only when it is known to be there.
fn above(v: f64, limit: f64) -> bool {
    v > limit
}

/// The range a measure was scaled to, in nm.
fn range_of(measure: &Measure) -> [f64; 2] {
    [
        measure.centre - measure.half_width,
        measure.centre + measure.half_width,
    ]
}

fn undefined_rule(order: usize, status: Status, reason: String) -> Rule {
    Rule {
        order,
        status,
        nodes_nm: Vec::new(),
        weights: Vec::new(),
        max_imaginary_nm: 0.0,
        reason,
    }
}

// ---------------------------------------------------------------------------------------------
// Comparison with the chosen method
// ---------------------------------------------------------------------------------------------

/// A way of computing the rules.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Method {
    /// The derivation's own: [`stieltjes`] and [`gauss_rule`] (compared with itself, as a check).
    Chosen,
    /// The chosen nodes with [`vandermonde_weights`] (scaled variable).
    Vandermonde,
    /// The chosen nodes with [`vandermonde_weights_nm`].
    VandermondeNm,
    /// [`raw_nm_recurrence`].
    RawNm,
    /// [`monomial_roots`] (scaled variable).
    MonomialRoots,
    /// [`monomial_roots_nm`].
    MonomialRootsNm,
}

impl Method {
    /// Every method, the chosen one first.
    pub const ALL: [Method; 6] = [
        Method::Chosen,
        Method::Vandermonde,
        Method::VandermondeNm,
        Method::RawNm,
        Method::MonomialRoots,
        Method::MonomialRootsNm,
    ];

    /// A short name for tables.
    pub fn name(self) -> &'static str {
        match self {
            Method::Chosen => "chosen",
            Method::Vandermonde => "vandermonde",
            Method::VandermondeNm => "vandermonde-nm",
            Method::RawNm => "raw-nm",
            Method::MonomialRoots => "monomial-roots",
            Method::MonomialRootsNm => "monomial-roots-nm",
        }
    }

    /// The rules of orders 1..=max_order by this method (`reference`: the chosen rules, whose
    /// nodes the Vandermonde methods reuse).
    pub fn rules(self, measure: &Measure, reference: &[Rule]) -> Vec<Rule> {
        let max_order = reference.len();
        let with_weights = |f: fn(&Measure, &[f64]) -> Vec<f64>| {
            reference
                .iter()
                .map(|r| Rule {
                    weights: f(measure, &r.nodes_nm),
                    ..r.clone()
                })
                .collect()
        };
        match self {
            Method::Chosen => reference.to_vec(),
            Method::Vandermonde => with_weights(vandermonde_weights),
            Method::VandermondeNm => with_weights(vandermonde_weights_nm),
            Method::RawNm => raw_nm_recurrence(measure, max_order).rules,
            Method::MonomialRoots => (1..=max_order)
                .map(|n| monomial_roots(measure, n))
                .collect(),
            Method::MonomialRootsNm => (1..=max_order)
                .map(|n| monomial_roots_nm(measure, n))
                .collect(),
        }
    }
}

/// When an alternative counts as broken down at an order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerance {
    /// Largest acceptable node error, nm.
    pub node_nm: f64,
    /// Largest acceptable weight error as a fraction of Σ |w| of the chosen rule.
    pub weight_relative: f64,
}

/// The breakdown tolerance: nodes within 0.01 nm (a tenth of the precision the paper prints),
/// weights within 1e-6 of Σ |w| (far below what a colour needs): beyond it a method's tables
/// would differ visibly.
pub const BREAKDOWN_TOLERANCE: Tolerance = Tolerance {
    node_nm: 0.01,
    weight_relative: 1e-6,
};

/// A stricter tolerance that marks where a method starts losing accuracy: nodes within 1e-6 nm
/// and weights within 1e-10 of Σ |w|, about a thousand times the chosen method's own error
/// (its nodes reproduce the rules' moments to about 1e-12 relative up to order 30).
pub const ACCURACY_TOLERANCE: Tolerance = Tolerance {
    node_nm: 1e-6,
    weight_relative: 1e-10,
};

/// One order of one channel: how an alternative's rule differs from the chosen rule.
#[derive(Debug, Clone, PartialEq)]
pub struct OrderError {
    /// The order n.
    pub order: usize,
    /// The chosen rule's classification.
    pub reference: Status,
    /// The alternative's classification.
    pub alternative: Status,
    /// max_i |λ_i − λ_i^ref| in nm, where both have n real nodes.
    pub node_error_nm: Option<f64>,
    /// max_i |w_i − w_i^ref| / Σ |w^ref|, where both have n real nodes and finite reference
    /// weights.
    pub weight_error: Option<f64>,
    /// Whether the alternative's nodes and weights are all finite.
    pub finite: bool,
    /// [`moment_residual`] of the chosen rule: how exact the reference itself is.
    pub reference_residual: Option<f64>,
    /// [`moment_residual`] of the alternative's rule, judged without the reference.
    pub alternative_residual: Option<f64>,
}

impl OrderError {
    /// Whether the alternative has failed at this order: a different classification, a
    /// non-finite node or weight, or an error above the tolerance.
    pub fn fails(&self, tolerance: &Tolerance) -> bool {
        self.reference != self.alternative
            || !self.finite
            || self
                .node_error_nm
                .is_some_and(|e| exceeds(e, tolerance.node_nm))
            || self
                .weight_error
                .is_some_and(|e| exceeds(e, tolerance.weight_relative))
    }
}

/// The first order at which `errors` fail the tolerance ([`OrderError::fails`]), if any.
pub fn breakdown_order(errors: &[OrderError], tolerance: &Tolerance) -> Option<usize> {
    errors.iter().find(|e| e.fails(tolerance)).map(|e| e.order)
}

/// How exactly a rule with real nodes integrates the monomials x^k, k = 0..2n (the degree a
/// Gauss rule must integrate exactly), in the scaled variable: the largest
/// |Σ w_i x_i^k − Σ mass_j x_j^k| / max(Σ |mass_j x_j^k|, Σ |w_i x_i^k|). `None` without nodes.
/// A reference-free check of a rule's accuracy (for nodes outside the range |x| > 1, so the
/// highest powers dominate).
pub fn moment_residual(measure: &Measure, rule: &Rule) -> Option<f64> {
    if rule.nodes_nm.is_empty() || rule.nodes_nm.len() != rule.weights.len() {
        return None;
    }
    let xs: Vec<f64> = rule.nodes_nm.iter().map(|&l| measure.to_x(l)).collect();
    let mut node_power: Vec<f64> = std::vec![1.0; xs.len()];
    let mut grid_power: Vec<f64> = std::vec![1.0; measure.x.len()];
    let mut worst = 0.0f64;
    for _ in 0..2 * xs.len() {
        let quad: f64 = node_power
            .iter()
            .zip(&rule.weights)
            .map(|(p, w)| p * w)
            .sum();
        let exact: f64 = integrate(measure, &grid_power);
        let scale = node_power
            .iter()
            .zip(&rule.weights)
            .map(|(p, w)| (p * w).abs())
            .sum::<f64>()
            .max(
                grid_power
                    .iter()
                    .zip(&measure.mass)
                    .map(|(p, m)| (p * m).abs())
                    .sum(),
            );
        let r = (quad - exact).abs() / scale;
        worst = if r.is_nan() { f64::NAN } else { worst.max(r) };
        for (p, x) in node_power.iter_mut().zip(&xs) {
            *p *= x;
        }
        for (p, x) in grid_power.iter_mut().zip(&measure.x) {
            *p *= x;
        }
    }
    Some(worst)
}

/// One method on one channel, orders 1..=max_order.
#[derive(Debug, Clone, PartialEq)]
pub struct MethodComparison {
    /// The method.
    pub method: Method,
    /// The channel (0 A, 1 C1, 2 C2).
    pub channel: usize,
    /// `errors[n - 1]`: order n.
    pub errors: Vec<OrderError>,
    /// [`breakdown_order`] of `errors` with the comparison's tolerance.
    pub breakdown: Option<usize>,
}

/// Every method on every channel.
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    /// The highest order compared.
    pub max_order: usize,
    /// The tolerance of the [`MethodComparison::breakdown`] orders.
    pub tolerance: Tolerance,
    /// One entry per method and channel, in the order of [`Method::ALL`] then channel.
    pub methods: Vec<MethodComparison>,
}

impl Comparison {
    /// The entry of a method and channel.
    pub fn get(&self, method: Method, channel: usize) -> Option<&MethodComparison> {
        self.methods
            .iter()
            .find(|m| m.method == method && m.channel == channel)
    }

    /// The first order at which a method fails `tolerance` on a channel (`None`: not up to
    /// `max_order`, or no such entry).
    pub fn breakdown(
        &self,
        method: Method,
        channel: usize,
        tolerance: &Tolerance,
    ) -> Option<usize> {
        self.get(method, channel)
            .and_then(|m| breakdown_order(&m.errors, tolerance))
    }

    /// A plain-text table of breakdown orders for `tolerance`, one row per method.
    pub fn breakdown_table(&self, tolerance: &Tolerance) -> String {
        let mut s = std::format!(
            "breakdown order (nodes > {:e} nm, weights > {:e} of sum |w|, non-finite, or another classification)\n{:<18}",
            tolerance.node_nm, tolerance.weight_relative, "method"
        );
        for c in CHANNELS {
            s.push_str(&std::format!(" {c:>6}"));
        }
        s.push('\n');
        for method in Method::ALL {
            s.push_str(&std::format!("{:<18}", method.name()));
            for c in 0..3 {
                let cell = match self.breakdown(method, c, tolerance) {
                    Some(n) => std::format!("{n}"),
                    None => std::format!(">{}", self.max_order),
                };
                s.push_str(&std::format!(" {cell:>6}"));
            }
            s.push('\n');
        }
        s
    }

    /// A plain-text table: the breakdown orders for [`BREAKDOWN_TOLERANCE`] and
    /// [`ACCURACY_TOLERANCE`], then per method each order's largest node error (nm), weight
    /// error (of Σ |w|) and [`moment_residual`] per channel; `-` where there are no nodes to
    /// compare, `*` after an entry whose classification differs from the chosen one or whose
    /// values are not all finite.
    pub fn table(&self) -> String {
        let mut s = self.breakdown_table(&BREAKDOWN_TOLERANCE);
        s.push('\n');
        s.push_str(&self.breakdown_table(&ACCURACY_TOLERANCE));
        let fmt = |v: Option<f64>| v.map_or("-".into(), |v| std::format!("{v:.1e}"));
        for method in Method::ALL {
            s.push_str(&std::format!(
                "\n{}: node error (nm) / weight error (of sum |w|) / moment residual\n{:>3}",
                method.name(),
                "n"
            ));
            for c in CHANNELS {
                s.push_str(&std::format!(" {c:>26}"));
            }
            s.push('\n');
            for n in 1..=self.max_order {
                s.push_str(&std::format!("{n:>3}"));
                for c in 0..3 {
                    let cell = match self.get(method, c).and_then(|m| m.errors.get(n - 1)) {
                        Some(e) => {
                            let flag = if e.reference != e.alternative || !e.finite {
                                "*"
                            } else {
                                " "
                            };
                            std::format!(
                                "{}/{}/{}{flag}",
                                fmt(e.node_error_nm),
                                fmt(e.weight_error),
                                fmt(e.alternative_residual)
                            )
                        }
                        None => "?".into(),
                    };
                    s.push_str(&std::format!(" {cell:>26}"));
                }
                s.push('\n');
            }
        }
        s
    }
}

/// The chosen method's rules of orders 1..=max_order for a measure: [`stieltjes`] then
/// [`gauss_rule`], as the derivation forms them.
pub fn chosen_rules(measure: &Measure, max_order: usize) -> Vec<Rule> {
    let rec = stieltjes(measure, max_order);
    let range_nm = range_of(measure);
    (1..=max_order)
        .map(|n| gauss_rule(measure, &rec, n, range_nm))
        .collect()
}

/// How `alternative` differs from `reference` (both of the same order on `measure`).
pub fn order_error(measure: &Measure, reference: &Rule, alternative: &Rule) -> OrderError {
    let finite = alternative
        .nodes_nm
        .iter()
        .chain(&alternative.weights)
        .all(|v| v.is_finite());
    let comparable = !reference.nodes_nm.is_empty()
        && reference.nodes_nm.len() == alternative.nodes_nm.len()
        && reference.weights.len() == alternative.weights.len();
    let max_abs_diff = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0f64, |m, d| if d.is_nan() { f64::NAN } else { m.max(d) })
    };
    let node_error_nm =
        comparable.then(|| max_abs_diff(&reference.nodes_nm, &alternative.nodes_nm));
    let weight_error = if comparable && reference.weights.iter().all(|w| w.is_finite()) {
        let scale: f64 = reference.weights.iter().map(|w| w.abs()).sum();
        Some(max_abs_diff(&reference.weights, &alternative.weights) / scale)
    } else {
        None
    };
    OrderError {
        order: reference.order,
        reference: reference.status,
        alternative: alternative.status,
        node_error_nm,
        weight_error,
        finite,
        reference_residual: moment_residual(measure, reference),
        alternative_residual: moment_residual(measure, alternative),
    }
}

/// Every [`Method`] against the chosen method on each of the derivation's measures, orders
/// 1..=max_order (capped at one less than the grid size), with breakdown orders for `tolerance`.
pub fn compare(derivation: &Derivation, max_order: usize, tolerance: Tolerance) -> Comparison {
    let max_order = max_order.min(derivation.grid_nm.len().saturating_sub(1));
    let references: Vec<Vec<Rule>> = derivation
        .measures
        .iter()
        .map(|m| chosen_rules(m, max_order))
        .collect();
    let mut methods = Vec::new();
    for method in Method::ALL {
        for (c, measure) in derivation.measures.iter().enumerate() {
            let reference = &references[c];
            let errors: Vec<OrderError> = reference
                .iter()
                .zip(method.rules(measure, reference))
                .map(|(r, a)| order_error(measure, r, &a))
                .collect();
            let breakdown = breakdown_order(&errors, &tolerance);
            methods.push(MethodComparison {
                method,
                channel: c,
                errors,
                breakdown,
            });
        }
    }
    Comparison {
        max_order,
        tolerance,
        methods,
    }
}

// ---------------------------------------------------------------------------------------------
// Margins of the classification
// ---------------------------------------------------------------------------------------------

/// What counts as a clear margin: a classification whose deciding quantities all pass these
/// should not be flipped by perturbing the data at its rounding level.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClearMargin {
    /// The smallest norm ratio min_{k<n} |⟨P_k,P_k⟩| / Σ |w| P_k² must exceed
    /// `norm_factor` × [`VANISHING_NORM`] (or, for a vanishing norm, lie below it divided by
    /// `norm_factor`).
    pub norm_factor: f64,
    /// A complex order's largest |Im| of a node must exceed this, nm.
    pub imaginary_nm: f64,
    /// A real order's deciding node (see [`OrderMargin::range_margin_nm`]) must be this far
    /// from the nearer range end, nm. Waived for a positive measure whose grid lies within the
    /// range: its Gauss nodes lie strictly inside the grid's span, so they cannot leave the
    /// range however close to its end they come.
    pub range_nm: f64,
    /// A real order of an indefinite recurrence (some β_k ≤ 0, so two real nodes could merge
    /// into a complex pair) must have adjacent nodes at least this far apart, nm.
    pub gap_nm: f64,
}

/// The clear margin the tests use:
///
/// * norms: ratio > 1e3 × [`VANISHING_NORM`] = 1e-7 (three decades above the threshold, which
///   itself is about five above the rounding of the sums);
/// * complex nodes: |Im| > 1 nm. Near a collision the imaginary part goes like the square root
///   of the discriminant, so a relative perturbation u of the data moves it by about
///   √u × half-width ≈ 0.14 nm for u = 5e-7; 1 nm is several times that (and about 5000 ×
///   [`COMPLEX_TOLERANCE`], 0.000195 nm);
/// * real nodes near a range end: > 1 nm, the same bound for nodes that move linearly with the
///   data (u × the range's 390 nm is 2e-4 nm; nodes near the ends move by about 1e-3 nm);
///   not applied to a positive measure (channel A), whose nodes cannot leave its grid's span;
/// * real nodes of an indefinite recurrence: adjacent nodes > 1 nm apart (a collision is the
///   mirror image of a small imaginary part).
///
/// Under the coarser 6-decimal rounding of the 5 nm data ([`ROUNDING_LEVEL_ABSOLUTE`]) nodes of
/// orders ≤ 16 move by up to about 0.6 nm and imaginary parts by up to about 0.3 nm, so there
/// the same thresholds leave a factor of two or more, not hundreds.
pub const CLEAR_MARGIN: ClearMargin = ClearMargin {
    norm_factor: 1e3,
    imaginary_nm: 1.0,
    range_nm: 1.0,
    gap_nm: 1.0,
};

/// How far one order's classification is from flipping.
#[derive(Debug, Clone, PartialEq)]
pub struct OrderMargin {
    /// The order n.
    pub order: usize,
    /// Its classification.
    pub status: Status,
    /// The smallest |⟨P_k,P_k⟩| / Σ |w| P_k² over k < n (for a vanishing norm: that of the norm
    /// that vanished).
    pub norm_ratio: f64,
    /// `norm_ratio / VANISHING_NORM` where no norm vanished (> 1), and `VANISHING_NORM /
    /// norm_ratio` where one did (≥ 1): the factor by which the norm sits on its side of the
    /// threshold.
    pub norm_margin: f64,
    /// Whether every β_k, 1 ≤ k < n, is positive (then the nodes are real and distinct).
    pub definite: bool,
    /// Whether every mass of the measure is ≥ 0 and its grid lies within the range (then the
    /// nodes lie strictly inside the range and the range criterion is waived).
    pub positive: bool,
    /// The largest |Im| of a node in nm (0 for the definite branch).
    pub max_imaginary_nm: f64,
    /// For a complex order, `max|Im| / (COMPLEX_TOLERANCE × half-width)`; for a real order of an
    /// indefinite recurrence, its inverse (the factor the rounding noise in Im sits below the
    /// tolerance, infinite for exactly real nodes); `None` otherwise.
    pub imag_margin: Option<f64>,
    /// For real nodes, the signed distance in nm from the range end of the node that decides the
    /// classification: for `Defined`, the node nearest an end (positive: inside); for
    /// `Outside`, minus the distance of the node farthest outside (the order becomes defined
    /// only when that node comes in).
    pub range_margin_nm: Option<f64>,
    /// For two or more real nodes, the smallest distance between adjacent nodes, nm.
    pub min_gap_nm: Option<f64>,
    /// Whether the margin is clear by [`ClearMargin`].
    pub clear: bool,
    /// Which criteria failed the clear margin, empty when clear.
    pub unclear: String,
}

/// The margin of one order's rule given its measure and recurrence, judged by `clear`.
pub fn order_margin(
    measure: &Measure,
    rec: &Recurrence,
    rule: &Rule,
    clear: &ClearMargin,
) -> OrderMargin {
    let n = rule.order;
    let range_nm = range_of(measure);
    let vanished = rule.status == Status::VanishingNorm;
    let norm_ratio = if vanished {
        rec.vanished_at
            .filter(|&k| k < rec.norm.len())
            .map_or(0.0, |k| norm_ratio(rec, k))
    } else {
        (0..n.min(rec.norm.len()))
            .map(|k| norm_ratio(rec, k))
            .fold(f64::INFINITY, f64::min)
    };
    let norm_margin = if vanished {
        VANISHING_NORM / norm_ratio
    } else {
        norm_ratio / VANISHING_NORM
    };
    let definite = !vanished && rec.beta.len() >= n && rec.beta[1..n].iter().all(|&b| b > 0.0);
    let positive = measure.mass.iter().all(|&m| m >= 0.0)
        && measure
            .wavelengths
            .iter()
            .all(|&l| l >= range_nm[0] && l <= range_nm[1]);
    let tolerance_nm = COMPLEX_TOLERANCE * measure.half_width;
    let imag_margin = match rule.status {
        Status::Complex => Some(rule.max_imaginary_nm / tolerance_nm),
        Status::Defined | Status::Outside if !definite => {
            Some(tolerance_nm / rule.max_imaginary_nm)
        }
        _ => None,
    };
    let distance_inside = |l: f64| (l - range_nm[0]).min(range_nm[1] - l);
    // The smallest signed distance is the deciding node's in both cases: the node nearest an
    // end when all are inside, the node farthest outside otherwise.
    let range_margin_nm = matches!(rule.status, Status::Defined | Status::Outside).then(|| {
        rule.nodes_nm
            .iter()
            .map(|&l| distance_inside(l))
            .fold(f64::INFINITY, f64::min)
    });
    let min_gap_nm = (rule.nodes_nm.len() >= 2).then(|| {
        rule.nodes_nm
            .windows(2)
            .map(|p| p[1] - p[0])
            .fold(f64::INFINITY, f64::min)
    });
    let mut unclear = Vec::new();
    if !above(norm_margin, clear.norm_factor) {
        unclear.push(std::format!("norm margin {norm_margin:.2e}"));
    }
    match rule.status {
        Status::Complex if !above(rule.max_imaginary_nm, clear.imaginary_nm) => unclear.push(
            std::format!("imaginary part {:.3} nm", rule.max_imaginary_nm),
        ),
        Status::Defined | Status::Outside => {
            if let Some(r) =
                range_margin_nm.filter(|r| !positive && !above(r.abs(), clear.range_nm))
            {
                unclear.push(std::format!("node {r:.3} nm from the range end"));
            }
            if !definite {
                if let Some(g) = min_gap_nm.filter(|g| !above(*g, clear.gap_nm)) {
                    unclear.push(std::format!("nodes {g:.3} nm apart"));
                }
            }
        }
        _ => {}
    }
    OrderMargin {
        order: n,
        status: rule.status,
        norm_ratio,
        norm_margin,
        definite,
        positive,
        max_imaginary_nm: rule.max_imaginary_nm,
        imag_margin,
        range_margin_nm,
        min_gap_nm,
        clear: unclear.is_empty(),
        unclear: unclear.join("; "),
    }
}

/// The margins of every rule of the derivation (`[channel][n - 1]`), judged by [`CLEAR_MARGIN`].
pub fn margins(derivation: &Derivation) -> [Vec<OrderMargin>; 3] {
    [0, 1, 2].map(|c| {
        derivation.rules[c]
            .iter()
            .map(|r| {
                order_margin(
                    &derivation.measures[c],
                    &derivation.recurrences[c],
                    r,
                    &CLEAR_MARGIN,
                )
            })
            .collect()
    })
}

/// A plain-text table of [`margins`].
pub fn margin_table(margins: &[Vec<OrderMargin>; 3]) -> String {
    let mut s = std::format!(
        "{:<3} {:>3} {:<15} {:>10} {:>9} {:>10} {:>9} {:>9} {:>6}  {}\n",
        "ch",
        "n",
        "status",
        "norm marg",
        "Im nm",
        "Im marg",
        "range nm",
        "gap nm",
        "clear",
        "why not"
    );
    let opt = |v: Option<f64>, p: usize| v.map_or("-".into(), |v| std::format!("{v:.p$}"));
    for (c, rows) in margins.iter().enumerate() {
        for m in rows {
            s.push_str(&std::format!(
                "{:<3} {:>3} {:<15} {:>10.2e} {:>9.3} {:>10} {:>9} {:>9} {:>6}  {}\n",
                CHANNELS[c],
                m.order,
                m.status.as_str(),
                m.norm_margin,
                m.max_imaginary_nm,
                m.imag_margin
                    .map_or("-".into(), |v| std::format!("{v:.2e}")),
                opt(m.range_margin_nm, 2),
                opt(m.min_gap_nm, 2),
                if m.clear { "yes" } else { "no" },
                m.unclear
            ));
        }
    }
    s
}

// ---------------------------------------------------------------------------------------------
// Perturbation at the rounding level of the data
// ---------------------------------------------------------------------------------------------

/// The rounding level of the CIE tables as a relative perturbation: 5e-7, half a unit in the
/// 7th significant digit (the 1 nm tables carry 6-7 significant digits).
pub const ROUNDING_LEVEL: f64 = 5e-7;

/// The rounding level of the CIE 1931 values on the 5 nm grid the derivation uses, which are
/// published to 6 decimals (0.001368, 0.000039, 0.323): half a unit in the 6th decimal, 5e-7
/// absolute (x̄ȳz̄ peak near 1-1.8). Near the range ends this is far more than 5e-7 relative
/// (ȳ(380 nm) = 0.000039 is known to about 1 %).
pub const ROUNDING_LEVEL_ABSOLUTE: f64 = 5e-7;

/// How [`perturb_observer`] changes each value v, with u = ±1 from [`SignSequence`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Perturbation {
    /// v (1 + u r).
    Relative(f64),
    /// v + u a, for v ≠ 0 (values printed as 0 stay 0: the functions are non-negative and
    /// CIE 1931's z̄ is zero above 650 nm by construction).
    Absolute(f64),
}

/// A deterministic ±1 sequence from a 64-bit linear congruential generator (Knuth's MMIX
/// constants; the sign is the top bit of the state).
#[derive(Debug, Clone)]
pub struct SignSequence(u64);

impl SignSequence {
    /// The sequence of a seed.
    pub fn new(seed: u64) -> SignSequence {
        let mut s = SignSequence(seed ^ 0x9E37_79B9_7F4A_7C15);
        s.step();
        s
    }

    fn step(&mut self) {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
    }

    /// The next sign, +1 or −1.
    pub fn next_sign(&mut self) -> f64 {
        self.step();
        if self.0 >> 63 == 0 {
            1.0
        } else {
            -1.0
        }
    }
}

/// The observer with every x̄, ȳ, z̄ value perturbed, u = ±1 drawn from [`SignSequence`] of
/// `seed` (rows in order, x̄ ȳ z̄ within a row; a sign is drawn for every value, zero or not).
pub fn perturb_observer(observer: &Observer, seed: u64, perturbation: Perturbation) -> Observer {
    let mut signs = SignSequence::new(seed);
    let mut out = observer.clone();
    for v in out.xyz.iter_mut().flatten() {
        let u = signs.next_sign();
        match perturbation {
            Perturbation::Relative(r) => *v *= 1.0 + u * r,
            Perturbation::Absolute(a) => {
                if *v != 0.0 {
                    *v += u * a;
                }
            }
        }
    }
    out
}

/// The derivation of `settings` on its observer perturbed by [`perturb_observer`] (with
/// `settings.observer_decimals` set, the rounding is applied after the perturbation, which it
/// may undo).
pub fn perturbed_derivation(
    settings: &Settings,
    seed: u64,
    perturbation: Perturbation,
) -> Result<Derivation, Error> {
    let observer = settings.observer.load(&settings.data_dir)?;
    derive_with(settings, perturb_observer(&observer, seed, perturbation))
}

/// Each rule's classification, `[channel][n - 1]`.
pub fn classifications(derivation: &Derivation) -> [Vec<Status>; 3] {
    [0, 1, 2].map(|c| derivation.rules[c].iter().map(|r| r.status).collect())
}

/// The classifications of the derivation with every observer value multiplied by
/// (1 ± [`ROUNDING_LEVEL`]), signs from `seed`.
pub fn perturbed_classifications(
    settings: &Settings,
    seed: u64,
) -> Result<[Vec<Status>; 3], Error> {
    perturbed_derivation(settings, seed, Perturbation::Relative(ROUNDING_LEVEL))
        .map(|d| classifications(&d))
}

/// ∫ f w dλ for f given at the measure's grid points.
fn integrate(measure: &Measure, f: &[f64]) -> f64 {
    measure.mass.iter().zip(f).map(|(m, v)| m * v).sum()
}

/// |⟨P_k, P_k⟩| / Σ |w| P_k²: 1 for a positive measure, near 0 when the norm almost vanishes.
fn norm_ratio(rec: &Recurrence, k: usize) -> f64 {
    (rec.norm[k] / rec.abs_norm[k]).abs()
}
