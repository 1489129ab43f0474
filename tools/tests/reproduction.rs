//! The derivation reproduces the numbers the paper prints (Eq. 9, Eq. 10, Table 1a, Table 2).
//! Each tolerance says where it comes from.

/// The data files the derivation reads (the runtime crate's `data/`).
const DATA_DIR: &str = spectral_quadrature_tools::DATA_DIR;

use spectral_quadrature_generator::{derive, Derivation, Settings, Status};
use spectral_quadrature_tools::paper;
use std::sync::OnceLock;

/// The derivation with the settings that reproduce the paper (CIE data rounded to 5 decimals;
/// see `paper::settings`).
fn paper_derivation() -> &'static Derivation {
    static D: OnceLock<Derivation> = OnceLock::new();
    D.get_or_init(|| derive(&paper::settings(DATA_DIR)).expect("paper derivation"))
}

/// The derivation the crate bakes (CIE data as published).
fn default_derivation() -> &'static Derivation {
    static D: OnceLock<Derivation> = OnceLock::new();
    D.get_or_init(|| derive(&Settings::new(DATA_DIR)).expect("default derivation"))
}

#[test]
fn eq9_coefficients_within_0_002() {
    for d in [paper_derivation(), default_derivation()] {
        for (r, (row, printed)) in d
            .opponent
            .xyz_to_ac1c2
            .iter()
            .zip(paper::EQ9_XYZ_TO_AC1C2)
            .enumerate()
        {
            for (c, (v, p)) in row.iter().zip(printed).enumerate() {
                // The budget: the paper prints 4 decimals, and its peak scaling and data
                // differ slightly from the CIE tables used here.
                assert!(
                    (v - p).abs() <= 0.002,
                    "Eq. 9 [{r}][{c}]: {v} vs printed {p}"
                );
            }
        }
    }
}

#[test]
fn eq10_eigenvalue_ratios_within_1_5_percent() {
    for d in [paper_derivation(), default_derivation()] {
        let e = d.opponent.eigenvalues;
        let p = paper::EQ10_EIGENVALUE_RATIO;
        // 1.5 %: the paper prints three significant digits and docs/reproducing-the-paper.md finds
        // the last one reproducible to about 1 %.
        for (ours, printed, what) in [
            (e[0] / e[1], p[0] / p[1], "A/C1"),
            (e[1] / e[2], p[1] / p[2], "C1/C2"),
        ] {
            let rel = (ours / printed - 1.0).abs();
            assert!(
                rel <= 0.015,
                "{what}: {ours} vs printed {printed} ({rel:.4})"
            );
        }
    }
}

#[test]
fn eq9_is_the_kl_transform() {
    // The rows are eigenvectors of the covariance (in SML): T C Tᵀ is diagonal. Off-diagonal
    // terms relative to the diagonal at f64 rounding of a 3×3 eigen solve (1e-12, generous).
    let d = paper_derivation();
    let t = d.opponent.sml_to_ac1c2;
    let c = d.covariance;
    for i in 0..3 {
        for j in 0..3 {
            let v: f64 = (0..3)
                .flat_map(|k| (0..3).map(move |l| (k, l)))
                .map(|(k, l)| t[i][k] * c[k][l] * t[j][l])
                .sum();
            if i != j {
                let scale: f64 = (0..3).map(|k| t[i][k].abs()).sum::<f64>()
                    * (0..3).map(|k| t[j][k].abs()).sum::<f64>()
                    * d.opponent.eigenvalues[0];
                assert!(v.abs() <= 1e-12 * scale, "T C Tᵀ [{i}][{j}] = {v}");
            }
        }
    }
}

#[test]
fn sensitivities_peak_and_signs_as_the_paper_scales_them() {
    let d = paper_derivation();
    // On the 5 nm grid the peaks are at most 1 (they are scaled on the 1 nm table); the trough of
    // c1 falls between grid points, so allow what docs/reproducing-the-paper.md measures
    // (about 0.3 %).
    let col = |c: usize| d.sensitivities.iter().map(move |s| s[c]);
    let max_a = col(0).fold(f64::MIN, f64::max);
    let min_c1 = col(1).fold(f64::MAX, f64::min);
    let max_c2 = col(2).fold(f64::MIN, f64::max);
    assert!(max_a <= 1.0 + 1e-12 && max_a > 0.999, "max a = {max_a}");
    assert!(
        (-1.0 - 1e-12..-0.995).contains(&min_c1),
        "min c1 = {min_c1}"
    );
    assert!(max_c2 <= 1.0 + 1e-12 && max_c2 > 0.995, "max c2 = {max_c2}");
    let at = |nm: f64, c: usize| {
        let i = d.grid_nm.iter().position(|&l| l == nm).unwrap();
        d.sensitivities[i][c]
    };
    assert!(at(530.0, 1) > 0.0, "C1 positive in the green");
    assert!(at(620.0, 1) < 0.0, "C1 negative in the red");
    assert!(at(450.0, 2) > 0.0, "C2 positive in the blue");
}

/// Table 1a's nodes are printed to 0.1 nm: ±0.5 nm is the budget (rounding plus the
/// difference between the paper's CIE data and today's).
const NODE_NM: f64 = 0.5;
/// Weights: 0.5 % relative after normalizing by the channel's total mass, or 0.0005 absolute for
/// weights printed below 0.01 (the budget). The paper prints H_i to 5 decimals, so a
/// weight below 0.01 has at most 3 significant digits; that allowance is for the printed
/// precision and is applied on the printed scale (ours × printed mass / our mass).
const WEIGHT_REL: f64 = 0.005;
const WEIGHT_ABS_SMALL: f64 = 0.0005;

/// Weights that differ from the printed ones by more than 0.5 % under every variant of the
/// derivation tried (data as published, rounded to 5 decimals, printed Eq. 9 rows as weight
/// functions), although each is printed to 4 significant digits (rounding ≤ 0.04 %) and its row
/// sums correctly: the paper's own computation differs there. (channel, order, index, bound):
/// C1 order 8 weight 6, printed −0.01134: measured 0.73 % (0.86 % with the data as published);
/// C2 order 3 weight 0 at 386.9 nm, the range's edge, printed 0.01859: measured 0.67 %. Bound
/// 1 %, for these two entries only.
const MEASURED_EXCEPTIONS: [(usize, usize, usize, f64); 2] = [(1, 8, 6, 0.01), (2, 3, 0, 0.01)];

/// `ours` and `printed` on the printed scale.
fn weight_ok(ours: f64, printed: f64) -> bool {
    if printed.abs() < 0.01 {
        (ours - printed).abs() <= WEIGHT_ABS_SMALL
    } else {
        (ours / printed - 1.0).abs() <= WEIGHT_REL
    }
}

/// A printed entry with the suspect readings of `paper::TABLE_1A_SUSPECTS` applied.
fn printed_entry(c: usize, order: usize, i: usize, entry: paper::Entry, printed: f64) -> f64 {
    match paper::TABLE_1A_SUSPECTS
        .iter()
        .find(|s| s.channel == c && s.order == order && s.index == i && s.entry == entry)
    {
        Some(s) => {
            assert_eq!(s.printed, printed, "suspect list matches the table");
            s.reading
        }
        None => printed,
    }
}

#[test]
fn table_1a_nodes_weights_and_undefined_pattern() {
    let d = paper_derivation();
    // For C2 order 7 (see below): the same rule on a 1 nm grid.
    let fine = derive(&Settings {
        step_nm: 1.0,
        ..paper::settings(DATA_DIR)
    })
    .expect("1 nm derivation");
    let mut checked = 0;
    for (c, channel) in ["A", "C1", "C2"].iter().enumerate() {
        let mass_ours: f64 = d.measures[c].mass.iter().sum();
        let mass_printed = paper::TABLE_1A_TOTAL_MASS[c];
        for order in 1..=8 {
            let rule = &d.rules[c][order - 1];
            let what = format!("{channel} order {order}");
            let Some(printed) = &paper::TABLE_1A[c][order - 1] else {
                assert!(!rule.is_defined(), "{what} should be undefined: {rule:?}");
                continue;
            };
            assert!(
                rule.is_defined(),
                "{what} should be defined: {}",
                rule.reason
            );
            assert_eq!(rule.nodes_nm.len(), order);
            for (i, (ours, &p)) in rule.nodes_nm.iter().zip(printed.wavelengths_nm).enumerate() {
                let expected = printed_entry(c, order, i, paper::Entry::Node, p);
                assert!(
                    (ours - expected).abs() <= NODE_NM,
                    "{what} node {i}: {ours:.2} vs printed {expected}"
                );
                checked += 1;
            }
            for (i, (ours, &p)) in rule.weights.iter().zip(printed.weights).enumerate() {
                // On the printed scale.
                let expected = printed_entry(c, order, i, paper::Entry::Weight, p);
                let ours = ours * mass_printed / mass_ours;
                if c == 2 && order == 7 {
                    // C2 order 7's printed weights do not sum to H_1 (one entry misprinted, which
                    // one is ambiguous: paper::TABLE_1A_C2_7_SUM). Its weights are also the
                    // most data-sensitive in the table, so the budget here is measured: the
                    // change of the same weight between the 5 nm and the 1 nm grid.
                    let f = &fine.rules[2][6];
                    assert!(f.is_defined());
                    let mass_fine: f64 = fine.measures[2].mass.iter().sum();
                    let sensitivity = (f.weights[i] * mass_printed / mass_fine - ours).abs();
                    assert!(
                        (ours - expected).abs() <= sensitivity.max(WEIGHT_ABS_SMALL),
                        "{what} weight {i}: {ours:.5} vs printed {expected:.5} (5 nm/1 nm sensitivity {sensitivity:.5})"
                    );
                    let sum: f64 = printed.weights.iter().sum();
                    assert!((sum - paper::TABLE_1A_C2_7_SUM).abs() < 1e-9);
                } else if let Some(x) = MEASURED_EXCEPTIONS
                    .iter()
                    .find(|x| (x.0, x.1, x.2) == (c, order, i))
                {
                    assert!(
                        (ours / expected - 1.0).abs() <= x.3,
                        "{what} weight {i}: {ours:.5} vs {expected:.5} (measured exception)"
                    );
                } else {
                    assert!(
                        weight_ok(ours, expected),
                        "{what} weight {i}: {ours:.5} vs printed {expected:.5} (normalized by total mass)"
                    );
                }
                checked += 1;
            }
        }
    }
    // 1+2+…+8 for A, 2+4+6+8 for C1, 1+2+3+7 for C2; nodes and weights.
    assert_eq!(checked, 2 * (36 + 20 + 13));
}

#[test]
fn suspect_weight_readings_restore_the_printed_sums() {
    // Every weight reading restores its row's sum to the channel's printed total mass within the
    // rounding of 5-decimal entries (n × 0.000005 ≤ 0.00004).
    for s in paper::TABLE_1A_SUSPECTS
        .iter()
        .filter(|s| s.entry == paper::Entry::Weight)
    {
        let row = paper::TABLE_1A[s.channel][s.order - 1].unwrap().weights;
        let printed_sum: f64 = row.iter().sum();
        let read_sum = printed_sum - s.printed + s.reading;
        let mass = paper::TABLE_1A_TOTAL_MASS[s.channel];
        assert!(
            (printed_sum - mass).abs() > 0.0005,
            "{s:?} row already sums right"
        );
        assert!(
            (read_sum - mass).abs() <= 0.00004,
            "{s:?}: {read_sum} vs {mass}"
        );
    }
}

#[test]
fn table_1a_undefined_orders_have_the_reasons_notes_md_finds() {
    let d = paper_derivation();
    for order in [1, 3, 5, 7] {
        assert_eq!(
            d.rules[1][order - 1].status,
            Status::Outside,
            "C1 order {order}"
        );
    }
    for order in [4, 5, 6, 8] {
        assert_eq!(
            d.rules[2][order - 1].status,
            Status::Complex,
            "C2 order {order}"
        );
    }
    assert!(d.rules[0].iter().take(8).all(|r| r.is_defined()));
}

#[test]
fn table_1a_weights_scale_is_a_constant_multiple() {
    // docs/reproducing-the-paper.md: H_i ≈ 0.0099 × (weights for dλ in nm), the same factor for
    // every channel. H_1 of A and C2 are printed to 5 decimals, so their factors agree to ~1e-5
    // relative; the data differences allow 0.5 %.
    let d = paper_derivation();
    let fa = paper::TABLE_1A[0][0].unwrap().weights[0] / d.rules[0][0].weights[0];
    let fc2 = paper::TABLE_1A[2][0].unwrap().weights[0] / d.rules[2][0].weights[0];
    assert!((fa / fc2 - 1.0).abs() < 0.005, "{fa} vs {fc2}");
    assert!((fa - 0.0099).abs() < 0.0001, "{fa}");
}

#[test]
fn gauss_rules_sum_to_the_total_mass_and_integrate_polynomials() {
    // A Gauss rule of order n integrates polynomials of degree ≤ 2n − 1 exactly against the
    // discrete measure. Checked for every defined rule up to MAX_ORDER against the measure's own
    // sums; tolerance: f64 rounding amplified by the cancellation of the signed weights
    // (1e-9 relative to Σ|w|·|x^k|).
    let d = paper_derivation();
    for c in 0..3 {
        let m = &d.measures[c];
        for rule in d.rules[c].iter().filter(|r| r.is_defined()) {
            let n = rule.order;
            for k in 0..2 * n {
                let exact: f64 =
                    m.x.iter()
                        .zip(&m.mass)
                        .map(|(x, w)| w * x.powi(k as i32))
                        .sum();
                let scale: f64 =
                    m.x.iter()
                        .zip(&m.mass)
                        .map(|(x, w)| (w * x.powi(k as i32)).abs())
                        .sum();
                let quad: f64 = rule
                    .nodes_nm
                    .iter()
                    .zip(&rule.weights)
                    .map(|(l, w)| w * m.to_x(*l).powi(k as i32))
                    .sum();
                assert!(
                    (quad - exact).abs() <= 1e-9 * scale,
                    "channel {c} order {n} degree {k}: {quad} vs {exact}"
                );
            }
        }
    }
}

#[test]
fn table2_sets() {
    let d = paper_derivation();
    let [row1, row2] = &d.table2;
    assert_eq!(row1.len(), 6, "{:?}", row1.wavelengths_nm);
    assert_eq!(row2.len(), 4, "{:?}", row2.wavelengths_nm);
    let printed = [456.4, 490.9, 557.7, 631.4];
    for (ours, p) in row2.wavelengths_nm.iter().zip(printed) {
        assert!(
            (ours - p).abs() <= NODE_NM,
            "row 2 wavelength {ours} vs {p}"
        );
    }
    // Row 2's A weights at 490.9, 557.7, 631.4 nm as printed.
    let a: Vec<f64> = row2.weights[0]
        .iter()
        .copied()
        .filter(|w| *w != 0.0)
        .collect();
    assert_eq!(a.len(), 3);
    let mass: f64 = d.measures[0].mass.iter().sum();
    for (i, (o, p)) in a.iter().zip(paper::TABLE2_ROW2_A.weights).enumerate() {
        let o = o * paper::TABLE_1A_TOTAL_MASS[0] / mass;
        assert!(
            weight_ok(o, *p),
            "Table 2 row 2 A weight {i}: {o:.5} vs printed {p:.5}"
        );
    }
    // Row 2's A rule is interpolatory: exact for degree ≤ 2 (f64 rounding, 1e-12 relative).
    let m = &d.measures[0];
    for k in 0..3 {
        let exact: f64 = m.x.iter().zip(&m.mass).map(|(x, w)| w * x.powi(k)).sum();
        let quad: f64 = row2
            .wavelengths_nm
            .iter()
            .zip(&row2.weights[0])
            .map(|(l, w)| w * m.to_x(*l).powi(k))
            .sum();
        assert!((quad - exact).abs() <= 1e-12 * m.mass.iter().map(|w| w.abs()).sum::<f64>());
    }
    // C1 and C2 rows are the per-channel rules unchanged in both rows.
    for row in [row1, row2] {
        let c2: Vec<f64> = row.weights[2]
            .iter()
            .copied()
            .filter(|w| *w != 0.0)
            .collect();
        assert_eq!(c2, d.rules[2][0].weights);
        let c1: Vec<f64> = row.weights[1]
            .iter()
            .copied()
            .filter(|w| *w != 0.0)
            .collect();
        assert_eq!(c1, d.rules[1][1].weights);
    }
}
