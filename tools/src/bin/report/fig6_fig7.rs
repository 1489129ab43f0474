//! Sections 2 and 3: the paper's Figs. 6 and 7, every combination of per-channel Gauss rules
//! (`tools::evaluate`) in AC1C2, XYZ and SML, averaged by the total number of wavelengths (Fig.
//! 6) and by the fraction of them given to each channel (Fig. 7).

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;

use spectral_quadrature_spectra::{Errors, EvalSet, Stimulus};

use crate::tools::csv_table::Table;

/// Fig. 6: mean error against the total number of wavelengths (n_A + n_C1 + n_C2).
pub struct Fig6 {
    /// (space, total, number of combinations, mean ΔE*ab averaged over them)
    pub points: Vec<(String, usize, usize, f64)>,
}

/// Fig. 6 from every space's combinations and their errors.
pub fn fig6_data(spaces: &[(&str, Vec<EvalSet>)], errors: &[Vec<Errors>]) -> Fig6 {
    let mut points = Vec::new();
    for ((name, sets), errs) in spaces.iter().zip(errors) {
        let mut by_total: BTreeMap<usize, Vec<f64>> = Default::default();
        for (set, e) in sets.iter().zip(errs) {
            let o = set.orders.expect("combinations have orders");
            by_total
                .entry(o.iter().sum())
                .or_default()
                .push(e.mean_de76());
        }
        for (total, v) in by_total {
            points.push((
                name.to_string(),
                total,
                v.len(),
                v.iter().sum::<f64>() / v.len() as f64,
            ));
        }
    }
    Fig6 { points }
}

/// fig6.csv.
pub fn fig6_csv(f: &Fig6) -> Table {
    let mut t = Table::new("space,total_wavelengths,combinations,mean_de76");
    for (space, total, n, e) in &f.points {
        t.row([
            space.clone(),
            total.to_string(),
            n.to_string(),
            format!("{e:.4}"),
        ]);
    }
    t
}

// ---------------------------------------------------------------------------------------------
// Section 3: Fig. 7, the allocation triangle.

/// Subdivisions of each side of the triangle (K² sub-triangles).
pub const K: usize = 6;

pub struct Fig7 {
    /// Per sub-triangle: (row i, column j, upward, number of combinations, mean ΔE*ab).
    pub cells: Vec<(usize, usize, bool, usize, f64)>,
}

/// The sub-triangle of barycentric fractions (fa, fc1, fc2): i = ⌊fa·K⌋, j = ⌊fc1·K⌋, upward
/// when the remainders sum below 1.
fn cell_of(fa: f64, fc1: f64) -> (usize, usize, bool) {
    let (x, y) = (fa * K as f64, fc1 * K as f64);
    let i = (x.floor() as usize).min(K - 1);
    let j = (y.floor() as usize).min(K - 1 - i);
    let up = (x - i as f64) + (y - j as f64) < 1.0 || i + j == K - 1;
    (i, j, up)
}

/// The fractions (A, C1, C2) at the centroid of sub-triangle (i, j, up).
fn centroid(i: usize, j: usize, up: bool) -> [f64; 3] {
    let off = if up { 1.0 / 3.0 } else { 2.0 / 3.0 };
    let (fa, fc1) = ((i as f64 + off) / K as f64, (j as f64 + off) / K as f64);
    [fa, fc1, 1.0 - fa - fc1]
}

/// Fig. 7 from the AC1C2 combinations and their errors.
pub fn fig7_data(sets: &[EvalSet], errors: &[Errors]) -> Fig7 {
    let mut acc: BTreeMap<(usize, usize, bool), Vec<f64>> = Default::default();
    for (set, e) in sets.iter().zip(errors) {
        let o = set.orders.expect("combinations have orders");
        let t = (o[0] + o[1] + o[2]) as f64;
        acc.entry(cell_of(o[0] as f64 / t, o[1] as f64 / t))
            .or_default()
            .push(e.mean_de76());
    }
    Fig7 {
        cells: acc
            .into_iter()
            .map(|((i, j, up), v)| (i, j, up, v.len(), v.iter().sum::<f64>() / v.len() as f64))
            .collect(),
    }
}

/// fig7.csv.
pub fn fig7_csv(f: &Fig7) -> Table {
    let mut t = Table::new("a_fraction_from,c1_fraction_from,orientation,combinations,mean_de76");
    for (i, j, up, n, e) in &f.cells {
        t.row([
            format!("{:.3}", *i as f64 / K as f64),
            format!("{:.3}", *j as f64 / K as f64),
            (if *up { "up" } else { "down" }).to_string(),
            n.to_string(),
            format!("{e:.4}"),
        ]);
    }
    t
}

/// Section 2's text.
pub fn fig6_text(o: &mut String, fig_stimuli: &[Stimulus], fig6: &Fig6) {
    writeln!(
        o,
        "2. Fig. 6: mean ΔE*ab against the total number of wavelengths (n_A + n_C1 + n_C2),"
    )
    .ok();
    writeln!(
        o,
        "   averaged over every order combination with that total; {} stimuli ({} ... {})",
        fig_stimuli.len(),
        fig_stimuli[0].name,
        fig_stimuli[fig_stimuli.len() - 1].name
    )
    .ok();
    writeln!(
        o,
        "   {:>5} {:>9} {:>9} {:>9}",
        "total", "AC1C2", "XYZ", "SML"
    )
    .ok();
    let totals: BTreeSet<usize> = fig6.points.iter().map(|p| p.1).collect();
    for t in totals.iter().filter(|t| **t <= 24) {
        let cell = |space: &str| {
            fig6.points
                .iter()
                .find(|p| p.0 == space && p.1 == *t)
                .map_or("-".to_string(), |p| format!("{:.3}", p.3))
        };
        writeln!(
            o,
            "   {t:>5} {:>9} {:>9} {:>9}",
            cell("AC1C2"),
            cell("XYZ"),
            cell("SML")
        )
        .ok();
    }
    writeln!(o, "   (totals up to 24 shown; all in fig6.csv)\n").ok();
}

/// Section 3's text.
pub fn fig7_text(o: &mut String, fig7: &Fig7) {
    writeln!(o, "3. Fig. 7: mean ΔE*ab by the fraction of wavelengths given to A, C1, C2 ({K}x{K} sub-triangles)").ok();
    for (what, pred) in [
        (
            "mostly A   (A ≥ 2/3 of the wavelengths)",
            &(|f: [f64; 3]| f[0] >= 2.0 / 3.0) as &dyn Fn([f64; 3]) -> bool,
        ),
        ("mostly C1  (C1 ≥ 2/3)", &|f: [f64; 3]| f[1] >= 2.0 / 3.0),
        ("mostly C2  (C2 ≥ 2/3)", &|f: [f64; 3]| f[2] >= 2.0 / 3.0),
        ("balanced   (each ≥ 1/6)", &|f: [f64; 3]| {
            f.iter().all(|x| *x >= 1.0 / 6.0)
        }),
    ] {
        let v: Vec<f64> = fig7
            .cells
            .iter()
            .filter(|c| pred(centroid(c.0, c.1, c.2)))
            .map(|c| c.4)
            .collect();
        let mean = v.iter().sum::<f64>() / v.len().max(1) as f64;
        writeln!(
            o,
            "   {what}: {mean:.3} (mean of {} sub-triangles)",
            v.len()
        )
        .ok();
    }
    writeln!(o).ok();
}
