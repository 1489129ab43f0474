//! The f32 runtime against the f64 derivation on extreme inputs: ±MAX, subnormals, mixtures of
//! huge and tiny samples, and catastrophic cancellation in C1 and C2.

/// The data files the derivation reads (the runtime crate's `data/`).
const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data");

use spectral_quadrature::{f32_budget, tables, WavelengthSet};

const POOL: [f32; 21] = [
    0.0,
    -0.0,
    1.0,
    -1.0,
    0.5,
    f32::MAX,
    -f32::MAX,
    1e38,
    -3e37,
    1e30,
    -1e20,
    1e-30,
    -1e-30,
    f32::MIN_POSITIVE,
    -f32::MIN_POSITIVE,
    1e-40,
    -1e-40,
    1e-45,
    -1e-45,
    123_456.79,
    7.0e-39,
];

/// Checks one input against the documented contract; returns |error| / budget (0 when the
/// output is allowed to be non-finite).
fn check<const N: usize>(set: &WavelengthSet<N>, weights: &[Vec<f64>; 3], s: &[f32; N]) -> f64 {
    let out = set.ac1c2(s);
    let mut worst = 0.0f64;
    for c in 0..3 {
        let exact: f64 = (0..N).map(|i| weights[c][i] * f64::from(s[i])).sum();
        let abs_sum: f64 = (0..N)
            .map(|i| (weights[c][i] * f64::from(s[i])).abs())
            .sum();
        let budget = f32_budget(N, abs_sum);
        // Partial sums stay below abs_sum·(1 + (N + 1)ε): below f32::MAX nothing can overflow.
        let safe =
            abs_sum * (1.0 + (N as f64 + 1.0) * f64::from(f32::EPSILON)) < f64::from(f32::MAX);
        if safe {
            assert!(
                out[c].is_finite(),
                "channel {c} of {s:?}: {} (exact {exact:e})",
                out[c]
            );
            let err = (f64::from(out[c]) - exact).abs();
            assert!(
                err <= budget,
                "channel {c} of {s:?}: error {err:e} > budget {budget:e}"
            );
            if budget > 0.0 {
                worst = worst.max(err / budget);
            }
        }
    }
    worst
}

fn weights_of(d: &spectral_quadrature_generator::Derivation, k: usize) -> [Vec<f64>; 3] {
    d.table2[k].weights.clone()
}

#[test]
fn every_combination_of_extreme_samples_stays_within_budget_or_overflows_honestly() {
    let d = spectral_quadrature_generator::derive(&spectral_quadrature_generator::Settings::new(
        DATA_DIR,
    ))
    .unwrap();
    let w2 = weights_of(&d, 1);
    let mut worst = 0.0f64;
    let mut checked = 0usize;
    // Table 2 row 2 (N = 4): all 21⁴ = 194 481 combinations.
    for a in POOL {
        for b in POOL {
            for c in POOL {
                for e in POOL {
                    worst = worst.max(check(&tables::TABLE2_ROW2, &w2, &[a, b, c, e]));
                    checked += 1;
                }
            }
        }
    }
    // Table 2 row 1 (N = 6): each sample position takes each pool value, the rest a mixture.
    let w1 = weights_of(&d, 0);
    for i in 0..6 {
        for v in POOL {
            for fill in [1.0f32, 1e-40, 1e30, -f32::MAX] {
                let mut s = [fill; 6];
                s[i] = v;
                worst = worst.max(check(&tables::TABLE2_ROW1, &w1, &s));
                checked += 1;
            }
        }
    }
    eprintln!("{checked} extreme inputs: largest error / budget = {worst:.3}");
    assert!(checked > 190_000);
}

#[test]
fn catastrophic_cancellation_in_c1_and_c2_is_within_the_absolute_budget() {
    // C1 of Table 2's sets uses two nodes with weights of opposite sign (32.2 and −46.5): samples
    // in the inverse ratio make C1 cancel to rounding level. The budget is absolute (relative to
    // Σ|w·s|), so it holds, while C1's relative error may be of order one: that is the honest
    // statement for signed channels.
    let d = spectral_quadrature_generator::derive(&spectral_quadrature_generator::Settings::new(
        DATA_DIR,
    ))
    .unwrap();
    let w = weights_of(&d, 1);
    let set = tables::TABLE2_ROW2;
    let (i, j) = {
        let nz: Vec<usize> = (0..4).filter(|&i| set.weights()[1][i] != 0.0).collect();
        (nz[0], nz[1])
    };
    let mut worst = 0.0f64;
    let mut rel_worst = 0.0f64;
    for k in 0..10_000u32 {
        let scale = 10f32.powi((k % 60) as i32 - 30);
        let mut s = [0.3f32 * scale; 4];
        s[i] = scale * (1.0 + (k as f32) * 1e-7);
        s[j] = (-(set.weights()[1][i] * s[i]) / set.weights()[1][j]).abs()
            * (-set.weights()[1][j]).signum()
            * set.weights()[1][i].signum();
        let r = check(&set, &w, &s);
        worst = worst.max(r);
        let exact: f64 = (0..4).map(|n| w[1][n] * f64::from(s[n])).sum();
        let got = f64::from(set.ac1c2(&s)[1]);
        if exact != 0.0 {
            rel_worst = rel_worst.max(((got - exact) / exact).abs());
        }
    }
    eprintln!("cancellation: largest error / budget = {worst:.3}, largest relative error of C1 = {rel_worst:.3e}");
    // The samples really cancel: C1's relative error is far above f32 epsilon somewhere.
    assert!(rel_worst > 1e-4, "{rel_worst}");
}

#[test]
fn overflowing_inputs_give_infinities_or_nan_never_a_panic() {
    let out = tables::TABLE2_ROW2.ac1c2(&[f32::MAX; 4]);
    assert!(out.iter().all(|v| !v.is_finite()), "{out:?}");
    let rgb = tables::folded::TABLE2_ROW2_SRGB.linear_rgb(&[f32::MAX; 4]);
    assert!(rgb.iter().any(|v| !v.is_finite()), "{rgb:?}");
    // And the encoded path turns whatever comes out into a valid pixel.
    let px = tables::folded::TABLE2_ROW2_SRGB
        .encode_u8(spectral_quadrature::GamutMapping::Clip, &[f32::MAX; 4]);
    assert!(px == [0, 0, 0] || px.contains(&255), "{px:?}");
}
