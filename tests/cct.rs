//! Correlated colour temperature and Duv against the exact reference: the nearest point of the
//! Planckian locus in CIE 1960 (u, v), computed in f64 with the crate's observer by
//! `spectral_quadrature_build::planckian` (a scan, then false position on the distance's
//! derivative), for the same f32 XYZ the runtime gets.
//!
//! `cargo test --release --test integration -- cct:: --nocapture` prints the accuracy tables of
//! docs/colour-temperature-and-calibration.md.

use spectral_quadrature_build as sqd;

mod common;

use proptest::prelude::*;
use spectral_quadrature::tables::PLANCKIAN_LOCUS;
use spectral_quadrature::{uv_from_xyz, Cct, PlanckianLocus, CCT_MAX_ERROR_MIRED, DUV_MAX_ERROR};
use sqd::planckian::{self, CctDuv};
use std::sync::OnceLock;

/// The data files the derivation reads (the runtime crate's `data/`).
const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data");

struct Fixture {
    d: sqd::Derivation,
    locus: planckian::PlanckianLocus,
}

fn fixture() -> &'static Fixture {
    static F: OnceLock<Fixture> = OnceLock::new();
    F.get_or_init(|| {
        let d = sqd::derive(&sqd::Settings::new(DATA_DIR)).expect("default derivation");
        let locus = planckian::PlanckianLocus::new(&d.observer, d.settings.range_nm).unwrap();
        Fixture { d, locus }
    })
}

/// The f32 XYZ (Y = 1) of the point at `duv` from the locus at μ mired.
fn xyz_at(mired: f64, duv: f64) -> [f32; 3] {
    planckian::xyz_from_uv(fixture().locus.offset(mired, duv)).map(|c| c as f32)
}

/// The exact CCT and Duv of an f32 XYZ, from its chromaticity in f64.
fn exact(xyz: [f32; 3]) -> Option<CctDuv> {
    let uv = planckian::uv_from_xyz(xyz.map(f64::from))?;
    fixture().locus.cct_duv(uv)
}

/// The runtime's answer for `xyz`, the exact one, and the errors: |Δμ| in mired and |ΔDuv|.
fn errors(xyz: [f32; 3]) -> (Cct, CctDuv, f64, f64) {
    let e = exact(xyz).unwrap_or_else(|| panic!("no exact CCT for {xyz:?}"));
    let got = PLANCKIAN_LOCUS
        .cct(xyz)
        .unwrap_or_else(|| panic!("no CCT for {xyz:?} (exact {e:?})"));
    let dmired = (1e6 / f64::from(got.kelvin) - e.mired).abs();
    let dduv = (f64::from(got.duv) - e.duv).abs();
    (got, e, dmired, dduv)
}

/// The table's temperature range, 1000-100 000 K, in mired.
const TABLE_MIRED: [f64; 2] = planckian::TABLE_MIRED;

#[test]
fn the_baked_table_is_a_fresh_derivations() {
    let nodes = fixture().locus.table();
    assert_eq!(nodes.len(), PLANCKIAN_LOCUS.mired.len());
    for (i, n) in nodes.iter().enumerate() {
        assert_eq!(PLANCKIAN_LOCUS.mired[i], n.mired as f32);
        assert_eq!(PLANCKIAN_LOCUS.uv[i], n.uv.map(|c| c as f32));
        assert_eq!(PLANCKIAN_LOCUS.tangent[i], n.tangent.map(|c| c as f32));
        let (unit, along) = n.fixed_point();
        assert_eq!(PLANCKIAN_LOCUS.unit_tangent_q14[i], unit);
        assert_eq!(PLANCKIAN_LOCUS.along_q30[i], along);
        let chord = match nodes.get(i + 1) {
            Some(next) => [0, 1].map(|c| (next.uv[c] - n.uv[c]) as f32),
            None => [0.0; 2],
        };
        assert_eq!(PLANCKIAN_LOCUS.chord[i], chord);
    }
    assert_eq!(PLANCKIAN_LOCUS.kelvin_range(), [1000.0, 100_000.0]);
    // Every segment's cubic Hermite interpolant stays within the generator's tolerance of the
    // locus, checked here at odd sixteenths, between the quarters the generator checks.
    for w in nodes.windows(2) {
        for k in (1..16).step_by(2) {
            let t = k as f64 / 16.0;
            let h = planckian::hermite(&w[0], &w[1], t);
            let e = fixture()
                .locus
                .uv(w[0].mired + t * (w[1].mired - w[0].mired));
            let dist = (h[0] - e[0]).hypot(h[1] - e[1]);
            // A cubic Hermite's error is ∝ t²(1 − t)² to leading order, largest at the half,
            // which the generator checks: elsewhere it stays under the same bound.
            assert!(
                dist <= planckian::TABLE_TOLERANCE_UV,
                "segment at {} mired, t = {t}: {dist:e}",
                w[0].mired
            );
        }
    }
}

/// Largest errors over a band of temperatures and Duv.
#[derive(Default, Clone, Copy)]
struct Worst {
    points: usize,
    mired: f64,
    kelvin: f64,
    duv: f64,
}

impl Worst {
    fn add(&mut self, got: &Cct, e: &CctDuv, dmired: f64, dduv: f64) {
        self.points += 1;
        self.mired = self.mired.max(dmired);
        self.kelvin = self.kelvin.max((f64::from(got.kelvin) - e.kelvin).abs());
        self.duv = self.duv.max(dduv);
    }
}

/// A dense sweep of the whole documented domain: 1000-100 000 K (4001 equal steps in mired) by
/// Duv from −0.05 to 0.05 in steps of 0.005: every point within the stated bounds of the exact
/// CCT and Duv, and within what the crate promises in kelvin (1 K or 0.05 %, whichever is
/// larger, and 2e-4 in Duv). Prints the table of docs/colour-temperature-and-calibration.md.
#[test]
fn dense_sweep_within_the_stated_accuracy() {
    let bands: [(f64, f64); 6] = [
        (1000.0, 2000.0),
        (2000.0, 4000.0),
        (4000.0, 7000.0),
        (7000.0, 12_000.0),
        (12_000.0, 20_000.0),
        (20_000.0, 100_000.0),
    ];
    let mut within3 = [Worst::default(); 6];
    let mut within5 = [Worst::default(); 6];
    let steps = 4000;
    // The exact ends of the table may fall a rounding either side of it: not the first and
    // last step.
    for i in 1..steps {
        let mired = TABLE_MIRED[0] + (TABLE_MIRED[1] - TABLE_MIRED[0]) * i as f64 / steps as f64;
        for k in -10..=10 {
            // ±0.0499 at the ends: exactly ±0.05 may round either side of the limit.
            let duv = (k as f64 * 0.005).clamp(-0.0499, 0.0499);
            let xyz = xyz_at(mired, duv);
            let (got, e, dmired, dduv) = errors(xyz);
            assert!(
                dmired <= f64::from(CCT_MAX_ERROR_MIRED) && dduv <= f64::from(DUV_MAX_ERROR),
                "{xyz:?} ({mired} mired, Duv {duv}): Δμ {dmired:e} mired, ΔDuv {dduv:e}"
            );
            let promised = (0.0005 * e.kelvin).max(1.0);
            assert!((f64::from(got.kelvin) - e.kelvin).abs() <= promised && dduv <= 2e-4);
            let band = bands
                .iter()
                .position(|&(lo, hi)| e.kelvin >= lo && e.kelvin < hi)
                .unwrap_or(5);
            within5[band].add(&got, &e, dmired, dduv);
            if duv.abs() <= 0.03 + 1e-12 {
                within3[band].add(&got, &e, dmired, dduv);
            }
        }
    }
    println!(
        r"| CCT | points, \|Duv\| ≤ 0.03 | max \|Δμ\| | max \|ΔT\| | max \|ΔDuv\| | \|Duv\| ≤ 0.05: max \|Δμ\| | max \|ΔT\| | max \|ΔDuv\| |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for (b, (lo, hi)) in bands.iter().enumerate() {
        let (w3, w5) = (within3[b], within5[b]);
        println!(
            "| {lo}-{hi} K | {} | {:.1e} mired | {:.4} K | {:.1e} | {:.1e} mired | {:.4} K | {:.1e} |",
            w3.points, w3.mired, w3.kelvin, w3.duv, w5.mired, w5.kelvin, w5.duv
        );
    }
}

/// Points whose foot lies at a node or just beside one, where the binary search's integer sides
/// (exact to about 2e-5 in (u, v)) may pick either neighbouring segment: within the bounds.
#[test]
fn feet_at_the_nodes() {
    let nodes = fixture().locus.table();
    for (i, n) in nodes.iter().enumerate() {
        for offset in [-1e-3, -1e-4, 0.0, 1e-4, 1e-3] {
            let mired = n.mired + offset;
            let end = (i == 0 && offset <= 0.0) || (i == nodes.len() - 1 && offset >= 0.0);
            if end {
                continue;
            }
            for duv in [-0.0499, -0.02, 0.0, 0.003, 0.0499] {
                let (_, _, dmired, dduv) = errors(xyz_at(mired, duv));
                assert!(
                    dmired <= f64::from(CCT_MAX_ERROR_MIRED) && dduv <= f64::from(DUV_MAX_ERROR),
                    "node {i} ({mired} mired), Duv {duv}: Δμ {dmired:e}, ΔDuv {dduv:e}"
                );
            }
        }
    }
}

/// Every CIE illuminant and LED light in data/, its XYZ integrated at 1 nm: within the bounds.
/// Prints the per-light table of docs/colour-temperature-and-calibration.md.
#[test]
fn the_cie_illuminants_and_leds() {
    let f = fixture();
    let range = f.d.settings.range_nm;
    let full = sqd::evaluate::full_integration(&f.d.observer, range, 1.0).unwrap();
    println!("| light | exact CCT | exact Duv | runtime CCT | runtime Duv | ΔT | ΔDuv |");
    println!("|---|---|---|---|---|---|---|");
    let mut checked = 0;
    for name in sqd::evaluate::builtin_lights() {
        let light =
            sqd::evaluate::builtin_illuminant(std::path::Path::new(DATA_DIR), name, range).unwrap();
        let xyz = full.xyz(|nm| light.at(nm)).map(|c| c as f32);
        let e = exact(xyz).unwrap_or_else(|| panic!("{name}: no exact CCT"));
        let (got, _, dmired, dduv) = errors(xyz);
        assert!(
            dmired <= f64::from(CCT_MAX_ERROR_MIRED) && dduv <= f64::from(DUV_MAX_ERROR),
            "{name}: Δμ {dmired:e} mired, ΔDuv {dduv:e}"
        );
        println!(
            "| {name} | {:.3} K | {:.6} | {:.3} K | {:.6} | {:.4} K | {:.1e} |",
            e.kelvin,
            e.duv,
            got.kelvin,
            got.duv,
            f64::from(got.kelvin) - e.kelvin,
            f64::from(got.duv) - e.duv
        );
        checked += 1;
    }
    assert_eq!(
        checked, 26,
        "the illuminants A, C, D50, D65, E, F1-F12 and 9 LEDs"
    );
}

/// Known values on the CIE 1931 locus at 380-770 nm: illuminant A is a blackbody (at 2856 K
/// with the c₂ of its time), and D65's CCT is about 6504 K.
#[test]
fn illuminant_a_and_d65() {
    let f = fixture();
    let range = f.d.settings.range_nm;
    let full = sqd::evaluate::full_integration(&f.d.observer, range, 1.0).unwrap();
    let cct = |name: &str| {
        let light =
            sqd::evaluate::builtin_illuminant(std::path::Path::new(DATA_DIR), name, range).unwrap();
        PLANCKIAN_LOCUS
            .cct(full.xyz(|nm| light.at(nm)).map(|c| c as f32))
            .unwrap()
    };
    let a = cct("A");
    // CIE S 014-2 defines A as Planck's law at 2848 K with c₂ = 1.435e-2 (so that it is the
    // 2856 K of the older c₂ = 1.438e-2): the same curve as 2848 · 1.4388 / 1.435 K with CIE
    // 015's c₂ = 1.4388e-2. The 380-770 nm range and the data's 5-6 digits move it by 0.2 K.
    let expected = 2848.0 * 1.4388 / 1.435;
    assert!(
        (f64::from(a.kelvin) - expected).abs() < 0.5,
        "{a:?} vs {expected}"
    );
    assert!(a.duv.abs() < 1e-5, "{a:?}");
    let d65 = cct("D65");
    // 6504 K and Duv 0.0032 in the literature (CIE 1931 at 360-830 nm); within a kelvin here.
    assert!((d65.kelvin - 6504.0).abs() < 1.0, "{d65:?}");
    assert!((d65.duv - 0.0032).abs() < 1e-4, "{d65:?}");
}

/// Beyond the table's ends, farther than MAX_DUV from the locus, and for XYZ without a
/// chromaticity, the answer is `None`; just inside them, an answer.
#[test]
fn outside_the_range_is_none() {
    // On the locus below 1000 K and above 100 000 K.
    for kelvin in [500.0, 900.0, 995.0, 100_500.0, 150_000.0, 1e6] {
        let xyz = xyz_at(1e6 / kelvin, 0.0);
        assert_eq!(PLANCKIAN_LOCUS.cct(xyz), None, "{kelvin} K");
    }
    for kelvin in [1005.0, 1500.0, 50_000.0, 99_000.0] {
        let xyz = xyz_at(1e6 / kelvin, 0.0);
        let got = PLANCKIAN_LOCUS.cct(xyz).unwrap();
        assert!(
            (f64::from(got.kelvin) / kelvin - 1.0).abs() < 1e-5,
            "{kelvin}: {got:?}"
        );
    }
    // Farther than 0.05 from the locus on either side, and just inside.
    for mired in [60.0, 150.0, 400.0, 900.0] {
        for duv in [-0.2, -0.0502, 0.0502, 0.1, 0.3] {
            assert_eq!(
                PLANCKIAN_LOCUS.cct(xyz_at(mired, duv)),
                None,
                "{mired} {duv}"
            );
        }
        for duv in [-0.0498, 0.0498] {
            let got = PLANCKIAN_LOCUS.cct(xyz_at(mired, duv)).unwrap();
            assert!((f64::from(got.duv) - duv).abs() < 1e-6, "{got:?}");
        }
    }
    // No chromaticity: NaN, infinities, all zero, a denominator X + 15Y + 3Z ≤ 0.
    let nan = f32::NAN;
    let inf = f32::INFINITY;
    for xyz in [
        [nan, 1.0, 1.0],
        [1.0, nan, 1.0],
        [1.0, 1.0, nan],
        [inf, 1.0, 1.0],
        [1.0, -inf, 1.0],
        [inf, inf, inf],
        [0.0, 0.0, 0.0],
        [-0.0, 0.0, -0.0],
        [-1.0, -1.0, -1.0],
        [-30.0, 1.0, 1.0],
        [1.0, -1.0, 1.0],
    ] {
        assert_eq!(uv_from_xyz(xyz), None, "{xyz:?}");
        assert_eq!(PLANCKIAN_LOCUS.cct(xyz), None, "{xyz:?}");
    }
    // Negative components are used as they are: a small negative Z (noise in a dark blue
    // channel) moves the chromaticity a little, a large one far from the locus.
    let xyz = xyz_at(900.0, 0.0);
    let small = [xyz[0], xyz[1], -1e-4];
    let (_, _, dmired, dduv) = errors(small);
    assert!(dmired <= f64::from(CCT_MAX_ERROR_MIRED) && dduv <= f64::from(DUV_MAX_ERROR));
    let xyz = xyz_at(150.0, 0.0);
    assert_eq!(PLANCKIAN_LOCUS.cct([xyz[0], xyz[1], -xyz[2]]), None);
    // Empty and one-node tables answer None.
    let empty = PlanckianLocus::<0> {
        mired: [],
        uv: [],
        tangent: [],
        chord: [],
        unit_tangent_q14: [],
        along_q30: [],
    };
    assert_eq!(empty.cct([1.0, 1.0, 1.0]), None);
    assert!(empty.kelvin_range()[0].is_nan());
    let one = PlanckianLocus::<1> {
        mired: [PLANCKIAN_LOCUS.mired[5]],
        uv: [PLANCKIAN_LOCUS.uv[5]],
        tangent: [PLANCKIAN_LOCUS.tangent[5]],
        chord: [[0.0; 2]],
        unit_tangent_q14: [PLANCKIAN_LOCUS.unit_tangent_q14[5]],
        along_q30: [PLANCKIAN_LOCUS.along_q30[5]],
    };
    assert_eq!(
        one.cct(xyz_at(f64::from(PLANCKIAN_LOCUS.mired[5]), 0.0)),
        None
    );
}

/// The scale of XYZ does not matter: from subnormals to f32::MAX, the same chromaticity gives
/// the same answer (the scaling by powers of two is exact).
#[test]
fn any_scale_gives_the_same_answer() {
    let base = xyz_at(200.0, 0.01);
    let reference = PLANCKIAN_LOCUS.cct(base).unwrap();
    for e in [-149, -140, -126, -100, -60, -20, 0, 20, 60, 100, 120, 126] {
        let s = 2f32.powi(e);
        let xyz = base.map(|c| c * s);
        if xyz.iter().any(|c| !c.is_normal()) {
            // Subnormal components have lost bits: the same chromaticity only roughly, if any.
            if let Some(got) = PLANCKIAN_LOCUS.cct(xyz) {
                assert!(
                    (got.kelvin / reference.kelvin - 1.0).abs() < 0.2,
                    "2^{e}: {got:?}"
                );
            }
            continue;
        }
        assert_eq!(PLANCKIAN_LOCUS.cct(xyz), Some(reference), "2^{e}");
    }
    // Near f32::MAX (the denominator X + 15Y + 3Z would overflow without the scaling).
    let m = f32::MAX / base[1].max(base[0]).max(base[2]);
    let huge = base.map(|c| c * m);
    let got = PLANCKIAN_LOCUS.cct(huge).unwrap();
    assert!(
        (got.kelvin / reference.kelvin - 1.0).abs() < 1e-6,
        "{got:?}"
    );
}

/// Random points of the domain (μ uniform over the table, Duv uniform in ±0.05): within the
/// bounds.
#[test]
fn random_points_within_the_stated_accuracy() {
    common::check_property(
        2_000,
        "cct",
        (
            TABLE_MIRED[0] + 0.01..TABLE_MIRED[1] - 0.1,
            -0.0499f64..0.0499,
        ),
        |(mired, duv)| {
            let xyz = xyz_at(mired, duv);
            let (_, _, dmired, dduv) = errors(xyz);
            prop_assert!(dmired <= f64::from(CCT_MAX_ERROR_MIRED), "Δμ {dmired:e}");
            prop_assert!(dduv <= f64::from(DUV_MAX_ERROR), "ΔDuv {dduv:e}");
            Ok(())
        },
    );
}

/// The whole (u, v) plane on a grid: wherever the exact CCT lies inside the table with
/// |Duv| ≤ 0.05 (away from those limits by more than the stated bounds), the runtime gives it
/// within the bounds; wherever it lies outside, `None`. One nearest point is all the binary
/// search can find: this shows there is only one to find.
#[test]
fn the_uv_plane() {
    let [t_lo, t_hi] = PLANCKIAN_LOCUS.kelvin_range().map(f64::from);
    let mut some = 0;
    for i in 0..=300 {
        for j in 0..=250 {
            let uv = [i as f64 * 0.002, j as f64 * 0.002];
            let uv32 = uv.map(|c| c as f32);
            let got = PLANCKIAN_LOCUS.cct_from_uv(uv32);
            let e = fixture().locus.cct_duv(uv32.map(f64::from));
            let inside = |e: &CctDuv, margin: f64| {
                e.kelvin > t_lo * (1.0 + margin)
                    && e.kelvin < t_hi * (1.0 - margin)
                    && e.duv.abs() < 0.05 - margin
            };
            match (e, got) {
                (Some(e), Some(g)) if inside(&e, -1e-5) => {
                    let dmired = (1e6 / f64::from(g.kelvin) - e.mired).abs();
                    let dduv = (f64::from(g.duv) - e.duv).abs();
                    assert!(
                        dmired <= f64::from(CCT_MAX_ERROR_MIRED)
                            && dduv <= f64::from(DUV_MAX_ERROR),
                        "{uv:?}: {g:?} vs {e:?}"
                    );
                    some += 1;
                }
                (Some(e), None) if !inside(&e, 1e-5) => {}
                (None, None) => {}
                (e, g) => panic!("{uv:?}: runtime {g:?}, exact {e:?}"),
            }
        }
    }
    assert!(some > 1000, "{some} grid points near the locus");
}

/// The locus and the lights integrated over the derivation's 380-770 nm (what the crate's exact
/// colours use) against 380-780 nm, as far as the CIE's tables of these lights go (CIE 015
/// integrates over 360-830 nm where the data reach): the CCTs move by less than 0.1 K (measured
/// 0.04 K) and Duv by less than 1e-5, far within the 1 K or 0.05 % a CCT is quoted to. Prints
/// the comparison of docs/colour-temperature-and-calibration.md.
#[test]
fn the_range_of_integration() {
    let f = fixture();
    let cct_over = |range: [f64; 2], light: &str| {
        let locus = planckian::PlanckianLocus::new(&f.d.observer, range).unwrap();
        let full = sqd::evaluate::full_integration(&f.d.observer, range, 1.0).unwrap();
        let l = sqd::evaluate::builtin_illuminant(std::path::Path::new(DATA_DIR), light, range)
            .unwrap();
        let uv = planckian::uv_from_xyz(full.xyz(|nm| l.at(nm))).unwrap();
        locus.cct_duv(uv).unwrap()
    };
    println!("| light | CCT, 380-770 nm | 380-780 nm | Duv, 380-770 nm | 380-780 nm |");
    println!("|---|---|---|---|---|");
    let (mut dt, mut dduv) = (0.0f64, 0.0f64);
    for light in ["A", "D50", "D65", "F2", "F11", "LED_B3", "LED_V1"] {
        let (a, b) = (
            cct_over([380.0, 770.0], light),
            cct_over([380.0, 780.0], light),
        );
        println!(
            "| {light} | {:.2} K | {:.2} K | {:.5} | {:.5} |",
            a.kelvin, b.kelvin, a.duv, b.duv
        );
        dt = dt.max((a.kelvin - b.kelvin).abs());
        dduv = dduv.max((a.duv - b.duv).abs());
    }
    println!("largest differences: {dt:.3} K, {dduv:.1e}");
    assert!(dt < 0.1 && dduv < 1e-5, "{dt} K, {dduv}");
}
