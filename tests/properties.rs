//! Property tests of the runtime against the f64 derivation and against its own documented
//! invariants. Every random property runs `ProptestConfig::with_cases(10_000)` cases (regressions
//! are not persisted to files: a failure prints the shrunk input instead); the `micromath` check
//! (10) is a deterministic sweep of 12 million inputs instead.
//!
//! Notation in the tolerances: ε = `f32::EPSILON` = 2⁻²³, u = ε / 2 (the unit roundoff of
//! round-to-nearest). Every bound says where it comes from; where a property prints a "measured"
//! value, that is the largest error seen, in the units of the bound, so the slack can be judged.

// Channel loops index several parallel arrays (weights, references, outputs) by channel.
#![allow(clippy::needless_range_loop)]

/// The data files the derivation reads (the runtime crate's `data/`).
const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data");

mod common;

use common::{FOLDED_ROW1, FOLDED_ROW2, MAPPINGS};

use std::cell::Cell;
use std::fmt::Debug;
use std::sync::OnceLock;

use proptest::array::uniform;
use proptest::prelude::*;
use proptest::test_runner::TestCaseResult;
use spectral_quadrature::tables::{self, displays, folded, rules};
use spectral_quadrature::{
    ac1c2_from_xyz, f32_budget, xyz_from_ac1c2, Channel, Display, DynamicSet, Error, FoldedSet,
    GamutMapping, GaussRule, LengthOf, RuleStatus, WavelengthSet,
};
use spectral_quadrature_generator::{derive, Derivation, Settings};

/// ε as f64.
const EPS: f64 = f32::EPSILON as f64;
/// u = ε / 2, the unit roundoff of f32 round-to-nearest.
const U: f64 = EPS / 2.0;
/// 2⁻¹⁵⁰: half the smallest f32 subnormal, the absolute error of one f32 product that underflows.
const HALF_SUBNORMAL: f64 = 7.006_492_321_624_085e-46;

/// Runs one property for 10 000 cases with [`common::check_property`].
fn check<S>(name: &str, strategy: S, test: impl Fn(S::Value) -> TestCaseResult)
where
    S: Strategy,
    S::Value: Debug,
{
    common::check_property(10_000, name, strategy, test);
}

/// Keeps the largest value seen (a measured error, in the units of its bound).
fn record(worst: &Cell<f64>, value: f64) {
    if value > worst.get() {
        worst.set(value);
    }
}

fn fresh() -> &'static Derivation {
    static D: OnceLock<Derivation> = OnceLock::new();
    D.get_or_init(|| derive(&Settings::new(DATA_DIR)).expect("default derivation"))
}

/// The f64 folded weights `d.folded(table2[k], displays[j])`, `[k][j]`.
fn folded64() -> &'static [[[Vec<f64>; 3]; 4]; 2] {
    static F: OnceLock<[[[Vec<f64>; 3]; 4]; 2]> = OnceLock::new();
    F.get_or_init(|| {
        let d = fresh();
        assert_eq!(d.displays.len(), 4);
        // The derivation names displays by their const names; `displays::ALL` is in this order.
        let consts = ["SRGB", "DISPLAY_P3", "REC2020", "MEYER_1987"];
        for (j, display) in displays::ALL.iter().enumerate() {
            assert_eq!(d.displays[j].0.name, consts[j], "display order");
            let primaries = d.displays[j].0.primaries_xy.map(|p| p.map(|v| v as f32));
            assert_eq!(display.primaries_xy(), primaries, "{}", display.name());
            // One description: the baked human name is the derivation's label.
            assert_eq!(display.name(), d.displays[j].0.label, "display name");
        }
        [0, 1].map(|k| [0, 1, 2, 3].map(|j| d.folded(&d.table2[k], &d.displays[j].1)))
    })
}

/// One sample: reflectance-like 0..1, radiance-like 0..1e4, or signed ±1e3.
fn sample() -> impl Strategy<Value = f32> + Clone {
    prop_oneof![0.0f32..=1.0, 0.0f32..=1e4, -1e3f32..=1e3]
}

/// A spectrum of 16 samples (sets use a prefix): all in one range, or mixed per sample.
fn spectrum16() -> impl Strategy<Value = [f32; 16]> {
    prop_oneof![
        uniform(0.0f32..=1.0),
        uniform(0.0f32..=1e4),
        uniform(-1e3f32..=1e3),
        uniform(sample()),
    ]
}

fn prefix<const N: usize>(s: &[f32; 16]) -> [f32; N] {
    s[..N].try_into().expect("N <= 16")
}

/// `(Σ w_i s_i, Σ |w_i s_i|)` in f64.
fn dot64(w: &[f64], s: &[f32]) -> (f64, f64) {
    assert_eq!(w.len(), s.len());
    w.iter().zip(s).fold((0.0, 0.0), |(sum, abs), (w, s)| {
        let p = w * f64::from(*s);
        (sum + p, abs + p.abs())
    })
}

/// The f64 reference's own rounding: an N-term f64 sum is within N · 2⁻⁵³ · Σ|terms| of exact
/// (recursive summation; products exact to 2⁻⁵³ relative). 2⁻²⁹ of the f32 budget: it only
/// makes the comparison rigorous.
fn f64_slack(n: usize, abs: f64) -> f64 {
    (n as f64 + 1.0) * f64::EPSILON * abs
}

/// Checks `got[c]` against the exact f64 sum `w64[c] · s` within `f32_budget(N, Σ|w s|)` and
/// records the error in units of ε · Σ|w s|.
fn assert_budget(
    name: &str,
    got: [f32; 3],
    w64: [&[f64]; 3],
    s: &[f32],
    worst: &Cell<f64>,
) -> TestCaseResult {
    let n = s.len();
    for c in 0..3 {
        let (exact, abs) = dot64(w64[c], s);
        let bound = f32_budget(n, abs) + f64_slack(n, abs);
        let err = (f64::from(got[c]) - exact).abs();
        if abs > 0.0 {
            record(worst, err / (EPS * abs));
        }
        prop_assert!(
            err <= bound,
            "{name} channel {c}: got {} exact {exact} error {err:e} > budget {bound:e}",
            got[c]
        );
    }
    Ok(())
}

/// The f64 rows of channel `c`'s rule of `order` as a 3-row set (other rows zero).
fn rule_rows(c: usize, order: usize) -> [Vec<f64>; 3] {
    let rule = &fresh().rules[c][order - 1];
    let zero = vec![0.0; rule.weights.len()];
    let mut rows = [zero.clone(), zero.clone(), zero];
    rows[c] = rule.weights.clone();
    rows
}

fn rows_ref(rows: &[Vec<f64>; 3]) -> [&[f64]; 3] {
    [&rows[0], &rows[1], &rows[2]]
}

fn check_set<const N: usize>(
    name: &str,
    set: &WavelengthSet<N>,
    w64: &[Vec<f64>; 3],
    s: &[f32; 16],
    worst: &Cell<f64>,
) -> TestCaseResult {
    let s: [f32; N] = prefix(s);
    assert_budget(name, set.ac1c2(&s), rows_ref(w64), &s, worst)
}

// ---------------------------------------------------------------------------------------------
// 1. Runtime f32 against the f64 derivation
// ---------------------------------------------------------------------------------------------

#[test]
fn p1_ac1c2_within_f32_budget_of_the_f64_derivation() {
    let d = fresh();
    let rule_sets = [
        ("A_3", 0, 3),
        ("A_16", 0, 16),
        ("C1_2", 1, 2),
        ("C1_15", 1, 15),
        ("C2_1", 2, 1),
        ("C2_15", 2, 15),
    ]
    .map(|(name, c, o)| (name, rule_rows(c, o)));
    let worst = Cell::new(0.0);
    check("ac1c2 vs derivation", spectrum16(), |s| {
        check_set(
            "TABLE2_ROW1",
            &tables::TABLE2_ROW1,
            &d.table2[0].weights,
            &s,
            &worst,
        )?;
        check_set(
            "TABLE2_ROW2",
            &tables::TABLE2_ROW2,
            &d.table2[1].weights,
            &s,
            &worst,
        )?;
        check_set("A_3", &rules::A_3, &rule_sets[0].1, &s, &worst)?;
        check_set("A_16", &rules::A_16, &rule_sets[1].1, &s, &worst)?;
        check_set("C1_2", &rules::C1_2, &rule_sets[2].1, &s, &worst)?;
        check_set("C1_15", &rules::C1_15, &rule_sets[3].1, &s, &worst)?;
        check_set("C2_1", &rules::C2_1, &rule_sets[4].1, &s, &worst)?;
        check_set("C2_15", &rules::C2_15, &rule_sets[5].1, &s, &worst)
    });
    // The budget is (N + 1) ε in these units (N ≤ 16).
    eprintln!("p1 ac1c2: measured max error = {:.3} ε·Σ|w s|", worst.get());
}

#[test]
fn p1_folded_linear_rgb_within_f32_budget_of_the_f64_fold() {
    let f64s = folded64();
    let worst = Cell::new(0.0);
    check("linear_rgb vs f64 fold", spectrum16(), |s| {
        for j in 0..4 {
            let s6: [f32; 6] = prefix(&s);
            let name = format!("TABLE2_ROW1_{}", displays::ALL[j].name());
            assert_budget(
                &name,
                FOLDED_ROW1[j].linear_rgb(&s6),
                rows_ref(&f64s[0][j]),
                &s6,
                &worst,
            )?;
            let s4: [f32; 4] = prefix(&s);
            let name = format!("TABLE2_ROW2_{}", displays::ALL[j].name());
            assert_budget(
                &name,
                FOLDED_ROW2[j].linear_rgb(&s4),
                rows_ref(&f64s[1][j]),
                &s4,
                &worst,
            )?;
        }
        Ok(())
    });
    eprintln!(
        "p1 folded: measured max error = {:.3} ε·Σ|w s| (budget N + 1 = 5 or 7)",
        worst.get()
    );
}

// ---------------------------------------------------------------------------------------------
// 2. Linearity of AC1C2 in the samples
// ---------------------------------------------------------------------------------------------

/// `ac1c2(a·s + b·t)` and `a·ac1c2(s) + b·ac1c2(t)` (both f32) against the f64 reference
/// `R = a·(W s) + b·(W t)` with W the set's own f32 weights (exact in f64):
///
/// * left: `|ac1c2(u) − W u| ≤ f32_budget(N, Σ|W u|)` (u = fl(fl(a s) + fl(b t))), plus
///   `|W (u − (a s + b t))| ≤ Σ|W_i| (ε (1 + u) (|a s_i| + |b t_i|) + 2⁻¹⁴⁹)`: two products and a
///   sum, u each, and two possibly underflowing products (2⁻¹⁵⁰ each);
/// * right: `|a|·f32_budget(N, Σ|W s|) + |b|·f32_budget(N, Σ|W t|)` (the two sums), plus
///   `ε (1 + u) (|a p| + |b q|) + 2⁻¹⁴⁹` for forming `a p + b q` in f32;
/// * and the f64 reference's own rounding.
fn linearity<const N: usize>(
    name: &str,
    set: &WavelengthSet<N>,
    a: f32,
    b: f32,
    s: &[f32; N],
    t: &[f32; N],
    worst: &Cell<f64>,
) -> TestCaseResult {
    let u: [f32; N] = std::array::from_fn(|i| a * s[i] + b * t[i]);
    let lhs = set.ac1c2(&u);
    let p = set.ac1c2(s);
    let q = set.ac1c2(t);
    let rhs: [f32; 3] = std::array::from_fn(|c| a * p[c] + b * q[c]);
    let (a64, b64) = (f64::from(a), f64::from(b));
    for c in 0..3 {
        let w: Vec<f64> = set.weights()[c].iter().map(|&w| f64::from(w)).collect();
        let (ws, ws_abs) = dot64(&w, s);
        let (wt, wt_abs) = dot64(&w, t);
        let (_, wu_abs) = dot64(&w, &u);
        let reference = a64 * ws + b64 * wt;
        let forming_u: f64 = (0..N)
            .map(|i| {
                w[i].abs()
                    * (EPS * (1.0 + U) * (a64 * f64::from(s[i])).abs()
                        + EPS * (1.0 + U) * (b64 * f64::from(t[i])).abs()
                        + 4.0 * HALF_SUBNORMAL)
            })
            .sum();
        let ref_slack = f64_slack(N + 2, a64.abs() * ws_abs + b64.abs() * wt_abs);
        let left = f32_budget(N, wu_abs) + forming_u;
        let right = a64.abs() * f32_budget(N, ws_abs)
            + b64.abs() * f32_budget(N, wt_abs)
            + EPS * (1.0 + U) * (a64 * f64::from(p[c])).abs()
            + EPS * (1.0 + U) * (b64 * f64::from(q[c])).abs()
            + 4.0 * HALF_SUBNORMAL;
        let bound = left + right + 2.0 * ref_slack;
        let err = (f64::from(lhs[c]) - f64::from(rhs[c])).abs();
        if bound > 0.0 {
            record(worst, err / bound);
        }
        prop_assert!(
            err <= bound,
            "{name} channel {c}: ac1c2(a s + b t) = {} but a ac1c2(s) + b ac1c2(t) = {} \
             (reference {reference}); |diff| {err:e} > {bound:e}",
            lhs[c],
            rhs[c]
        );
    }
    Ok(())
}

#[test]
fn p2_ac1c2_is_linear_in_the_samples() {
    let coefficient = || prop_oneof![Just(0.0f32), Just(1.0f32), Just(-1.0f32), -10.0f32..=10.0];
    let worst = Cell::new(0.0);
    check(
        "linearity",
        (coefficient(), coefficient(), spectrum16(), spectrum16()),
        |(a, b, s, t)| {
            linearity(
                "TABLE2_ROW1",
                &tables::TABLE2_ROW1,
                a,
                b,
                &prefix(&s),
                &prefix(&t),
                &worst,
            )?;
            linearity(
                "TABLE2_ROW2",
                &tables::TABLE2_ROW2,
                a,
                b,
                &prefix(&s),
                &prefix(&t),
                &worst,
            )?;
            linearity("A_16", &rules::A_16, a, b, &s, &t, &worst)
        },
    );
    eprintln!(
        "p2 linearity: measured max |diff| = {:.3} of the summed bound",
        worst.get()
    );
}

// ---------------------------------------------------------------------------------------------
// 3. XYZ ↔ AC1C2 round trip
// ---------------------------------------------------------------------------------------------

fn abs_mat(m: &[[f32; 3]; 3]) -> [[f64; 3]; 3] {
    m.map(|r| r.map(|v| f64::from(v).abs()))
}

fn mat_vec64(m: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
}

#[test]
fn p3_f64_product_of_the_baked_matrices_is_identity() {
    // P = M⁻¹₃₂ · M₃₂ in f64 (exact to 2⁻⁵³ relative). M₃₂ and M⁻¹₃₂ are the f64 matrices
    // rounded entrywise (u relative each), so |P − I| ≤ u (|M⁻¹| |M|) + u (|M⁻¹| |M|) = ε (|M⁻¹| |M|)
    // entrywise, to first order (plus the derivation's f64 inverse, ~1e-16).
    let m = tables::XYZ_TO_AC1C2.map(|r| r.map(f64::from));
    let mi = tables::AC1C2_TO_XYZ.map(|r| r.map(f64::from));
    let (am, ami) = (
        abs_mat(&tables::XYZ_TO_AC1C2),
        abs_mat(&tables::AC1C2_TO_XYZ),
    );
    let mut worst: f64 = 0.0;
    for (label, a, b, aa, ab) in [("M⁻¹·M", &mi, &m, &ami, &am), ("M·M⁻¹", &m, &mi, &am, &ami)]
    {
        for i in 0..3 {
            for j in 0..3 {
                let p: f64 = (0..3).map(|k| a[i][k] * b[k][j]).sum();
                let abs: f64 = (0..3).map(|k| aa[i][k] * ab[k][j]).sum();
                let dev = (p - if i == j { 1.0 } else { 0.0 }).abs();
                worst = worst.max(dev);
                assert!(
                    dev <= EPS * abs + 1e-15,
                    "{label}[{i}][{j}] = {p}: deviation {dev:e} > ε·(|A||B|) = {:e}",
                    EPS * abs
                );
            }
        }
    }
    eprintln!("p3 matrices: measured max |P − I| = {worst:e}");
    // Measured 4.4e-8 (largest entry, M·M⁻¹); 1e-6 is the headline bound.
    assert!(worst <= 1e-6);
}

#[test]
fn p3_xyz_ac1c2_round_trip() {
    // z = M⁻¹ fl(M v): with y = M v + e₁, |e₁| ≤ γ₃ |M| |v| (3 products, 2 sums: 3u), and
    // z = M⁻¹ y + e₂, |e₂| ≤ γ₃ |M⁻¹| |y|, and M⁻¹₃₂ M₃₂ = I + E, |E| ≤ ε |M⁻¹| |M| (test above):
    // |z − v| ≤ (ε + 3u + 3u) |M⁻¹| |M| |v| = 4ε |M⁻¹| |M| |v| to first order. Asserted with c = 4;
    // underflow (values near 1e-38) adds at most 6 · 2⁻¹⁵⁰ · (|M⁻¹| 1), covered by 1e-44.
    let am = abs_mat(&tables::XYZ_TO_AC1C2);
    let ami = abs_mat(&tables::AC1C2_TO_XYZ);
    let worst = Cell::new(0.0);
    check("round trip", uniform::<_, 3>(sample()), |v| {
        let z = xyz_from_ac1c2(ac1c2_from_xyz(v));
        let scale = mat_vec64(&ami, mat_vec64(&am, v.map(|x| f64::from(x).abs())));
        for i in 0..3 {
            let err = (f64::from(z[i]) - f64::from(v[i])).abs();
            if scale[i] > 0.0 {
                record(&worst, err / (EPS * scale[i]));
            }
            prop_assert!(
                err <= 4.0 * EPS * scale[i] + 1e-44,
                "component {i}: {} → {} error {err:e} > 4ε·(|M⁻¹||M||v|) = {:e}",
                v[i],
                z[i],
                4.0 * EPS * scale[i]
            );
        }
        Ok(())
    });
    eprintln!(
        "p3 round trip: measured max error = {:.3} ε·(|M⁻¹||M||v|) (asserted ≤ 4)",
        worst.get()
    );
}

// ---------------------------------------------------------------------------------------------
// 4. Baked constants equal a fresh derivation
// ---------------------------------------------------------------------------------------------

fn status_matches(baked: RuleStatus, fresh: spectral_quadrature_generator::Status) -> bool {
    matches!(
        (baked, fresh),
        (
            RuleStatus::Defined,
            spectral_quadrature_generator::Status::Defined
        ) | (
            RuleStatus::Outside,
            spectral_quadrature_generator::Status::Outside
        ) | (
            RuleStatus::Complex,
            spectral_quadrature_generator::Status::Complex
        ) | (
            RuleStatus::VanishingNorm,
            spectral_quadrature_generator::Status::VanishingNorm
        )
    )
}

fn f32s(v: &[f64]) -> Vec<f32> {
    v.iter().map(|&x| x as f32).collect()
}

#[test]
fn p4_baked_constants_equal_a_fresh_derivation() {
    let d = fresh();
    let f64s = folded64();
    assert_eq!(tables::GRID_LEN, d.grid_nm.len());
    check(
        "baked == derived",
        (
            0usize..3,
            1usize..=tables::MAX_ORDER,
            0usize..tables::GRID_LEN,
            0usize..4,
        ),
        |(c, order, i, j)| {
            // Exact: the generator writes `v as f32` and Rust parses the printed f32 exactly.
            let baked = &tables::RULES[c][order - 1];
            let fresh_rule = &d.rules[c][order - 1];
            prop_assert_eq!(baked.channel().index(), c);
            prop_assert_eq!(usize::from(baked.order()), order);
            prop_assert!(status_matches(baked.status(), fresh_rule.status));
            if baked.status() == RuleStatus::Defined {
                prop_assert_eq!(baked.wavelengths_nm().to_vec(), f32s(&fresh_rule.nodes_nm));
                prop_assert_eq!(baked.weights().to_vec(), f32s(&fresh_rule.weights));
                prop_assert_eq!(baked.wavelengths_nm().len(), order);
            } else {
                prop_assert!(baked.wavelengths_nm().is_empty() && baked.weights().is_empty());
            }
            prop_assert_eq!(
                tables::SENSITIVITIES[i],
                d.sensitivities[i].map(|v| v as f32)
            );
            prop_assert_eq!(tables::GRID_NM[i], d.grid_nm[i] as f32);
            // And the folded weights of display j (both rows of Table 2).
            for r in 0..3 {
                prop_assert_eq!(FOLDED_ROW1[j].weights()[r].to_vec(), f32s(&f64s[0][j][r]));
                prop_assert_eq!(FOLDED_ROW2[j].weights()[r].to_vec(), f32s(&f64s[1][j][r]));
            }
            Ok(())
        },
    );
}

// ---------------------------------------------------------------------------------------------
// 5. Folded path equals the unfolded path
// ---------------------------------------------------------------------------------------------

/// `display.linear_from_xyz(set.xyz(s)) · (1 / UNIT_SPECTRUM_Y)` in f32 against
/// `folded.linear_rgb(s)`, both against the exact `F s` with F the f64 fold.
///
/// Unfolded budget, in units of u = ε/2 on `(|X2R| |A2X| |W| |s|)_r / Y`: N + 1 for the weighted
/// sums (weights rounded to f32, N products, N − 1 additions), 3 + 1 for each of the two 3×3
/// products (3 products and 2 additions, and the entries rounded to f32), 3 for the scale (Y
/// rounded to f32, the division 1/Y and the product): N + 12 u = (N/2 + 6) ε, first order. The
/// asserted (N + 10) ε leaves a factor ≥ 1.6 for second-order terms. The folded path has its own
/// `f32_budget` (the fold was done in f64). Underflow: the samples are never below ~1e-30, so no
/// product underflows; 1e-40 covers the reference's own f64 rounding.
#[allow(clippy::too_many_arguments)] // one set, display and its references: all needed
fn folded_vs_unfolded<const N: usize>(
    name: &str,
    set: &WavelengthSet<N>,
    folded_set: &FoldedSet<N>,
    display: &Display,
    w64: &[Vec<f64>; 3],
    x2r: &[[f64; 3]; 3],
    f64_fold: &[Vec<f64>; 3],
    s: &[f32; N],
    worst: &Cell<f64>,
) -> TestCaseResult {
    let a2x = &fresh().opponent.ac1c2_to_xyz;
    let y = fresh().unit_spectrum_y;
    let inv = 1.0f32 / tables::UNIT_SPECTRUM_Y;
    let unfolded = display.linear_from_xyz(set.xyz(s)).map(|v| v * inv);
    let folded_rgb = folded_set.linear_rgb(s);
    let abs_ws: [f64; 3] = [0, 1, 2].map(|c| {
        dot64(
            &w64[c].iter().map(|w| w.abs()).collect::<Vec<_>>(),
            &s.map(f32::abs),
        )
        .0
    });
    let abs_chain = mat_vec64(
        &x2r.map(|r| r.map(f64::abs)),
        mat_vec64(&a2x.map(|r| r.map(f64::abs)), abs_ws),
    );
    for r in 0..3 {
        let (exact, abs) = dot64(&f64_fold[r], s);
        let budget_folded = f32_budget(N, abs) + f64_slack(N, abs);
        let budget_unfolded = (N as f64 + 10.0) * EPS * abs_chain[r] / y + 1e-40;
        let bound = budget_folded + budget_unfolded;
        let err = (f64::from(unfolded[r]) - f64::from(folded_rgb[r])).abs();
        if abs_chain[r] > 0.0 {
            record(
                worst,
                (f64::from(unfolded[r]) - exact).abs() / (EPS * abs_chain[r] / y),
            );
        }
        prop_assert!(
            err <= bound,
            "{name} channel {r}: unfolded {} folded {} (exact {exact}): |diff| {err:e} > {bound:e}",
            unfolded[r],
            folded_rgb[r]
        );
        prop_assert!(
            (f64::from(unfolded[r]) - exact).abs() <= budget_unfolded,
            "{name} channel {r}: unfolded {} exact {exact} beyond (N + 10) ε budget {budget_unfolded:e}",
            unfolded[r]
        );
    }
    Ok(())
}

#[test]
fn p5_folded_equals_unfolded() {
    let d = fresh();
    let f64s = folded64();
    let worst = Cell::new(0.0);
    check("folded vs unfolded", spectrum16(), |s| {
        for j in 0..4 {
            let x2r = &d.displays[j].1.xyz_to_rgb;
            let display = &displays::ALL[j];
            folded_vs_unfolded(
                "ROW1",
                &tables::TABLE2_ROW1,
                &FOLDED_ROW1[j],
                display,
                &d.table2[0].weights,
                x2r,
                &f64s[0][j],
                &prefix(&s),
                &worst,
            )?;
            folded_vs_unfolded(
                "ROW2",
                &tables::TABLE2_ROW2,
                &FOLDED_ROW2[j],
                display,
                &d.table2[1].weights,
                x2r,
                &f64s[1][j],
                &prefix(&s),
                &worst,
            )?;
        }
        Ok(())
    });
    eprintln!(
        "p5 unfolded path: measured max error = {:.3} ε·(|X2R||A2X||W||s|)/Y (asserted ≤ N + 10 = 14 or 16)",
        worst.get()
    );
}

// ---------------------------------------------------------------------------------------------
// 6. Encoded greys are monotonic
// ---------------------------------------------------------------------------------------------

fn non_decreasing<T: PartialOrd + Copy + Debug>(lo: [T; 3], hi: [T; 3]) -> bool {
    (0..3).all(|c| lo[c] <= hi[c])
}

#[test]
fn p6_encoded_greys_are_monotonic() {
    let level = || prop_oneof![1 => Just(0.0f32), 1 => Just(1.0f32), 8 => 0.0f32..=1.0];
    check("grey monotonic", (level(), level()), |(x, y)| {
        let (g1, g2) = if x <= y { (x, y) } else { (y, x) };
        for display in &displays::ALL {
            for mapping in MAPPINGS {
                let (a8, b8) = (
                    display.encode_u8(mapping, [g1; 3]),
                    display.encode_u8(mapping, [g2; 3]),
                );
                prop_assert!(
                    non_decreasing(a8, b8),
                    "{} {mapping:?}: u8 grey {g1} → {a8:?} but {g2} → {b8:?}",
                    display.name()
                );
                let (a16, b16) = (
                    display.encode_u16(mapping, [g1; 3]),
                    display.encode_u16(mapping, [g2; 3]),
                );
                prop_assert!(
                    non_decreasing(a16, b16),
                    "{} {mapping:?}: u16 grey {g1} → {a16:?} but {g2} → {b16:?}",
                    display.name()
                );
            }
        }
        Ok(())
    });
}

#[test]
fn p6_constant_spectra_encode_monotonically() {
    // A constant spectrum is the equal-energy white E: through TABLE2_ROW2_SRGB its linear RGB is
    // c · (1.205, 0.948, 0.909) (all rows of the folded weights sum to a positive number), so
    // every encoded channel must be non-decreasing in c ≥ 0, for both mappings.
    let set = folded::TABLE2_ROW2_SRGB;
    let unit = set.linear_rgb(&[1.0; 4]);
    assert!(
        unit.iter().all(|&v| v > 0.8 && v < 1.3),
        "E white in sRGB: {unit:?}"
    );
    let level = || prop_oneof![8 => 0.0f32..=2.0, 1 => 0.0f32..=1e3, 1 => Just(0.0f32)];
    check(
        "constant spectrum monotonic",
        (level(), level()),
        |(x, y)| {
            let (c1, c2) = if x <= y { (x, y) } else { (y, x) };
            for mapping in MAPPINGS {
                let a = set.encode_u8(mapping, &[c1; 4]);
                let b = set.encode_u8(mapping, &[c2; 4]);
                prop_assert!(
                    non_decreasing(a, b),
                    "{mapping:?}: c = {c1} → {a:?} but c = {c2} → {b:?}"
                );
            }
            Ok(())
        },
    );
}

// ---------------------------------------------------------------------------------------------
// 7. PreserveA keeps A
// ---------------------------------------------------------------------------------------------

/// `(Σ a_i rgb_i, Σ |a_i rgb_i|, Σ a_i)` in f64.
fn a_of(display: &Display, rgb: [f32; 3]) -> (f64, f64, f64) {
    let a = display.a_from_rgb().map(f64::from);
    let (sum, abs) = dot64(&a, &rgb);
    (sum, abs, a.iter().sum())
}

#[test]
fn p7_preserve_a_keeps_a() {
    // The library computes level = fl(fl(a·rgb) / fl(Σa)): |level₃₂ − level| ≤ (3u |a||rgb| + 3u
    // Σa |level|) / Σa ≤ 2ε (|a||rgb|/Σa + |level|) =: δ. Outside a δ band around 0 and 1 the
    // branch taken is therefore known.
    //
    // Inside, a·r = (1 − t) Σa level₃₂ + t a·rgb + rounding of r_c = level + t d_c: the error in
    // level contributes ≤ 3u|a||rgb| + 3u A ≤ 3ε |a||rgb|; d_c = rgb_c − level (u), t (u) and
    // t·d_c (u) contribute 3u Σ a_c t |d_c| ≤ 3u · 2|a||rgb| = 3ε |a||rgb|; the final sums u Σ a_c
    // r_c ≤ u |a||rgb|. Total ≤ 6.5 ε |a||rgb|; asserted: 8 ε (|a|·|rgb|) (a_from_rgb > 0).
    for display in &displays::ALL {
        assert!(display.a_from_rgb().iter().all(|&a| a > 0.0));
    }
    let worst = Cell::new(0.0);
    let branches = Cell::new([0usize; 4]);
    check(
        "PreserveA keeps A",
        (uniform::<_, 3>(-2.0f32..=3.0), 0usize..4),
        |(rgb, j)| {
            let display = &displays::ALL[j];
            let r = display.map_gamut(GamutMapping::PreserveA, rgb);
            prop_assert!(r.iter().all(|v| (0.0..=1.0).contains(v)), "{rgb:?} → {r:?}");
            let (a_in, abs, sa) = a_of(display, rgb);
            let level = a_in / sa;
            let delta = 2.0 * EPS * (abs / sa + level.abs()) + 1e-40;
            let mut counts = branches.get();
            if level >= 1.0 + delta {
                counts[0] += 1;
                prop_assert_eq!(r, [1.0; 3], "level {} ≥ 1 must give white", level);
            } else if level <= -delta {
                counts[1] += 1;
                prop_assert_eq!(r, [0.0; 3], "level {} ≤ 0 must give black", level);
            } else if level >= delta && level <= 1.0 - delta {
                counts[2] += 1;
                let (a_out, _, _) = a_of(display, r);
                let err = (a_out - a_in).abs();
                record(&worst, err / (EPS * abs));
                prop_assert!(
                    err <= 8.0 * EPS * abs + f64_slack(3, abs),
                    "{} {rgb:?} → {r:?}: A {a_in} → {a_out}, error {err:e} > 8ε·|a||rgb| = {:e}",
                    display.name(),
                    8.0 * EPS * abs
                );
            } else {
                counts[3] += 1;
            }
            branches.set(counts);
            Ok(())
        },
    );
    eprintln!(
        "p7 PreserveA: measured max |ΔA| = {:.3} ε·(|a|·|rgb|) (asserted ≤ 8); cases white/black/kept/boundary = {:?}",
        worst.get(),
        branches.get()
    );
}

#[test]
fn p7_preserve_a_leaves_in_gamut_colours_unchanged() {
    // In gamut, t = 1 in exact arithmetic and r_c = level + (rgb_c − level) = rgb_c; in f32 the
    // subtraction and the sum round (u each, relative to max(rgb_c, level)), and t can come out an
    // ulp below 1 (another u on |d_c| ≤ max(rgb_c, level)). Asserted: |r_c − rgb_c| ≤ 2ε
    // max(rgb_c, level), i.e. within about two ulps of the larger of the channel and the grey
    // level.
    let worst = Cell::new(0.0);
    check(
        "PreserveA identity in gamut",
        (
            uniform::<_, 3>(prop_oneof![1 => Just(0.0f32), 1 => Just(1.0f32), 8 => 0.0f32..=1.0]),
            0usize..4,
        ),
        |(rgb, j)| {
            let display = &displays::ALL[j];
            let r = display.map_gamut(GamutMapping::PreserveA, rgb);
            let (a_in, _, sa) = a_of(display, rgb);
            let level = (a_in / sa).clamp(0.0, 1.0);
            for c in 0..3 {
                let scale = f64::from(rgb[c]).max(level);
                let err = (f64::from(r[c]) - f64::from(rgb[c])).abs();
                if scale > 0.0 {
                    record(&worst, err / (EPS * scale));
                }
                prop_assert!(
                    err <= 2.0 * EPS * scale,
                    "{} in gamut {rgb:?} → {r:?} (channel {c}, error {err:e})",
                    display.name()
                );
            }
            Ok(())
        },
    );
    eprintln!(
        "p7 in gamut: measured max |r − rgb| = {:.3} ε·max(rgb_c, level) (asserted ≤ 2)",
        worst.get()
    );
}

// ---------------------------------------------------------------------------------------------
// 8. Batch equals per-pixel
// ---------------------------------------------------------------------------------------------

fn same_f32(a: [f32; 3], b: [f32; 3]) -> bool {
    (0..3).all(|c| a[c].to_bits() == b[c].to_bits() || (a[c].is_nan() && b[c].is_nan()))
}

/// Pixels of mixed samples, some with arbitrary f32 (NaN, ±Inf, subnormals, huge).
fn pixels<const N: usize>() -> impl Strategy<Value = Vec<[f32; N]>> {
    let s = prop_oneof![9 => sample(), 1 => any::<f32>()];
    proptest::collection::vec(uniform::<_, N>(s), 0..8)
}

fn batch_case<const N: usize>(
    set: &WavelengthSet<N>,
    folded_set: &FoldedSet<N>,
    mapping: GamutMapping,
    px: &[[f32; N]],
    extra: usize,
) -> TestCaseResult {
    let n = px.len();
    let mut lin = vec![[f32::NAN; 3]; n];
    folded_set.linear_rgb_batch(px, &mut lin).unwrap();
    let mut ac = vec![[f32::NAN; 3]; n];
    set.ac1c2_batch(px, &mut ac).unwrap();
    let mut e8 = vec![[7u8; 3]; n];
    folded_set.encode_u8_batch(mapping, px, &mut e8).unwrap();
    let mut e16 = vec![[7u16; 3]; n];
    folded_set.encode_u16_batch(mapping, px, &mut e16).unwrap();
    for (p, s) in px.iter().enumerate() {
        prop_assert!(
            same_f32(lin[p], folded_set.linear_rgb(s)),
            "linear_rgb pixel {p}"
        );
        prop_assert!(same_f32(ac[p], set.ac1c2(s)), "ac1c2 pixel {p}");
        prop_assert_eq!(
            e8[p],
            folded_set.encode_u8(mapping, s),
            "encode_u8 pixel {}",
            p
        );
        prop_assert_eq!(
            e16[p],
            folded_set.encode_u16(mapping, s),
            "encode_u16 pixel {}",
            p
        );
    }
    // Mismatched lengths (out longer by `extra`, or shorter when possible): an error naming both
    // lengths, and `out` untouched.
    let mut lengths = vec![n + extra];
    if n >= extra {
        lengths.push(n - extra);
    }
    for m in lengths {
        let expected = Err(Error::LengthMismatch {
            what: LengthOf::Output,
            expected: n,
            got: m,
        });
        let sentinel = [-7.5f32; 3];
        let mut out = vec![sentinel; m];
        prop_assert_eq!(folded_set.linear_rgb_batch(px, &mut out), expected);
        prop_assert!(out.iter().all(|o| *o == sentinel));
        prop_assert_eq!(set.ac1c2_batch(px, &mut out), expected);
        prop_assert!(out.iter().all(|o| *o == sentinel));
        let mut out8 = vec![[9u8; 3]; m];
        prop_assert_eq!(folded_set.encode_u8_batch(mapping, px, &mut out8), expected);
        prop_assert!(out8.iter().all(|o| *o == [9u8; 3]));
        let mut out16 = vec![[9u16; 3]; m];
        prop_assert_eq!(
            folded_set.encode_u16_batch(mapping, px, &mut out16),
            expected
        );
        prop_assert!(out16.iter().all(|o| *o == [9u16; 3]));
    }
    Ok(())
}

#[test]
fn p8_batch_equals_per_pixel() {
    check(
        "batch",
        (
            pixels::<6>(),
            pixels::<4>(),
            0usize..4,
            0usize..2,
            1usize..5,
        ),
        |(px6, px4, j, m, extra)| {
            batch_case(
                &tables::TABLE2_ROW1,
                &FOLDED_ROW1[j],
                MAPPINGS[m],
                &px6,
                extra,
            )?;
            batch_case(
                &tables::TABLE2_ROW2,
                &FOLDED_ROW2[j],
                MAPPINGS[m],
                &px4,
                extra,
            )
        },
    );
}

// ---------------------------------------------------------------------------------------------
// 9. DynamicSet
// ---------------------------------------------------------------------------------------------

#[test]
fn p9_dynamic_set_rebuilds_table2_row1_exactly() {
    let set = DynamicSet::<16>::from_rules(&[
        tables::A_RULES[2],
        tables::C1_RULES[1],
        tables::C2_RULES[0],
    ])
    .expect("defined rules, 6 wavelengths");
    assert_eq!(set.len(), 6);
    assert_eq!(
        set.wavelengths_nm(),
        tables::TABLE2_ROW1.wavelengths_nm().as_slice()
    );
    for c in Channel::ALL {
        assert_eq!(
            set.weights(c),
            tables::TABLE2_ROW1.weights()[c.index()].as_slice(),
            "{}",
            c.name()
        );
    }
}

/// All 48 baked rules.
fn all_rules() -> Vec<GaussRule> {
    tables::RULES.iter().flatten().copied().collect()
}

/// What the set should hold after adding `rules` in order, modelled independently: a sorted map
/// from wavelength to the three rows, weights accumulated in f32 in the same order as documented
/// (so equality is exact). `None` when an add fails.
type Model = std::collections::BTreeMap<u32, [f32; 3]>;

#[test]
fn p9_dynamic_set_model() {
    const CAP: usize = 16;
    let rules = all_rules();
    assert_eq!(rules.len(), 48);
    let pick = proptest::collection::vec(0usize..48, 1..7);
    let worst = Cell::new(0.0);
    let outcomes = Cell::new([0usize; 3]);
    check(
        "DynamicSet",
        (pick, spectrum16(), spectrum16()),
        |(picks, s1, s2)| {
            let mut set = DynamicSet::<CAP>::new();
            let mut model = Model::new();
            let mut added: Vec<&GaussRule> = Vec::new();
            let mut first_error = None;
            for &k in &picks {
                let rule = &rules[k];
                let before = set.clone();
                let result = set.add_rule(rule);
                let mut counts = outcomes.get();
                if rule.status() != RuleStatus::Defined {
                    counts[1] += 1;
                    prop_assert_eq!(
                        result,
                        Err(Error::UndefinedRule {
                            channel: rule.channel(),
                            order: rule.order()
                        })
                    );
                    prop_assert_eq!(&set, &before, "unchanged after UndefinedRule");
                } else {
                    let new = rule
                        .wavelengths_nm()
                        .iter()
                        .filter(|l| !model.contains_key(&l.to_bits()))
                        .count();
                    if model.len() + new > CAP {
                        counts[2] += 1;
                        prop_assert_eq!(result, Err(Error::Capacity { capacity: CAP }));
                        prop_assert_eq!(&set, &before, "unchanged after Capacity");
                    } else {
                        counts[0] += 1;
                        prop_assert_eq!(result, Ok(()));
                        for (&l, &w) in rule.wavelengths_nm().iter().zip(rule.weights()) {
                            model.entry(l.to_bits()).or_insert([0.0; 3])[rule.channel().index()] +=
                                w;
                        }
                        added.push(rule);
                    }
                }
                outcomes.set(counts);
                if let (Err(e), None) = (result, first_error) {
                    first_error = Some(e);
                }
                // Exact agreement with the model (wavelengths positive: bit order = numeric order).
                let model_nm: Vec<f32> = model.keys().map(|&b| f32::from_bits(b)).collect();
                prop_assert_eq!(set.wavelengths_nm(), model_nm.as_slice());
                for c in Channel::ALL {
                    let row: Vec<f32> = model.values().map(|w| w[c.index()]).collect();
                    prop_assert_eq!(set.weights(c), row.as_slice());
                }
            }
            // from_rules: the same set, or the first error.
            let picked: Vec<GaussRule> = picks.iter().map(|&k| rules[k]).collect();
            match (DynamicSet::<CAP>::from_rules(&picked), first_error) {
                (Ok(built), None) => prop_assert_eq!(&built, &set),
                (Err(e), Some(first)) => prop_assert_eq!(e, first),
                (got, want) => prop_assert!(
                    false,
                    "from_rules gave {:?}, expected error {:?}",
                    got,
                    want
                ),
            }
            // ac1c2 of the merged set = Σ over the added rules of each rule's own Σ w_i s(λ_i), where
            // s is a random spectrum (s1 and s2 interleaved, up to CAP = 16 wavelengths). The merged
            // weights are f32 sums of rule weights (u each, on shared wavelengths), then an n-term
            // f32 sum: within f32_budget(n, Σ_rules Σ_i |w_i s_i|) ((n + 1) u ≤ (n + 1) ε).
            let n = set.len();
            let samples: Vec<f32> = (0..n)
                .map(|i| if i % 2 == 0 { s1[i] } else { s2[i] })
                .collect();
            let got = set.ac1c2(&samples).expect("right length");
            for c in 0..3 {
                let mut exact = 0.0f64;
                let mut abs = 0.0f64;
                for rule in added.iter().filter(|r| r.channel().index() == c) {
                    for (l, w) in rule.wavelengths_nm().iter().zip(rule.weights()) {
                        let i = set
                            .wavelengths_nm()
                            .iter()
                            .position(|x| x == l)
                            .expect("node in set");
                        let p = f64::from(*w) * f64::from(samples[i]);
                        exact += p;
                        abs += p.abs();
                    }
                }
                let bound = f32_budget(n, abs) + f64_slack(n, abs);
                let err = (f64::from(got[c]) - exact).abs();
                if abs > 0.0 {
                    record(&worst, err / (EPS * abs));
                }
                prop_assert!(
                    err <= bound,
                    "channel {c}: {} vs Σ contributions {exact}: {err:e} > {bound:e}",
                    got[c]
                );
            }
            prop_assert_eq!(
                set.ac1c2(&[0.0; CAP + 1][..n + 1]),
                Err(Error::LengthMismatch {
                    what: LengthOf::Samples,
                    expected: n,
                    got: n + 1
                })
            );
            Ok(())
        },
    );
    let [ok, undefined, capacity] = outcomes.get();
    eprintln!(
        "p9 DynamicSet: adds ok {ok}, UndefinedRule {undefined}, Capacity {capacity}; \
         measured max ac1c2 error {:.3} ε·Σ|w s|",
        worst.get()
    );
    assert!(
        ok > 0 && undefined > 0 && capacity > 0,
        "every branch exercised"
    );
}

// ---------------------------------------------------------------------------------------------
// 10. micromath: encode_fast within ENCODE_FAST_MAX_ERROR
// ---------------------------------------------------------------------------------------------

#[cfg(feature = "micromath")]
#[test]
fn p10_encode_fast_within_stated_error() {
    use spectral_quadrature::{TransferFunction, ENCODE_FAST_MAX_ERROR};

    let curves = [
        TransferFunction::Srgb,
        TransferFunction::Gamma(1.0),
        TransferFunction::Gamma(1.8),
        TransferFunction::Gamma(2.2),
        TransferFunction::Gamma(2.4),
        TransferFunction::Gamma(2.6),
        TransferFunction::Gamma(3.0),
    ];
    let one = 1.0f32.to_bits();
    // Every 97th f32 bit pattern in 0..=1 (11 million values, all binades), every u16 level,
    // and 10⁶ pseudo-random values (splitmix64): half uniform in 0..1 (24-bit), half uniform over
    // the bit patterns of 0..=1 (so every binade down to the subnormals).
    let mut xs: Vec<f32> = (0..=one).step_by(97).map(f32::from_bits).collect();
    xs.push(1.0);
    xs.extend((0..=65535u32).map(|k| k as f32 / 65535.0));
    let mut state = 0x5eed_u64;
    let mut next = move || {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    };
    for k in 0..1_000_000 {
        let r = next();
        xs.push(if k % 2 == 0 {
            (r >> 40) as f32 / (1u64 << 24) as f32
        } else {
            f32::from_bits((r % (u64::from(one) + 1)) as u32)
        });
    }
    // One thread per curve: 12 million points × 7 curves take ~35 s of CPU in a debug build.
    let results: Vec<(TransferFunction, f32, f32)> = std::thread::scope(|scope| {
        let handles: Vec<_> = curves
            .iter()
            .map(|&tf| {
                let xs = &xs;
                scope.spawn(move || {
                    let (mut worst, mut at) = (0.0f32, 0.0f32);
                    for &x in xs {
                        let (fast, exact) = (
                            tf.encode_fast(spectral_quadrature::Rgb::R, x),
                            tf.encode(spectral_quadrature::Rgb::R, x),
                        );
                        assert!(
                            (0.0..=1.0).contains(&fast),
                            "{tf:?} encode_fast({x}) = {fast}"
                        );
                        let e = (fast - exact).abs();
                        if e > worst {
                            (worst, at) = (e, x);
                        }
                    }
                    (tf, worst, at)
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("curve thread"))
            .collect()
    });
    let mut failures = Vec::new();
    let mut overall = 0.0f32;
    for (tf, worst, at) in results {
        eprintln!(
            "p10 {tf:?}: measured max |encode_fast − encode| = {worst:e} at x = {at:e} \
             (ENCODE_FAST_MAX_ERROR = {ENCODE_FAST_MAX_ERROR:e})"
        );
        overall = overall.max(worst);
        if worst > ENCODE_FAST_MAX_ERROR {
            failures.push(format!("{tf:?}: {worst} at x = {at}"));
        }
    }
    assert!(
        failures.is_empty(),
        "encode_fast beyond ENCODE_FAST_MAX_ERROR = {ENCODE_FAST_MAX_ERROR}: {failures:?}"
    );
    // The constant is documented as *the* largest difference: a bound more than twice the
    // largest error seen would be misleading.
    assert!(
        overall >= ENCODE_FAST_MAX_ERROR / 2.0,
        "ENCODE_FAST_MAX_ERROR = {ENCODE_FAST_MAX_ERROR} but the largest error seen is {overall}"
    );
}
