//! Every method at each wavelength budget: the sets the report's budget section and the tests
//! compare, per light, at N = 3..=16 distinct wavelengths.
//!
//! | method | sets at N |
//! |---|---|
//! | `AC1C2 rules` | every combination of the paper's per-channel Gauss rules with N distinct wavelengths |
//! | `XYZ rules` | the same with x̄, ȳ, z̄ as the weight functions |
//! | `SML rules` | the same with the cone fundamentals |
//! | `uniform` | N bin centres, box-filter weights |
//! | `interp A` | method (a): A's Gauss nodes, C1 and C2 interpolatory on them |
//! | `KQ radiance` | method (b): kernel quadrature on radiances |
//! | `KQ folded` | method (b) with the light folded into the weights |
//!
//! and, as references with more wavelengths, `interval 10 nm` and `interval 20 nm`: reflectance
//! sampled every 10 or 20 nm with the light folded into the weights and linear interpolation
//! between samples, the way ASTM E308's weighting tables fold the illuminant (E308 itself uses
//! a Lagrange scheme with bandpass correction; these are the plain version).

use std::vec::Vec;

use spectral_quadrature_generator::{shared, Derivation};
use spectral_quadrature_spectra::{
    builtin_illuminant, surfaces_under_lights, Curve, Errors, EvalSet, Reference, Spectra, Stimulus,
};

use crate::evaluate::{channel_rules, combinations, errors_of_sets, shared_on_radiance};
use crate::Error;

/// The lights the crate judges its shared sets under.
pub const LIGHTS: [&str; 4] = ["C", "D65", "A", "F11"];

/// The budgets compared.
pub const BUDGETS: core::ops::RangeInclusive<usize> = 3..=16;

/// The reflectances the sets are judged on (never trained on).
pub const JUDGE_FILE: &str = "data/reflectance_colorchecker_ohta.csv";

/// The methods, in table order.
pub const METHODS: [&str; 7] = [
    "AC1C2 rules",
    "XYZ rules",
    "SML rules",
    "uniform",
    "interp A",
    "KQ radiance",
    "KQ folded",
];

/// A space of per-channel rules: method name, weight functions on the grid, matrix to XYZ.
type Space<'a> = (&'static str, &'a [[f64; 3]], [[f64; 3]; 3]);

/// One light's comparison: per budget, each method's best entry; then the interval references.
pub type Comparison = (Vec<(usize, Vec<Entry>)>, Vec<Entry>);

/// The best set of one method at one budget under one light.
#[derive(Debug, Clone)]
pub struct Entry {
    /// One of [`METHODS`], or `interval 10 nm` / `interval 20 nm`.
    pub method: &'static str,
    /// The set (its `len()` is the budget, except for the interval references).
    pub set: EvalSet,
    /// Its errors on the judged stimuli.
    pub errors: Errors,
}

/// The judged stimuli: the ColorChecker under `light`.
pub fn judge_stimuli(d: &Derivation, light: &str) -> Result<Vec<Stimulus>, Error> {
    let range = d.settings.range_nm;
    let cc = Spectra::builtin(&d.settings.data_dir, JUDGE_FILE).and_then(|s| s.curves(range))?;
    let l = builtin_illuminant(&d.settings.data_dir, light, range)?;
    Ok(surfaces_under_lights(&cc, &[l]))
}

/// Reflectance sampled every `step_nm` over the range with `light` folded in: weights
/// `Σ_j x̄ȳz̄(λ_j) L(λ_j) h_i(λ_j)` on the 1 nm table (h_i the hat function of node i), as a
/// set on radiances (divided by L at each node, which must be positive there).
pub fn interval_set(d: &Derivation, light: &Curve, step_nm: f64) -> Result<EvalSet, Error> {
    let range = d.settings.range_nm;
    let full = d.observer.full_integration(range, 1.0)?;
    let mut nodes = Vec::new();
    let mut nm = range[0];
    while nm <= range[1] + 1e-9 {
        nodes.push(nm);
        nm += step_nm;
    }
    let last = *nodes.last().ok_or_else(|| {
        spectral_quadrature_generator::Error::Settings(std::format!(
            "no interval nodes on the range {range:?} at {step_nm} nm"
        ))
    })?;
    let mut w: [Vec<f64>; 3] = Default::default();
    for row in w.iter_mut() {
        *row = std::vec![0.0; nodes.len()];
    }
    for (j, &l) in full.wavelengths_nm.iter().enumerate() {
        let e = light.at(l);
        // Beyond the last node (a range that is not a whole number of steps): hold it.
        let t = ((l.min(last) - range[0]) / step_nm).max(0.0);
        let i = (t.floor() as usize).min(nodes.len() - 1);
        let frac = t - i as f64;
        for (row, weights) in w.iter_mut().zip(&full.xyz_weights) {
            let v = weights[j] * e;
            row[i] += v * (1.0 - frac);
            if frac > 0.0 {
                row[i + 1] += v * frac;
            }
        }
    }
    for (i, &l) in nodes.iter().enumerate() {
        let e = light.at(l);
        if e <= 0.0 || !e.is_finite() {
            return Err(Error::NoPower {
                light: light.name.clone(),
                nm: l,
            });
        }
        for row in w.iter_mut() {
            row[i] /= e;
        }
    }
    Ok(EvalSet {
        name: std::format!("interval {step_nm} nm"),
        family: "interval".into(),
        orders: None,
        wavelengths_nm: nodes,
        xyz_weights: w,
    })
}

/// The shared sets at every budget for radiances (`light` `None`, named `KQ_<n>`, method
/// `KQ radiance`) or with a built-in light folded in (`KQ_<light>_<n>`, `KQ folded`), from
/// one `shared::problem`.
pub fn shared_sets(d: &Derivation, light: Option<&str>) -> Result<Vec<EvalSet>, Error> {
    let curve = match light {
        Some(l) => Some(builtin_illuminant(
            &d.settings.data_dir,
            l,
            d.settings.range_nm,
        )?),
        None => None,
    };
    shared_sets_for(d, curve.as_ref())
}

/// [`shared_sets`] for any light given as a curve (a user's light: `KQ_<curve name>_<n>`).
pub fn shared_sets_for(d: &Derivation, light: Option<&Curve>) -> Result<Vec<EvalSet>, Error> {
    shared_sets_sized(d, light, BUDGETS)
}

/// [`shared_sets_for`] at the given sizes only.
pub fn shared_sets_sized(
    d: &Derivation,
    light: Option<&Curve>,
    sizes: impl IntoIterator<Item = usize>,
) -> Result<Vec<EvalSet>, Error> {
    let problem = shared::problem_for(d, light)?;
    let sizes: Vec<usize> = sizes.into_iter().collect();
    // One fit per size, about half a second each: on every core.
    crate::par_map(&sizes, |&n| {
        let set = problem.shared(n)?;
        Ok(match light {
            Some(l) => shared_on_radiance(&set, &std::format!("KQ_{}_{n}", l.name), "KQ folded"),
            None => shared_on_radiance(&set, &std::format!("KQ_{n}"), "KQ radiance"),
        })
    })
    .into_iter()
    .collect()
}

/// Every combination of per-channel Gauss rules of orders up to `max_order`, in the three
/// spaces whose weight functions the paper compares (Fig. 6): AC1C2, XYZ and the cone
/// fundamentals SML, each as `(space, sets)`, the space also each set's family.
pub fn rule_spaces(
    d: &Derivation,
    max_order: usize,
) -> Result<[(&'static str, Vec<EvalSet>); 3], Error> {
    let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let sml_to_xyz = {
        let m = nalgebra::Matrix3::from_fn(|r, c| d.settings.cone_matrix[r][c]);
        let inv = m.try_inverse().ok_or_else(|| {
            spectral_quadrature_generator::Error::Numerical("the cone matrix is singular".into())
        })?;
        [0, 1, 2].map(|r| [0, 1, 2].map(|c| inv[(r, c)]))
    };
    let spaces: [Space; 3] = [
        ("AC1C2", &d.sensitivities, d.opponent.ac1c2_to_xyz),
        ("XYZ", &d.xyz, identity),
        ("SML", &d.cones, sml_to_xyz),
    ];
    Ok(spaces.map(|(space, w, to_xyz)| {
        let rules = channel_rules(d, w, max_order);
        (space, combinations(&rules, &to_xyz, space))
    }))
}

/// The sets of every method other than the shared ones, at every budget: the combinations of
/// [`rule_spaces`] (as `AC1C2 rules`, `XYZ rules`, `SML rules`), the uniform sets and
/// method (a). The comparison keeps each method's best.
pub fn other_sets(
    d: &Derivation,
    spaces: &[(&'static str, Vec<EvalSet>); 3],
) -> Vec<(&'static str, EvalSet)> {
    let mut out = Vec::new();
    for ((_, sets), method) in spaces.iter().zip(&METHODS[..3]) {
        for set in sets.iter().filter(|s| BUDGETS.contains(&s.len())) {
            out.push((*method, set.clone()));
        }
    }
    for n in BUDGETS {
        out.push(("uniform", d.observer.uniform_set(d.settings.range_nm, n)));
        if let Ok(s) =
            spectral_quadrature_generator::catalog::resolve(d, &std::format!("INTERP_A_{n}"))
        {
            out.push(("interp A", d.eval_set(&s, "interp A")));
        }
    }
    out
}

/// Each method's best set (lowest mean ΔE00) at each budget under `light`, judged on the
/// ColorChecker: `(n, entries in METHODS order)` for n in [`BUDGETS`], then the interval
/// references. `others` from [`other_sets`]; `radiance` and `folded` from [`shared_sets`]
/// (without a light, and with this one).
pub fn compare(
    d: &Derivation,
    light: &str,
    others: &[(&'static str, EvalSet)],
    radiance: &[EvalSet],
    folded: &[EvalSet],
) -> Result<Comparison, Error> {
    let stimuli = judge_stimuli(d, light)?;
    let l = builtin_illuminant(&d.settings.data_dir, light, d.settings.range_nm)?;
    compare_on(d, &l, &stimuli, others, radiance, folded)
}

/// [`compare`] for any light, judged on any `stimuli` (a user's reflectances under the user's
/// light, say): the interval references fold `light`.
pub fn compare_on(
    d: &Derivation,
    light: &Curve,
    stimuli: &[Stimulus],
    others: &[(&'static str, EvalSet)],
    radiance: &[EvalSet],
    folded: &[EvalSet],
) -> Result<Comparison, Error> {
    let stimuli = stimuli.to_vec();
    let full = d.observer.full_integration(d.settings.range_nm, 1.0)?;
    let reference = Reference::new(full, &stimuli);
    let mut best: Vec<(usize, Vec<Option<Entry>>)> = BUDGETS
        .map(|n| (n, std::vec![None; METHODS.len()]))
        .collect();
    let all: Vec<(&'static str, &EvalSet)> = others
        .iter()
        .map(|(m, s)| (*m, s))
        .chain(radiance.iter().map(|s| ("KQ radiance", s)))
        .chain(folded.iter().map(|s| ("KQ folded", s)))
        .filter(|(_, s)| BUDGETS.contains(&s.len()))
        .collect();
    // Every set's errors at once, on every core (`Reference::errors` for each, bit for bit).
    let sets: Vec<EvalSet> = all.iter().map(|(_, s)| (*s).clone()).collect();
    let measured = errors_of_sets(&reference, &stimuli, &sets, &|_| true, &|_| {});
    for ((method, set), errors) in all.into_iter().zip(measured) {
        let Some(slot) = best.iter_mut().find(|b| b.0 == set.len()) else {
            continue;
        };
        let k = METHODS
            .iter()
            .position(|m| *m == method)
            .ok_or_else(|| Error::UnknownMethod(method.into()))?;
        if slot.1[k]
            .as_ref()
            .is_none_or(|e| errors.mean_de00() < e.errors.mean_de00())
        {
            slot.1[k] = Some(Entry {
                method,
                set: set.clone(),
                errors,
            });
        }
    }
    let table = best
        .into_iter()
        .map(|(n, e)| (n, e.into_iter().flatten().collect()))
        .collect();
    let mut intervals = Vec::new();
    for (method, step) in [("interval 10 nm", 10.0), ("interval 20 nm", 20.0)] {
        // A light without power at a node cannot be divided out there: no reference then.
        let set = match interval_set(d, light, step) {
            Err(Error::NoPower { .. }) => continue,
            other => other?,
        };
        let errors = reference.errors(&set, &stimuli);
        intervals.push(Entry {
            method,
            set,
            errors,
        });
    }
    Ok((table, intervals))
}
