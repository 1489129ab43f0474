//! Section 4: error against run time, the crate's main job. Every set the crate offers and its
//! alternatives (the best per-channel Gauss combinations, Table 2's sets, uniform sets, the
//! shared sets for radiances, method (a), sampling every 10 and 20 nm, full integration),
//! judged on every stimulus and timed on the runtime's f32 path (`crate::timing`); with the
//! user's lights and scene, their sets too (`crate::user`).

use std::collections::BTreeMap;
use std::fmt::Write as _;

use spectral_quadrature_generator::Derivation;
use spectral_quadrature_spectra::{Curve, Errors, EvalSet, Reference, Stimulus};

use crate::progress::Meter;
use crate::timing::time_set;
use crate::tools::budget;
use crate::tools::csv_table::Table;
use crate::tools::evaluate;
use crate::user::Extra;
use crate::{table2, Error};

/// One row of section 4.
pub struct Row {
    pub set: EvalSet,
    /// Samples per pixel: the set's wavelengths, or a sensor's channels.
    pub samples: usize,
    pub errors: Errors,
    pub ns_per_pixel: f64,
    /// What the set is judged on, when not every stimulus (a set with a light folded in is
    /// judged under that light only).
    pub judged_on: Option<String>,
}

/// What section 4 measures on.
pub struct Inputs<'a> {
    /// The derivation.
    pub d: &'a Derivation,
    /// Every stimulus of the report.
    pub stimuli: &'a [Stimulus],
    /// Their reference (the 1 nm integration).
    pub reference: &'a Reference,
    /// The per-channel rule combinations (AC1C2, XYZ, SML).
    pub spaces: &'a [(&'static str, Vec<EvalSet>); 3],
    /// Their errors on these stimuli, where sections 2-3 have judged them on the same.
    pub space_errors: Option<&'a [Vec<Errors>]>,
    /// The shared sets for radiances.
    pub radiance: &'a [EvalSet],
    /// The user's sets: shared sets folded for their lights, and a scene's.
    pub extras: Vec<Extra>,
    /// Timing runs per set.
    pub runs: usize,
}

/// Section 4's rows: every set judged on the stimuli and timed, then the user's.
pub fn rows(x: Inputs) -> Result<Vec<Row>, Error> {
    let d = x.d;
    let range = d.settings.range_nm;
    let reference_set = &x.reference.set;
    let stimuli = x.stimuli;
    let spaces = x.spaces;
    // The rule combinations: every AC1C2 one, and each number of distinct wavelengths' best in
    // XYZ (up to 16), with their errors where sections 2-3 measured them on these stimuli.
    let xyz: Vec<usize> = (0..spaces[1].1.len())
        .filter(|&k| spaces[1].1[k].len() <= 16)
        .collect();
    let mut sets: Vec<EvalSet> = spaces[0].1.clone();
    sets.extend(xyz.iter().map(|&k| spaces[1].1[k].clone()));
    let mut known: Vec<Errors> = match x.space_errors {
        Some(e) => e[0]
            .iter()
            .cloned()
            .chain(xyz.iter().map(|&k| e[1][k].clone()))
            .collect(),
        None => Vec::new(),
    };
    let mut others = Vec::new();
    for set in &d.table2 {
        others.push(EvalSet {
            name: table2::name(&set.name),
            ..d.eval_set(set, "Table 2")
        });
    }
    for n in (3..=16).chain([24, 32]) {
        others.push(d.observer.uniform_set(range, n));
    }
    // The shared sets for radiances (the lights here are many; section 5 folds each one in),
    // method (a) for comparison, and sampling every 10 and 20 nm with linear interpolation.
    others.extend(x.radiance.iter().cloned());
    for n in budget::BUDGETS {
        if let Ok(a) = spectral_quadrature_generator::catalog::resolve(d, &format!("INTERP_A_{n}"))
        {
            others.push(d.eval_set(&a, "interp A"));
        }
    }
    let flat = Curve::constant("equal energy", 1.0, range);
    for step in [10.0, 20.0] {
        others.push(budget::interval_set(d, &flat, step)?);
    }
    others.push(d.observer.full_integration(range, 5.0)?);
    others.push(reference_set.clone());
    // The table's order: the AC1C2 combinations, Table 2's sets, the XYZ combinations, the rest.
    let table2_count = d.table2.len();
    let ac1c2 = spaces[0].1.len();
    let judging = Meter::new(
        "judging",
        others.len() + if known.is_empty() { sets.len() } else { 0 },
        "sets",
    );
    if known.is_empty() {
        known =
            evaluate::errors_of_sets(x.reference, stimuli, &sets, &|_| true, &judging.counter());
    }
    let rest =
        evaluate::errors_of_sets(x.reference, stimuli, &others, &|_| true, &judging.counter());
    let mut rest = rest.into_iter();
    let mut known = known.into_iter();
    let mut sets = sets.into_iter();
    let mut others = others.into_iter();
    let mut measured: Vec<(EvalSet, Errors)> = Vec::new();
    measured.extend(sets.by_ref().take(ac1c2).zip(known.by_ref()));
    measured.extend(others.by_ref().take(table2_count).zip(rest.by_ref()));
    measured.extend(sets.zip(known));
    measured.extend(others.zip(rest));
    let total = measured.len();
    let meter = Meter::new("timing", total, "sets");
    let mut rows = Vec::with_capacity(total);
    for (set, errors) in measured {
        let ns_per_pixel = time_set(&set, stimuli, x.runs)?;
        meter.add(1);
        rows.push(Row {
            samples: set.len(),
            set,
            errors,
            ns_per_pixel,
            judged_on: None,
        });
    }
    // The user's: shared sets folded for each light of --illuminants, and a scene's sets. A
    // set already measured (a scene naming a light of --illuminants, or a set of the
    // report's own) is measured once; a set judged on exactly the report's stimuli (the only
    // light's folded sets) is labelled as judged on all of them, as the report's own are.
    for extra in x.extras {
        if rows.iter().any(|r| r.set.name == extra.set.name) {
            continue;
        }
        let (own, judged_on) = match extra.judged_on {
            Some((s, what)) if !same_stimuli(&s, stimuli, range) => (s, Some(what)),
            _ => (stimuli.to_vec(), None),
        };
        let errors = Reference::new(reference_set.clone(), &own).errors(&extra.set, &own);
        let ns_per_pixel = time_set(&extra.timing, &own, x.runs)?;
        rows.push(Row {
            set: extra.set,
            samples: extra.samples,
            errors,
            ns_per_pixel,
            judged_on,
        });
    }
    Ok(rows)
}

/// error_vs_time.csv.
pub fn csv(rows: &[Row]) -> Table {
    let mut t = Table::new(
        "set,distinct_wavelengths,mean_de76,max_de76,mean_de00,max_de00,ns_per_pixel,judged_on",
    );
    for r in rows {
        t.row([
            r.set.name.clone(),
            r.samples.to_string(),
            format!("{:.4}", r.errors.mean_de76()),
            format!("{:.4}", r.errors.max_de76()),
            format!("{:.4}", r.errors.mean_de00()),
            format!("{:.4}", r.errors.max_de00()),
            format!("{:.2}", r.ns_per_pixel),
            r.judged_on.clone().unwrap_or_else(|| "all stimuli".into()),
        ]);
    }
    t
}

/// Section 4's text.
pub fn text(o: &mut String, rows: &[Row]) {
    writeln!(
        o,
        "4. Error against run time ({} sets; all in error_vs_time.csv)",
        rows.len()
    )
    .ok();
    writeln!(o, "   the best per-channel Gauss combination (AC1C2 and XYZ) at each number of distinct wavelengths, Table 2's").ok();
    writeln!(o, "   sets, uniform sets, shared sets for radiances (KQ_N; trained on the CIE test colour samples, which these").ok();
    writeln!(o, "   stimuli include by default: section 5 judges on the ColorChecker alone), method (a) INTERP_A_N, sampling").ok();
    writeln!(o, "   every 10 and 20 nm, full integration:").ok();
    writeln!(
        o,
        "   {:<22} {:>5} {:>9} {:>9} {:>9} {:>9} {:>9}",
        "set", "N", "mean76", "max76", "mean00", "max00", "ns/pixel"
    )
    .ok();
    let mut best: BTreeMap<(&str, usize), &Row> = Default::default();
    for r in rows
        .iter()
        .filter(|r| r.set.family == "AC1C2" || r.set.family == "XYZ")
    {
        let e = best.entry((&r.set.family, r.set.len())).or_insert(r);
        if r.errors.mean_de00() < e.errors.mean_de00() {
            *e = r;
        }
    }
    let shown = best.values().copied().filter(|r| r.set.len() <= 16).chain(
        rows.iter()
            .filter(|r| r.set.family != "AC1C2" && r.set.family != "XYZ"),
    );
    for r in shown.clone().filter(|r| r.judged_on.is_none()) {
        line(o, r);
    }
    let mut own: Vec<&Row> = shown.filter(|r| r.judged_on.is_some()).collect();
    own.sort_by_key(|r| r.judged_on.clone());
    let mut last: Option<&str> = None;
    for r in own {
        let on = r.judged_on.as_deref().unwrap_or_default();
        if last != Some(on) {
            writeln!(
                o,
                "   judged on {on} only (a light folded in, or a sensor fitted under it):"
            )
            .ok();
            last = Some(on);
        }
        line(o, r);
    }
    let full = rows.iter().find(|r| r.set.name == "full 1 nm");
    let row2 = rows.iter().find(|r| r.set.name == "table2 row2");
    if let (Some(f), Some(r)) = (full, row2) {
        writeln!(o, "   table 2 row 2 is {:.0}x faster than the full 1 nm integration (medians of this run)", f.ns_per_pixel / r.ns_per_pixel).ok();
    }
}

/// One row of section 4's text table.
fn line(o: &mut String, r: &Row) {
    writeln!(
        o,
        "   {:<22} {:>5} {:>9.3} {:>9.3} {:>9.3} {:>9.3} {:>9.1}",
        r.set.name,
        r.samples,
        r.errors.mean_de76(),
        r.errors.max_de76(),
        r.errors.mean_de00(),
        r.errors.max_de00(),
        r.ns_per_pixel
    )
    .ok();
}

/// Whether `a` and `b` are the same stimuli: the same names, and the same radiance at every nm
/// of `range`.
fn same_stimuli(a: &[Stimulus], b: &[Stimulus], range: [f64; 2]) -> bool {
    let (lo, hi) = (range[0].ceil() as i64, range[1].floor() as i64);
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            x.name == y.name && (lo..=hi).all(|nm| x.radiance(nm as f64) == y.radiance(nm as f64))
        })
}
