//! The derivation's parts on their own: covariance kinds, quadrature classification on synthetic
//! measures, the two weight formulas, settings, and Table 2's sets. Each tolerance says where it
//! comes from.

/// The data files the derivation reads (the runtime crate's `data/`).
const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../data");

use crate::quadrature::{gauss_rule, interpolatory_weights, stieltjes, Measure, Recurrence};
use crate::{derive, Covariance, Derivation, ObserverId, Settings, Status};
use std::sync::OnceLock;

fn default_derivation() -> &'static Derivation {
    static D: OnceLock<Derivation> = OnceLock::new();
    D.get_or_init(|| derive(&Settings::new(DATA_DIR)).expect("default derivation"))
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(f64::MIN_POSITIVE)
}

fn max_rel_matrix(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> f64 {
    let scale = b.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .map(|(x, y)| (x - y).abs() / scale)
        .fold(0.0, f64::max)
}

// ---------------------------------------------------------------------------------------------
// 1. Covariance kinds
// ---------------------------------------------------------------------------------------------

#[test]
fn exponential_with_tiny_length_is_delta_times_step() {
    let delta = default_derivation();
    // ℓ = 0.01 nm on a 5 nm grid: off-diagonal K = exp(−500) ≈ 7e-218, below the rounding of
    // every sum it enters, so K = I and FᵀKF·step² = (FᵀF·step)·step.
    let exp = derive(&Settings {
        covariance: Covariance::Exponential { length_nm: 0.01 },
        ..Settings::new(DATA_DIR)
    })
    .expect("exponential 0.01 nm");
    let step = Settings::new(DATA_DIR).step_nm;
    // The eigenvalues: exactly step times Delta's, up to f64 rounding of the two products and the
    // 3×3 eigen solve (a few ulps; 1e-12 relative is generous).
    for k in 0..3 {
        let r = exp.opponent.eigenvalues[k] / delta.opponent.eigenvalues[k];
        eprintln!("eigenvalue {k}: ratio {r:.17}");
        assert!(
            rel(r, step) <= 1e-12,
            "eigenvalue {k}: ratio {r}, not {step}"
        );
    }
    // Eigenvectors and M (rows scaled to unit peak): the same matrix up to a scale factor, so the
    // same vectors up to the rounding of the eigen solve (eigenvalue gaps are large: condition
    // ≈ 1, so a few ulps; 1e-12).
    let ev = max_rel_matrix(
        &exp.opponent.eigenvectors_sml,
        &delta.opponent.eigenvectors_sml,
    );
    let m = max_rel_matrix(&exp.opponent.xyz_to_ac1c2, &delta.opponent.xyz_to_ac1c2);
    eprintln!("eigenvectors max diff {ev:.3e}, M max rel diff {m:.3e}");
    assert!(ev <= 1e-12, "eigenvectors differ by {ev:e}");
    assert!(m <= 1e-12, "xyz_to_ac1c2 differs by {m:e}");
}

#[test]
fn exponential_40nm_is_a_valid_transform() {
    let delta = default_derivation();
    let d = derive(&Settings {
        covariance: Covariance::Exponential { length_nm: 40.0 },
        ..Settings::new(DATA_DIR)
    })
    .expect("exponential 40 nm");
    let e = d.opponent.eigenvalues;
    eprintln!("exponential 40 nm eigenvalues {e:?}");
    assert!(e.iter().all(|v| *v > 0.0), "eigenvalues {e:?}");
    assert!(e[0] >= e[1] && e[1] >= e[2], "not descending: {e:?}");
    // A is luminance-like: its sensitivity peaks between 540 and 570 nm (ȳ peaks at 555 nm).
    let (i_max, _) = d
        .sensitivities
        .iter()
        .enumerate()
        .max_by(|a, b| a.1[0].total_cmp(&b.1[0]))
        .unwrap();
    let peak = d.grid_nm[i_max];
    eprintln!("A peak at {peak} nm");
    assert!((540.0..=570.0).contains(&peak), "A peaks at {peak} nm");
    // A luminance channel: every entry of A's SML eigenvector is positive.
    assert!(d.opponent.eigenvectors_sml[0].iter().all(|v| *v > 0.0));
    // It differs from delta: a smoother covariance weighs the cone fundamentals' overlap more.
    // Measured max difference of M is 0.217 (relative to M's largest entry); asserting more
    // than 1e-3 is far above rounding and far below that.
    let diff = max_rel_matrix(&d.opponent.xyz_to_ac1c2, &delta.opponent.xyz_to_ac1c2);
    eprintln!("exponential 40 nm vs delta: M max rel diff {diff:.3e}");
    assert!(diff > 1e-3, "exponential 40 nm equals delta ({diff:e})");
}

/// A deterministic linear congruential generator (Knuth's MMIX constants), uniform in [0, 1).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `count` smooth spectra on `grid`: an offset plus three Gaussians each.
fn smooth_spectra(grid: &[f64], count: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = Lcg(seed);
    (0..count)
        .map(|_| {
            let offset = 0.2 * rng.next();
            let bumps: Vec<[f64; 3]> = (0..3)
                .map(|_| {
                    [
                        rng.next(),                 // amplitude
                        380.0 + 390.0 * rng.next(), // centre, nm
                        15.0 + 85.0 * rng.next(),   // width, nm
                    ]
                })
                .collect();
            grid.iter()
                .map(|&l| {
                    offset
                        + bumps
                            .iter()
                            .map(|[a, c, s]| a * (-0.5 * ((l - c) / s).powi(2)).exp())
                            .sum::<f64>()
                })
                .collect()
        })
        .collect()
}

#[test]
fn empirical_covariance_is_the_sample_covariance_of_sml() {
    let d = default_derivation();
    let step = d.settings.step_nm;
    let spectra = smooth_spectra(&d.grid_nm, 50, 0x5eed);
    let c = crate::opponent::covariance_matrix(
        &d.cones,
        &d.grid_nm,
        step,
        &Covariance::Empirical(spectra.clone()),
    )
    .expect("empirical covariance");
    // The tristimulus values t_k = Σ_j cone(λ_j) s_k(λ_j) dλ and their sample covariance.
    let t: Vec<[f64; 3]> = spectra
        .iter()
        .map(|s| {
            [0, 1, 2].map(|i| {
                d.cones
                    .iter()
                    .zip(s)
                    .map(|(cone, v)| cone[i] * v * step)
                    .sum()
            })
        })
        .collect();
    let m = t.len() as f64;
    let mean = [0, 1, 2].map(|i| t.iter().map(|v| v[i]).sum::<f64>() / m);
    let mut max_rel = 0.0f64;
    for i in 0..3 {
        for j in 0..3 {
            let expected: f64 = t
                .iter()
                .map(|v| (v[i] - mean[i]) * (v[j] - mean[j]))
                .sum::<f64>()
                / (m - 1.0);
            // Relative to the diagonal scale √(C_ii C_jj) (off-diagonal entries may be small).
            let scale = (c[(i, i)] * c[(j, j)]).sqrt();
            let r = (c[(i, j)] - expected).abs() / scale;
            max_rel = max_rel.max(r);
            // 1e-9: the two sides sum the same products in different orders (79 × 50 terms of
            // mixed sign after mean removal); measured 1.1e-15, f64 rounding.
            assert!(
                r <= 1e-9,
                "C[{i}][{j}] = {} vs sample covariance {expected}",
                c[(i, j)]
            );
        }
    }
    eprintln!("empirical covariance: max rel diff {max_rel:.3e}");
    // And the derivation runs with it.
    let e = derive(&Settings {
        covariance: Covariance::Empirical(spectra),
        ..Settings::new(DATA_DIR)
    })
    .expect("derive with empirical covariance");
    assert!(e.opponent.eigenvalues.iter().all(|v| *v > 0.0));
}

#[test]
fn covariance_errors() {
    let d = default_derivation();
    let n = d.grid_nm.len();
    let step = d.settings.step_nm;
    // Every covariance mistake is a setting the derivation cannot honour: its message.
    let cov =
        |k: &Covariance| match crate::opponent::covariance_matrix(&d.cones, &d.grid_nm, step, k) {
            Ok(m) => Ok(m),
            Err(crate::Error::Settings(message)) => Err(message),
            Err(e) => panic!("{}: expected Error::Settings, got {e:?}", k.describe()),
        };

    let one = Covariance::Empirical(vec![vec![1.0; n]]);
    let err = cov(&one).unwrap_err();
    assert!(err.contains("at least two"), "{err}");
    let none = Covariance::Empirical(Vec::new());
    assert!(cov(&none).unwrap_err().contains("at least two"));

    let short = Covariance::Empirical(vec![vec![1.0; n], vec![1.0; n - 1], vec![1.0; n]]);
    let err = cov(&short).unwrap_err();
    assert!(
        err.contains("spectrum 2")
            && err.contains(&format!("{}", n - 1))
            && err.contains(&format!("{n}")),
        "{err}"
    );

    let mut bad_lengths = vec![one, short];
    for length_nm in [0.0, -5.0, f64::NAN, f64::INFINITY] {
        let k = Covariance::Exponential { length_nm };
        let err = cov(&k).unwrap_err();
        assert!(err.contains("positive finite length"), "{length_nm}: {err}");
        bad_lengths.push(k);
    }
    for k in bad_lengths {
        let what = k.describe();
        match derive(&Settings {
            covariance: k,
            ..Settings::new(DATA_DIR)
        }) {
            Err(crate::Error::Settings(msg)) => eprintln!("{what}: {msg}"),
            other => panic!("{what}: expected Error::Settings, got {other:?}"),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 2. Quadrature classification on synthetic measures
// ---------------------------------------------------------------------------------------------

/// 2001 points, wavelengths 0..=2000 nm at 1 nm, range [0, 2000]: x = (λ − 1000)/1000 ∈ [−1, 1].
const RANGE: [f64; 2] = [0.0, 2000.0];

fn synthetic(w: impl Fn(f64) -> f64) -> Measure {
    let wavelengths: Vec<f64> = (0..=2000).map(|k| k as f64).collect();
    let weights: Vec<f64> = wavelengths
        .iter()
        .map(|&l| w((l - 1000.0) / 1000.0))
        .collect();
    Measure::new(&wavelengths, &weights, 1.0, RANGE)
}

#[test]
fn positive_weight_rules_are_defined() {
    let m = synthetic(|_| 1.0);
    let rec = stieltjes(&m, 10);
    assert_eq!(rec.vanished_at, None);
    let total: f64 = m.mass.iter().sum();
    assert_eq!(total, 2001.0);
    for n in 1..=10 {
        let r = gauss_rule(&m, &rec, n, RANGE);
        assert_eq!(r.status, Status::Defined, "order {n}: {}", r.reason);
        assert_eq!(r.nodes_nm.len(), n);
        assert!(r.nodes_nm.iter().all(|&l| l > 0.0 && l < 2000.0), "{r:?}");
        assert!(r.nodes_nm.windows(2).all(|p| p[0] < p[1]), "{r:?}");
        assert!(r.weights.iter().all(|&w| w > 0.0), "{r:?}");
        let sum: f64 = r.weights.iter().sum();
        // Σ w_i = β_0 Σ v_0i² = β_0 for an orthonormal eigenvector matrix: rounding only
        // (1e-12 relative).
        assert!(rel(sum, total) <= 1e-12, "order {n}: Σ w = {sum}");
        assert_eq!(r.max_imaginary_nm, 0.0);
    }
    // Order 2: by symmetry α = 0 and P_2 = x² − β_1 with β_1 = the discrete mean of x², which is
    // Σ_{j=−N}^{N} (j/N)² / (2N+1) = (N+1)/(3N) for N = 1000, i.e. 1/3 (1 + 1/1000). So the
    // nodes are ±√(1001/3000) = ±0.577639 instead of ±1/√3 = ±0.577350: 2.9e-4 apart, the
    // rectangle rule's discretization. Assert the exact discrete value to rounding (1e-12) and
    // the continuous one to 1e-3 (3.5 × the measured 2.9e-4).
    let r = gauss_rule(&m, &rec, 2, RANGE);
    let x: Vec<f64> = r.nodes_nm.iter().map(|&l| m.to_x(l)).collect();
    let discrete = (1001.0f64 / 3000.0).sqrt();
    let continuous = 1.0 / 3f64.sqrt();
    eprintln!(
        "2-point nodes {x:?}: vs 1/√3 {:.3e}, vs discrete {:.3e}",
        (x[1] - continuous).abs(),
        (x[1] - discrete).abs()
    );
    for (xi, sign) in x.iter().zip([-1.0, 1.0]) {
        assert!((xi - sign * discrete).abs() <= 1e-12, "node {xi}");
        assert!((xi - sign * continuous).abs() <= 1e-3, "node {xi}");
    }
}

#[test]
fn odd_weight_has_vanishing_norm() {
    // w(x) = x on a symmetric grid: ⟨P_0, P_0⟩ = Σ w = 0 (up to rounding of the sum, far below
    // VANISHING_NORM · Σ |w|).
    let m = synthetic(|x| x);
    let rec = stieltjes(&m, 4);
    eprintln!(
        "odd weight: norm0 {:e}, abs_norm0 {:e}",
        rec.norm[0], rec.abs_norm[0]
    );
    assert_eq!(rec.vanished_at, Some(0));
    assert!(rec.alpha.is_empty());
    for n in [1, 2] {
        let r = gauss_rule(&m, &rec, n, RANGE);
        assert_eq!(r.status, Status::VanishingNorm, "order {n}");
        assert!(r.nodes_nm.is_empty() && r.weights.is_empty());
        assert!(r.reason.contains("vanishes"), "{}", r.reason);
    }
}

#[test]
fn signed_even_weight_has_complex_order_2() {
    // w(x) = x² − 1/2 is even, so every α_k = 0 and P_2 = x² − β_1 with β_1 = μ_2 / μ_0.
    // Continuous moments on [−1, 1]: μ_0 = 2/3 − 1 = −1/3, μ_2 = 2/5 − 1/3 = 1/15, so
    // β_1 = −1/5 < 0 and the 2×2 monic Jacobi matrix [[0, β_1], [1, 0]] has eigenvalues
    // λ² = β_1, i.e. ±i/√5 = ±0.447i: complex, 447 nm in a half-width of 1000 nm. Any c in
    // (1/3, 3/5) gives μ_0 < 0 < μ_2.
    let m = synthetic(|x| x * x - 0.5);
    let rec = stieltjes(&m, 4);
    assert_eq!(rec.vanished_at, None);
    // The discrete moments, for the exact expectation.
    let mu0: f64 = m.mass.iter().sum();
    let mu2: f64 = m.mass.iter().zip(&m.x).map(|(w, x)| w * x * x).sum();
    assert!(mu0 < 0.0 && mu2 > 0.0, "μ0 {mu0}, μ2 {mu2}");
    let expected_nm = (-mu2 / mu0).sqrt() * m.half_width;
    let r1 = gauss_rule(&m, &rec, 1, RANGE);
    // Order 1: the node α_0 = 0 (the centre) with weight μ_0 < 0; real and inside.
    assert_eq!(r1.status, Status::Defined, "{}", r1.reason);
    assert!((r1.nodes_nm[0] - 1000.0).abs() <= 1e-9, "{r1:?}");
    let r = gauss_rule(&m, &rec, 2, RANGE);
    eprintln!(
        "complex order 2: max_imaginary_nm {} (expected {expected_nm}, continuous {})",
        r.max_imaginary_nm,
        1000.0 / 5f64.sqrt()
    );
    assert_eq!(r.status, Status::Complex, "{r:?}");
    assert!(r.max_imaginary_nm > 0.0);
    assert!(r.nodes_nm.is_empty());
    // √(−β_1) from the 2×2 eigen solve vs the same number from the moments: rounding (1e-9).
    assert!(
        rel(r.max_imaginary_nm, expected_nm) <= 1e-9,
        "{} vs {expected_nm}",
        r.max_imaginary_nm
    );
    // And the continuous value 1000/√5 = 447.21 nm, within the discretization: the 2001-point
    // rectangle rule counts the endpoints fully, an O(1/N) error in each moment that μ_0's
    // cancellation (2/3 − 1) amplifies. In closed form the discrete means are
    // E x² = (N+1)/(3N), E x⁴ = (N+1)(3N²+3N−1)/(15N³) for N = 1000, giving 449.23 nm:
    // measured 2.01 nm from the continuous value; bound 3 nm.
    let n = 1000.0f64;
    let ex2 = (n + 1.0) / (3.0 * n);
    let ex4 = (n + 1.0) * (3.0 * n * n + 3.0 * n - 1.0) / (15.0 * n.powi(3));
    let closed_form = 1000.0 * (-(ex4 - 0.5 * ex2) / (ex2 - 0.5)).sqrt();
    // The closed form vs the summed moments: rounding of 2001-term sums (1e-9).
    assert!(
        rel(r.max_imaginary_nm, closed_form) <= 1e-9,
        "{closed_form}"
    );
    assert!((r.max_imaginary_nm - 1000.0 / 5f64.sqrt()).abs() <= 3.0);
}

#[test]
fn small_mass_puts_the_order_1_node_outside() {
    // w = x + 0.01: Σ w = 0.01 · 2001 = 20.01 (small but far above VANISHING_NORM · Σ |w| ≈
    // 1e-10 · 1000), Σ x w = Σ x² ≈ 667.7, so α_0 = Σ x w / Σ w ≈ 33.4: 33 half-widths outside.
    let m = synthetic(|x| x + 0.01);
    let rec = stieltjes(&m, 2);
    let mu0: f64 = m.mass.iter().sum();
    let mu1: f64 = m.mass.iter().zip(&m.x).map(|(w, x)| w * x).sum();
    let alpha0 = mu1 / mu0;
    let expected_nm = m.to_nm(alpha0);
    let r = gauss_rule(&m, &rec, 1, RANGE);
    eprintln!(
        "outside: α0 = {alpha0}, node {:?}, reason {}",
        r.nodes_nm, r.reason
    );
    assert_eq!(r.status, Status::Outside, "{r:?}");
    assert_eq!(r.nodes_nm.len(), 1);
    // Both sides compute Σ x w / Σ w; the test sums in the same order, so rounding only.
    assert!(
        rel(r.nodes_nm[0], expected_nm) <= 1e-12,
        "{r:?} vs {expected_nm}"
    );
    assert!(r.nodes_nm[0] > 30_000.0);
    assert!(rel(r.weights[0], mu0) <= 1e-12, "{r:?}");
    assert!(r.reason.contains("outside"), "{}", r.reason);
}

// ---------------------------------------------------------------------------------------------
// 3. The weight formulas agree
// ---------------------------------------------------------------------------------------------

/// 1 / Σ_{k<n} P_k(x)² / ⟨P_k, P_k⟩.
fn christoffel(rec: &Recurrence, n: usize, x: f64) -> f64 {
    let p = rec.evaluate(n - 1, x);
    1.0 / p
        .iter()
        .zip(&rec.norm)
        .map(|(pk, h)| pk * pk / h)
        .sum::<f64>()
}

#[test]
fn golub_welsch_weights_are_christoffel_numbers() {
    let d = default_derivation();
    let (m, rec) = (&d.measures[0], &d.recurrences[0]);
    let mut worst = 0.0f64;
    let mut checked = 0;
    for rule in d.rules[0].iter().filter(|r| r.is_defined()) {
        let n = rule.order;
        // Channel A is a positive measure here, so the Golub-Welsch branch was taken.
        assert!(rec.beta[1..n].iter().all(|&b| b > 0.0), "A order {n}");
        for (node, w) in rule.nodes_nm.iter().zip(&rule.weights) {
            let c = christoffel(rec, n, m.to_x(*node));
            let r = rel(c, *w);
            worst = worst.max(r);
            // 1e-10: both are f64 evaluations of the same number (β_0 v_0² from the eigen solve
            // vs a sum of positive terms); measured worst 1.9e-13 over orders 1-16.
            assert!(
                r <= 1e-10,
                "A order {n} at {node} nm: GW {w} vs Christoffel {c}"
            );
        }
        checked += 1;
    }
    eprintln!("A: {checked} defined rules, worst GW/Christoffel rel diff {worst:.3e}");
    assert!(checked >= 8, "only {checked} defined A rules");
}

#[test]
fn signed_rules_integrate_polynomials_exactly() {
    let d = default_derivation();
    for c in [1, 2] {
        let m = &d.measures[c];
        let mut worst = 0.0f64;
        let mut checked = 0;
        for rule in d.rules[c].iter().filter(|r| r.is_defined()) {
            let n = rule.order;
            let xs: Vec<f64> = rule.nodes_nm.iter().map(|&l| m.to_x(l)).collect();
            for k in 0..2 * n as i32 {
                let quad: f64 = xs
                    .iter()
                    .zip(&rule.weights)
                    .map(|(x, w)| w * x.powi(k))
                    .sum();
                let exact: f64 = m.x.iter().zip(&m.mass).map(|(x, w)| w * x.powi(k)).sum();
                let scale: f64 =
                    m.x.iter()
                        .zip(&m.mass)
                        .map(|(x, w)| (w * x.powi(k)).abs())
                        .sum();
                let r = (quad - exact).abs() / scale;
                worst = worst.max(r);
                // 1e-8 of Σ |mass x^k|: signed weights cancel, and the recurrence's rounding
                // grows with the order; measured worst 3.3e-12 (C1), 3.1e-14 (C2).
                assert!(
                    r <= 1e-8,
                    "channel {c} order {n} moment {k}: rule {quad} vs measure {exact} (scale {scale})"
                );
            }
            checked += 1;
        }
        eprintln!("channel {c}: {checked} defined rules, worst moment error {worst:.3e}");
        assert!(checked >= 2, "channel {c}: only {checked} defined rules");
    }
}

#[test]
fn interpolatory_weights_on_gauss_nodes_are_gauss_weights() {
    let d = default_derivation();
    let m = &d.measures[0];
    let mut worst = 0.0f64;
    for rule in d.rules[0].iter().filter(|r| r.is_defined()) {
        let w = interpolatory_weights(m, &rule.nodes_nm);
        for (a, b) in w.iter().zip(&rule.weights) {
            let r = rel(*a, *b);
            worst = worst.max(r);
            // 1e-9: the Lagrange products over the grid sum terms of mixed sign up to order 16;
            // measured worst 1.8e-13.
            assert!(
                r <= 1e-9,
                "A order {}: interpolatory {a} vs Gauss {b}",
                rule.order
            );
        }
    }
    eprintln!("A: worst interpolatory/Gauss rel diff {worst:.3e}");
}

// ---------------------------------------------------------------------------------------------
// 4. Settings
// ---------------------------------------------------------------------------------------------

#[test]
fn observers_ranges_steps_and_orders() {
    let ten = derive(&Settings {
        observer: ObserverId::Cie1964_10deg,
        ..Settings::new(DATA_DIR)
    })
    .expect("1964 10° at the default range");
    assert_eq!(ten.observer.name, "cie1964_10deg");
    for c in 0..3 {
        assert_eq!(ten.rules[c].len(), 16, "default max_order");
    }
    for observer in ObserverId::ALL {
        for step_nm in [5.0, 1.0] {
            let d = derive(&Settings {
                observer,
                range_nm: [390.0, 770.0],
                step_nm,
                ..Settings::new(DATA_DIR)
            })
            .unwrap_or_else(|e| panic!("{} step {step_nm}: {e}", observer.name()));
            assert_eq!(d.grid_nm.len(), (380.0 / step_nm) as usize + 1);
            assert_eq!(d.grid_nm[0], 390.0);
            assert_eq!(*d.grid_nm.last().unwrap(), 770.0);
            for c in 0..3 {
                assert_eq!(d.rules[c].len(), Settings::new(DATA_DIR).max_order);
                for (i, r) in d.rules[c].iter().enumerate() {
                    assert_eq!(r.order, i + 1);
                }
            }
        }
    }
    let d30 = derive(&Settings {
        max_order: 30,
        ..Settings::new(DATA_DIR)
    })
    .expect("max_order 30");
    for c in 0..3 {
        assert_eq!(d30.rules[c].len(), 30);
        assert_eq!(d30.rules[c][29].order, 30);
    }
    // The first 16 rules do not depend on max_order.
    assert_eq!(d30.rules[0][..16], default_derivation().rules[0][..]);
}

#[test]
fn cie2015_does_not_cover_380() {
    match derive(&Settings {
        observer: ObserverId::Cie2015_2deg,
        ..Settings::new(DATA_DIR)
    }) {
        Err(crate::Error::Settings(msg)) => {
            eprintln!("{msg}");
            assert!(msg.contains("380") && msg.contains("not covered"), "{msg}");
        }
        other => panic!("expected Error::Settings, got {other:?}"),
    }
}

#[test]
fn max_order_bounds() {
    let points = default_derivation().grid_nm.len();
    assert_eq!(points, 79);
    for max_order in [0, points, points + 1, 1000] {
        match derive(&Settings {
            max_order,
            ..Settings::new(DATA_DIR)
        }) {
            Err(crate::Error::Settings(msg)) => eprintln!("max_order {max_order}: {msg}"),
            other => panic!("max_order {max_order}: expected Error::Settings, got {other:?}"),
        }
    }
    let one = derive(&Settings {
        max_order: 1,
        ..Settings::new(DATA_DIR)
    })
    .expect("max_order 1");
    assert_eq!(one.rules[0].len(), 1);
}

fn one_nm_derivation() -> &'static Derivation {
    static D: OnceLock<Derivation> = OnceLock::new();
    D.get_or_init(|| {
        derive(&Settings {
            step_nm: 1.0,
            ..Settings::new(DATA_DIR)
        })
        .expect("1 nm derivation")
    })
}

#[test]
fn one_nm_grid_agrees_with_5_nm() {
    let five = default_derivation();
    let one = one_nm_derivation();
    let (a5, a1) = (&five.rules[0][0], &one.rules[0][0]);
    assert!(a5.is_defined() && a1.is_defined());
    let dn = (a5.nodes_nm[0] - a1.nodes_nm[0]).abs();
    eprintln!(
        "A order 1: 5 nm {} vs 1 nm {} (diff {dn:.4} nm)",
        a5.nodes_nm[0], a1.nodes_nm[0]
    );
    // A's weight is positive and smooth, so the 5 nm rectangle rule is close to the 1 nm one:
    // measured 9.3e-5 nm (559.21416 vs 559.21425). Bound 0.01 nm, 100× the measurement and
    // 50× below the 0.5 nm printed-table budget.
    assert!(dn <= 0.01, "A order 1 node moved {dn} nm");
    let mut worst = 0.0f64;
    for (r5, r1) in five
        .opponent
        .eigenvectors_sml
        .iter()
        .zip(&one.opponent.eigenvectors_sml)
    {
        for (x, y) in r5.iter().zip(r1) {
            worst = worst.max((x - y).abs());
        }
    }
    eprintln!("eigenvectors 5 nm vs 1 nm: max diff {worst:.3e}");
    // The grids are expected to agree to about five digits; measured 4.2e-7 on the unit
    // eigenvectors. Bound 1e-5 (five digits, 24× the measurement).
    assert!(worst <= 1e-5, "eigenvectors differ by {worst}");
}

#[test]
fn classification_across_observers() {
    for observer in ObserverId::ALL {
        let d = derive(&Settings {
            observer,
            range_nm: [390.0, 770.0],
            ..Settings::new(DATA_DIR)
        })
        .expect("derive");
        for c in [1, 2] {
            let line: Vec<&str> = d.rules[c][..8].iter().map(|r| r.status.as_str()).collect();
            eprintln!(
                "{:14} {}: {}",
                observer.name(),
                ["A", "C1", "C2"][c],
                line.join(" ")
            );
        }
        for (c, rules) in d.rules.iter().enumerate() {
            for r in rules {
                assert!(matches!(
                    r.status,
                    Status::Defined | Status::Outside | Status::Complex | Status::VanishingNorm
                ));
                match r.status {
                    Status::Defined => {
                        assert_eq!(r.nodes_nm.len(), r.order);
                        assert_eq!(r.weights.len(), r.order);
                        assert!(
                            r.nodes_nm.iter().all(|l| (390.0..=770.0).contains(l)),
                            "{} channel {c} order {}: {:?}",
                            observer.name(),
                            r.order,
                            r.nodes_nm
                        );
                        assert!(r.weights.iter().all(|w| w.is_finite()), "{r:?}");
                        assert!(r.reason.is_empty());
                    }
                    Status::Outside => {
                        assert_eq!(r.nodes_nm.len(), r.order);
                        assert!(!r.reason.is_empty());
                    }
                    Status::Complex => {
                        assert!(r.nodes_nm.is_empty());
                        assert!(r.max_imaginary_nm > 0.0);
                    }
                    Status::VanishingNorm => assert!(r.nodes_nm.is_empty()),
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 5. Table 2's sets
// ---------------------------------------------------------------------------------------------

#[test]
fn table2_row2_wavelengths_come_from_the_rules() {
    let d = default_derivation();
    let row2 = &d.table2[1];
    assert_eq!(row2.len(), 4, "{:?}", row2.wavelengths_nm);
    let c2_1 = &d.rules[2][0].nodes_nm;
    let c1_2 = &d.rules[1][1].nodes_nm;
    let a_3 = &d.rules[0][2].nodes_nm;
    let candidates: Vec<f64> = c2_1.iter().chain(c1_2).chain([&a_3[1]]).copied().collect();
    for l in &row2.wavelengths_nm {
        // The sets copy the nodes; merge treats nodes within 1e-9 nm as one.
        assert!(
            candidates.iter().any(|c| (c - l).abs() <= 1e-9),
            "{l} nm is not a node of C2 1, C1 2 or A 3's middle node"
        );
    }
    eprintln!("row 2: {:?}", row2.wavelengths_nm);
    // And all four are used: C2's node, C1's two, A's middle one, as wavelengths ascending.
    let mut expected = candidates;
    expected.sort_by(f64::total_cmp);
    assert_eq!(row2.wavelengths_nm, expected);
}

#[test]
fn table2_sets_integrate_constants() {
    let d = default_derivation();
    let mass = [0, 1, 2].map(|c| d.measures[c].mass.iter().sum::<f64>());
    for (r, set) in d.table2.iter().enumerate() {
        let got = set.apply(|_| 1.0);
        for c in 0..3 {
            // Every rule (Gauss or interpolatory) integrates constants exactly; the weights sum
            // to the mass up to rounding (1e-9 relative, generous).
            assert!(
                rel(got[c], mass[c]) <= 1e-9,
                "row {} channel {c}: {} vs mass {}",
                r + 1,
                got[c],
                mass[c]
            );
        }
    }
}

#[test]
fn a_nan_node_is_never_defined() {
    // A degenerate eigen solve could return NaN; such a rule must not be baked as defined.
    let r = crate::quadrature::real_rule(
        2,
        vec![f64::NAN, 500.0],
        vec![1.0, 1.0],
        0.0,
        [380.0, 770.0],
    );
    assert_eq!(r.status, crate::Status::Outside);
    assert!(r.reason.contains("NaN"), "{}", r.reason);
    let ok =
        crate::quadrature::real_rule(2, vec![380.0, 770.0], vec![1.0, 1.0], 0.0, [380.0, 770.0]);
    assert_eq!(ok.status, crate::Status::Defined);
}
