//! The planner: the set with the fewest distinct wavelengths whose CIEDE2000 error on given
//! spectra meets a budget, among every set the catalogue can build for all three channels
//! (Table 2's rows, every defined `AC1C2_<a>_<c1>_<c2>` up to the derivation's maximum order,
//! the `UNIFORM_<n>` sets; [`catalog`]) and the shared sets ([`shared_sets`]).
//!
//! ```
//! use spectral_quadrature_generator::{derive, plan, Settings};
//! use spectral_quadrature_spectra::{builtin_illuminant, surfaces_under_lights, Spectra};
//! # let data_dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../data");
//! // data_dir: a directory laid out like spectral-quadrature's data/
//! let d = derive(&Settings::new(data_dir)).unwrap();
//! let range = d.settings.range_nm;
//! let cc = Spectra::builtin(&d.settings.data_dir, "data/reflectance_colorchecker_ohta.csv")
//!     .and_then(|s| s.curves(range))
//!     .unwrap();
//! let c = builtin_illuminant(&d.settings.data_dir, "C", range).unwrap();
//! let stimuli = surfaces_under_lights(&cc[..4], &[c]);
//! let p = plan::plan(&d, &stimuli, &[], 1.0, plan::Metric::Mean).unwrap();
//! assert!(p.chosen.mean_de00 <= 1.0);
//! assert!(p.candidates.iter().any(|c| c.name == p.chosen.name));
//! ```
//!
//! Every candidate is measured as the report measures sets: against the full 1 nm integration
//! of the derivation's observer over its range, with CIELAB's white integrated by the same
//! rule as the stimulus ([`spectral_quadrature_spectra::Reference`]).

use std::string::String;
use std::vec::Vec;

use super::catalog;
use super::user::UserLight;
use crate::base::error::Error;
use crate::derivation::derive::Derivation;
use crate::shared;
use spectral_quadrature_spectra::{
    builtin_lights, emissions, surfaces_under_lights, EvalSet, Negatives, Reference, Spectra,
    Stimulus, ZeroedNegatives,
};

pub use crate::base::error::PlanError;
pub use crate::base::error::{fmt_de, Candidate, Metric};

/// The planner's answer.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The set with the fewest wavelengths that meets the budget (ties: lower error, then name).
    pub chosen: Candidate,
    /// The set with the lowest error among those with fewer wavelengths than the chosen one:
    /// it misses the budget, and shows by how much. `None` when no set has fewer wavelengths.
    pub runner_up_with_fewer: Option<Candidate>,
    /// Every set measured: the catalogue's (Table 2's rows, the `AC1C2_<a>_<c1>_<c2>` in
    /// ascending orders, the `UNIFORM_<n>`), then the extra ones given to [`plan`].
    pub candidates: Vec<Candidate>,
    /// The budget on ΔE00.
    pub budget: f64,
    /// Which statistic of ΔE00 the budget bounds.
    pub metric: Metric,
    /// How many stimuli the sets were measured on.
    pub stimuli: usize,
}

/// Checks that a budget is a finite number greater than 0.
pub(crate) fn check_budget(budget: f64) -> Result<(), PlanError> {
    if budget.is_finite() && budget > 0.0 {
        Ok(())
    } else {
        Err(PlanError::BadBudget(budget))
    }
}

/// Measures every set of `catalog::colour_set_names` on `stimuli`, in the catalogue's order,
/// against the full 1 nm integration of `d`'s observer over its range. The sets are built and
/// measured on every available core (scoped threads; no other dependency, so build scripts can
/// call it too).
///
/// Errors: no stimuli, a stimulus whose reference colour is not finite (a light that is zero
/// everywhere), a set the catalogue cannot build.
pub(crate) fn evaluate_all(d: &Derivation, stimuli: &[Stimulus]) -> Result<Vec<Candidate>, Error> {
    if stimuli.is_empty() {
        return Err(PlanError::NoStimuli.into());
    }
    let reference = Reference::new(
        d.observer.full_integration(d.settings.range_nm, 1.0)?,
        stimuli,
    );
    for (s, lab) in stimuli.iter().zip(&reference.labs) {
        if lab.iter().any(|v| !v.is_finite()) {
            return Err(PlanError::NoReference {
                stimulus: s.name.clone(),
                lab: *lab,
            }
            .into());
        }
    }
    let names = catalog::colour_set_names(d);
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .clamp(1, names.len().max(1));
    let chunk = names.len().div_ceil(threads).max(1);
    let reference = &reference;
    let parts: Vec<Result<Vec<Candidate>, Error>> = std::thread::scope(|scope| {
        let handles: Vec<_> = names
            .chunks(chunk)
            .map(|part| {
                scope.spawn(move || {
                    part.iter()
                        .map(|name| candidate(d, reference, stimuli, name))
                        .collect::<Result<Vec<_>, Error>>()
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| {
                h.join()
                    .unwrap_or(Err(Error::Panicked("a set evaluation thread")))
            })
            .collect()
    });
    let mut out = Vec::with_capacity(names.len());
    for part in parts {
        out.extend(part?);
    }
    Ok(out)
}

/// Measures sets built elsewhere (a scene's fixed-wavelength and sensor sets, shared sets) on
/// `stimuli` like `evaluate_all`: `(name, samples per pixel, set)`.
pub(crate) fn evaluate_sets(
    d: &Derivation,
    stimuli: &[Stimulus],
    sets: &[(String, usize, EvalSet)],
) -> Result<Vec<Candidate>, Error> {
    if stimuli.is_empty() {
        return Err(PlanError::NoStimuli.into());
    }
    let reference = Reference::new(
        d.observer.full_integration(d.settings.range_nm, 1.0)?,
        stimuli,
    );
    Ok(sets
        .iter()
        .map(|(name, n, set)| {
            let e = reference.errors(set, stimuli);
            Candidate {
                name: name.clone(),
                wavelengths: *n,
                mean_de00: e.mean_de00(),
                max_de00: e.max_de00(),
                mean_de76: e.mean_de76(),
                max_de76: e.max_de76(),
            }
        })
        .collect())
}

/// The shared sets the planner adds to the catalogue's: `KQ_<n>` for radiances, and, when every
/// stimulus is a surface under one light that is built in or among `lights` (by its name),
/// `KQ_<light>_<n>` with that light folded in; n in `SHARED_SIZES`. Measured on radiances.
pub fn shared_sets(
    d: &Derivation,
    stimuli: &[Stimulus],
    lights: &[UserLight],
) -> Result<Vec<(String, usize, EvalSet)>, Error> {
    let mut out = Vec::new();
    for n in SHARED_SIZES {
        let name = std::format!("KQ_{n}");
        let set = catalog::resolve_with(d, &name, lights)?;
        out.push((name, n, d.eval_set(&set, "KQ radiance")));
    }
    let Some(first) = stimuli.first() else {
        return Ok(out);
    };
    let one_light = stimuli
        .iter()
        .all(|s| s.reflectance.is_some() && s.light == first.light);
    let name = &first.light.name;
    let known = builtin_lights().contains(&name.as_str()) || lights.iter().any(|l| &l.name == name);
    if !(one_light && known) {
        return Ok(out);
    }
    for n in SHARED_SIZES {
        let set_name = std::format!("KQ_{name}_{n}");
        let set = catalog::resolve_with(d, &set_name, lights)?;
        let eval = shared::eval_on_radiance(d, &set, "KQ folded", Some(&first.light))?;
        out.push((set_name, n, eval));
    }
    Ok(out)
}

/// The shared-set sizes the planner tries: those the node cache holds for the built-in lights.
pub(crate) const SHARED_SIZES: [usize; 3] = [4, 6, 8];

/// Builds the set `name` and measures it.
fn candidate(
    d: &Derivation,
    reference: &Reference,
    stimuli: &[Stimulus],
    name: &str,
) -> Result<Candidate, Error> {
    let set = catalog::resolve(d, name)?;
    let eval = d.eval_set(&set, "catalog");
    let e = reference.errors(&eval, stimuli);
    Ok(Candidate {
        name: set.name,
        wavelengths: eval.len(),
        mean_de00: e.mean_de00(),
        max_de00: e.max_de00(),
        mean_de76: e.mean_de76(),
        max_de76: e.max_de76(),
    })
}

/// An error for ordering: NaN last.
fn key(c: &Candidate, metric: Metric) -> f64 {
    let e = c.error(metric);
    if e.is_nan() {
        f64::INFINITY
    } else {
        e
    }
}

/// The set with the fewest distinct wavelengths whose error meets `error <= budget`; ties go to
/// the lower error, then to the name. If none does, [`PlanError::Unreachable`] names the budget
/// and the best achievable error, by which set and with how many wavelengths.
pub fn choose(
    candidates: &[Candidate],
    budget: f64,
    metric: Metric,
) -> Result<&Candidate, PlanError> {
    check_budget(budget)?;
    if candidates.is_empty() {
        return Err(PlanError::NoCandidates);
    }
    let chosen = candidates
        .iter()
        .filter(|c| c.meets(budget, metric))
        .min_by(|a, b| {
            a.wavelengths
                .cmp(&b.wavelengths)
                .then(key(a, metric).total_cmp(&key(b, metric)))
                .then_with(|| a.name.cmp(&b.name))
        });
    match chosen {
        Some(c) => Ok(c),
        None => Err(PlanError::Unreachable {
            budget,
            metric,
            best: best(candidates.iter(), metric)
                .expect("candidates is not empty")
                .clone(),
            evaluated: candidates.len(),
        }),
    }
}

/// The candidate with the lowest error (ties: fewer wavelengths, then name).
pub(crate) fn best<'a>(
    candidates: impl IntoIterator<Item = &'a Candidate>,
    metric: Metric,
) -> Option<&'a Candidate> {
    candidates.into_iter().min_by(|a, b| {
        key(a, metric)
            .total_cmp(&key(b, metric))
            .then(a.wavelengths.cmp(&b.wavelengths))
            .then_with(|| a.name.cmp(&b.name))
    })
}

/// The best candidate at each number of wavelengths (the lowest error; ties: the name), by
/// ascending count.
pub fn best_per_count(candidates: &[Candidate], metric: Metric) -> Vec<&Candidate> {
    let mut counts: Vec<usize> = candidates.iter().map(|c| c.wavelengths).collect();
    counts.sort_unstable();
    counts.dedup();
    counts
        .into_iter()
        .filter_map(|n| best(candidates.iter().filter(|c| c.wavelengths == n), metric))
        .collect()
}

/// [`choose`] on measured candidates, with the best set with fewer wavelengths beside it.
/// `stimuli` is how many stimuli they were measured on (for the scene's comment).
pub(crate) fn plan_from(
    candidates: Vec<Candidate>,
    stimuli: usize,
    budget: f64,
    metric: Metric,
) -> Result<Plan, PlanError> {
    let chosen = choose(&candidates, budget, metric)?.clone();
    let runner_up = best(
        candidates
            .iter()
            .filter(|c| c.wavelengths < chosen.wavelengths),
        metric,
    )
    .cloned();
    Ok(Plan {
        chosen,
        runner_up_with_fewer: runner_up,
        candidates,
        budget,
        metric,
        stimuli,
    })
}

/// The set with the fewest distinct wavelengths whose ΔE00 (`metric`) on `stimuli` meets
/// `budget`, among every colour set the catalogue can build (see [`Plan::candidates`]) and the
/// `extra` ones (`(name, samples per pixel, set)`: [`shared_sets`], or a scene's own sets),
/// each measured against the full 1 nm integration of `d`'s observer over its range (on every
/// available core). The budget is checked first ("bad budget: ..." unless finite and greater
/// than 0).
///
/// Errors: a bad budget, no stimuli, a stimulus whose reference colour is not finite (a light
/// that is zero everywhere), a set the catalogue cannot build, and
/// [`PlanError::Unreachable`] when no set meets the budget.
pub fn plan(
    d: &Derivation,
    stimuli: &[Stimulus],
    extra: &[(String, usize, EvalSet)],
    budget: f64,
    metric: Metric,
) -> Result<Plan, Error> {
    check_budget(budget)?;
    let mut candidates = evaluate_all(d, stimuli)?;
    candidates.extend(evaluate_sets(d, stimuli, extra)?);
    Ok(plan_from(candidates, stimuli.len(), budget, metric)?)
}

/// The stimuli of spectra files, on `range_nm`: every reflectance under every illuminant, or
/// lights seen directly (`emission`). Give either `emission` or both of the others. Negative
/// values follow `negatives` ([`Negatives`]); those read as 0 come back beside the stimuli, one
/// [`ZeroedNegatives`] per file that has any, for the caller to report. Errors name the file and
/// line ([`DataError`](spectral_quadrature_spectra::DataError)).
pub fn stimuli_from_files(
    range_nm: [f64; 2],
    reflectances: Option<&std::path::Path>,
    illuminants: Option<&std::path::Path>,
    emission: Option<&std::path::Path>,
    negatives: Negatives,
) -> Result<(Vec<Stimulus>, Vec<ZeroedNegatives>), Error> {
    let mut zeroed = Vec::new();
    let mut read = |p: &std::path::Path| -> Result<_, Error> {
        let spectra = Spectra::read_with(p, negatives)?;
        zeroed.extend(spectra.zeroed().cloned());
        Ok(spectra.curves(range_nm)?)
    };
    let stimuli = match (reflectances, illuminants, emission) {
        (None, None, Some(e)) => emissions(&read(e)?),
        (Some(r), Some(i), None) => {
            let surfaces = read(r)?;
            surfaces_under_lights(&surfaces, &read(i)?)
        }
        _ => return Err(PlanError::NoSpectra.into()),
    };
    Ok((stimuli, zeroed))
}
