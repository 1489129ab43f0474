//! Light groups judged on reflectances no fit saw: five-fold cross-validation of a group of
//! lights against each light's own folded set and against one radiance set fitted on the same
//! lights (the report's light-group section, `docs/light-groups.md`).
//!
//! Each fold fits the group and the radiance set on the other four folds, and judges every
//! method on the fold's reflectances that none of the fits saw: a reflectance of the crate's
//! own training file (the CIE test colours, on which the folded sets' model is trained) is
//! trained on in every fold and judged in none.

use spectral_quadrature_generator::shared::{
    nodes_of, problem_for, GroupObjective, Problem, Shared, Weights,
};
use spectral_quadrature_generator::{Derivation, Error};
use spectral_quadrature_spectra::{surfaces_under_lights, Curve, EvalSet, Reference, Spectra};

use crate::node_cache::NodeCache;

/// The number of folds.
pub const FOLDS: usize = 5;

/// The lights of the crate's light group: daylight, tungsten, a spiky fluorescent and a
/// phosphor LED.
pub const LIGHTS: [&str; 4] = ["D65", "A", "F11", "LED_B2"];

/// The crate's built-in illuminants `names` (`data/illuminant_<name>.csv`) on the derivation's
/// range: what the report's light-group and interreflection sections, the node cache and the
/// tests judge groups under.
pub fn builtin_lights(d: &Derivation, names: &[&str]) -> Result<Vec<Curve>, Error> {
    names
        .iter()
        .map(|n| {
            spectral_quadrature_spectra::builtin_illuminant(
                &d.settings.data_dir,
                n,
                d.settings.range_nm,
            )
            .map_err(Error::from)
        })
        .collect()
}

/// The sizes the report's light-group section compares at (a quick run: 8 alone).
pub const SIZES: [usize; 3] = [4, 6, 8];

/// One method's cross-validated errors at one size.
#[derive(Debug, Clone, PartialEq)]
pub struct Method {
    /// `own folded set`, `light group (mean)`, ….
    pub name: String,
    /// Per light (in [`Comparison::lights`]' order): mean CIEDE2000 over the held-out
    /// reflectances of every fold.
    pub mean_de00: Vec<f64>,
    /// Per light: the 95th percentile of CIEDE2000 over the same.
    pub p95_de00: Vec<f64>,
    /// Per light: the standard deviation of CIEDE2000 over the same (n − 1 in the
    /// denominator), for the standard error of `mean_de00` when the reflectances are a sample.
    pub sd_de00: Vec<f64>,
    /// Per fold: the nodes, nm.
    pub nodes_nm: Vec<Vec<f64>>,
}

/// The methods at one size.
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    /// N.
    pub n: usize,
    /// The lights' names.
    pub lights: Vec<String>,
    /// How many reflectances were judged (each once, in its fold).
    pub judged: usize,
    /// Each light's own folded set, then the light groups (mean and worst objective), then one
    /// radiance set fitted on the lights.
    pub methods: Vec<Method>,
}

impl Comparison {
    /// The method called `name`.
    pub fn method(&self, name: &str) -> Option<&Method> {
        self.methods.iter().find(|m| m.name == name)
    }
}

/// The name of each light's own folded set in [`Comparison::methods`].
pub const OWN: &str = "own folded sets";
/// The name of the light group searched for the mean ratio.
pub const GROUP_MEAN: &str = "light group (mean)";
/// The name of the light group searched for the worst ratio.
pub const GROUP_WORST: &str = "light group (worst)";
/// The name of the radiance set fitted on the lights.
pub const RADIANCE: &str = "radiance set fitted on the lights";

/// Fold `f`'s training and test reflectances: `training` (trained on in every fold) with every
/// judged reflectance outside fold `f`, and the judged ones in it. The folds are a fixed
/// interleaving (reflectance k is in fold k mod 5), so that they are the same in every run and
/// mix the files.
pub fn fold(training: &[Curve], judged: &[Curve], f: usize) -> (Vec<Curve>, Vec<Curve>) {
    let mut train = training.to_vec();
    let mut test = Vec::new();
    for (k, c) in judged.iter().enumerate() {
        if k % FOLDS == f {
            test.push(c.clone());
        } else {
            train.push(c.clone());
        }
    }
    (train, test)
}

/// Per light: its kernel-model problem, its own folded set, and that set's nodes as grid
/// indices ([`own_sets`]).
pub type OwnSets = (Vec<Problem>, Vec<Shared>, Vec<Vec<usize>>);

/// Each light's kernel-model problem and own folded set of `n` wavelengths (searched, or its
/// nodes from the report's [`NodeCache`]), with its nodes as grid indices: what a group is
/// compared with and its search starts from.
pub fn own_sets(d: &Derivation, lights: &[Curve], n: usize) -> Result<OwnSets, Error> {
    own_sets_with(d, NodeCache::report()?, lights, n)
}

/// [`own_sets`], the searches through `cache`.
pub fn own_sets_with(
    d: &Derivation,
    cache: &NodeCache,
    lights: &[Curve],
    n: usize,
) -> Result<OwnSets, Error> {
    let problems = lights
        .iter()
        .map(|l| problem_for(d, Some(l)))
        .collect::<Result<Vec<_>, Error>>()?;
    let own: Vec<Shared> = crate::par_map(&problems, |p| cache.shared(d, p, n))
        .into_iter()
        .collect::<Result<_, Error>>()?;
    let nodes = problems
        .iter()
        .zip(&own)
        .map(|(p, s)| nodes_of(p, s))
        .collect();
    Ok((problems, own, nodes))
}

/// The reflectances the report's light-group and bounced-light sections judge, and where they
/// come from in words: the user's (`--reflectances`), or by default the ColorChecker and the
/// 190 rawtoaces patches, which no fit of the crate's sets trains on.
pub fn judged_reflectances(
    d: &Derivation,
    user: Option<(&[Curve], &str)>,
) -> Result<(Vec<Curve>, String), Error> {
    if let Some((r, from)) = user {
        return Ok((r.to_vec(), from.to_string()));
    }
    let mut v = Vec::new();
    for f in [
        "data/reflectance_colorchecker_ohta.csv",
        "data/reflectance_rawtoaces_190.csv",
    ] {
        v.extend(Spectra::builtin(&d.settings.data_dir, f)?.curves(d.settings.range_nm)?);
    }
    Ok((
        v,
        "the ColorChecker and the 190 rawtoaces patches".to_string(),
    ))
}

/// Cross-validates the light group of `lights` at each of `sizes` on `training` (trained on in
/// every fold, judged in none) and `judged` (split into folds). `done` is called with 1 as each
/// fold of each size is finished ([`FOLDS`] × `sizes.len()` in all), for a progress line.
///
/// The node searches go through the report's [`NodeCache`]: on the report's default inputs
/// their nodes come from its file.
pub fn compare(
    d: &Derivation,
    lights: &[Curve],
    training: &[Curve],
    judged: &[Curve],
    sizes: &[usize],
    done: &(dyn Fn(usize) + Sync),
) -> Result<Vec<Comparison>, Error> {
    compare_with(
        d,
        NodeCache::report()?,
        lights,
        training,
        judged,
        sizes,
        done,
    )
}

/// [`compare`], the node searches through `cache`.
pub fn compare_with(
    d: &Derivation,
    cache: &NodeCache,
    lights: &[Curve],
    training: &[Curve],
    judged: &[Curve],
    sizes: &[usize],
    done: &(dyn Fn(usize) + Sync),
) -> Result<Vec<Comparison>, Error> {
    let range = d.settings.range_nm;
    let full = d.observer.full_integration(range, 1.0)?;
    let light_names: Vec<&str> = lights.iter().map(|l| l.name.as_str()).collect();
    let light_names = light_names.join("+");
    let mut out = Vec::new();
    for &n in sizes {
        let (problems, own, own_nodes) = own_sets_with(d, cache, lights, n)?;
        let folds: Vec<usize> = (0..FOLDS).collect();
        // Per fold: (method, light) → the held-out reflectances' CIEDE2000, and the nodes.
        type FoldResult = Vec<(Vec<Vec<f64>>, Vec<f64>)>;
        let per_fold: Vec<Result<FoldResult, Error>> = crate::par_map(&folds, |&f| {
            let (train, test) = fold(training, judged, f);
            let mut methods: Vec<(Vec<Vec<f64>>, Vec<f64>)> = Vec::new();
            // Own folded sets.
            let own_sets: Vec<_> = own
                .iter()
                .map(|s| crate::evaluate::shared_on_radiance(s, "own", "own"))
                .collect();
            methods.push((
                judge(&full, lights, &test, &own_sets),
                own[0].wavelengths_nm.clone(),
            ));
            for (objective, kind) in [
                (GroupObjective::Mean, Weights::PerLight),
                (GroupObjective::Worst, Weights::PerLight),
                (GroupObjective::Mean, Weights::Radiance),
            ] {
                let g = cache.group(
                    d,
                    &group_name(&light_names, n, f, objective, kind, ""),
                    problems.clone(),
                    &train,
                    n,
                    &own_nodes,
                    objective,
                    kind,
                )?;
                let sets: Vec<_> = g
                    .members
                    .iter()
                    .map(|m| {
                        crate::evaluate::member_on_radiance(m, &g.wavelengths_nm, "group", "group")
                    })
                    .collect();
                methods.push((judge(&full, lights, &test, &sets), g.wavelengths_nm));
            }
            done(1);
            Ok(methods)
        });
        let per_fold = per_fold.into_iter().collect::<Result<Vec<_>, Error>>()?;
        let names = [OWN, GROUP_MEAN, GROUP_WORST, RADIANCE];
        let methods = names
            .iter()
            .enumerate()
            .map(|(m, name)| {
                let mut mean = Vec::new();
                let mut p95 = Vec::new();
                let mut sd = Vec::new();
                for l in 0..lights.len() {
                    let mut all: Vec<f64> = per_fold
                        .iter()
                        .flat_map(|f| f[m].0[l].iter().copied())
                        .collect();
                    let mu = all.iter().sum::<f64>() / all.len() as f64;
                    mean.push(mu);
                    sd.push(standard_deviation(&all));
                    all.sort_by(f64::total_cmp);
                    p95.push(percentile(&all, 0.95));
                }
                Method {
                    name: (*name).into(),
                    mean_de00: mean,
                    p95_de00: p95,
                    sd_de00: sd,
                    nodes_nm: per_fold.iter().map(|f| f[m].1.clone()).collect(),
                }
            })
            .collect();
        out.push(Comparison {
            n,
            lights: lights.iter().map(|l| l.name.clone()).collect(),
            judged: judged.len(),
            methods,
        });
    }
    Ok(out)
}

/// The node cache's name of a cross-validated group: `cv_<lights>_<n>_fold<f>_<objective>_<weights><suffix>`.
pub(crate) fn group_name(
    lights: &str,
    n: usize,
    f: usize,
    objective: GroupObjective,
    kind: Weights,
    suffix: &str,
) -> String {
    format!("cv_{lights}_{n}_fold{f}_{objective:?}_{kind:?}{suffix}")
}

/// Per light: the CIEDE2000 of each test reflectance under that light by `sets[l]`.
fn judge(full: &EvalSet, lights: &[Curve], test: &[Curve], sets: &[EvalSet]) -> Vec<Vec<f64>> {
    lights
        .iter()
        .zip(sets)
        .map(|(l, s)| {
            let stimuli = surfaces_under_lights(test, std::slice::from_ref(l));
            Reference::new(full.clone(), &stimuli)
                .errors(s, &stimuli)
                .de00
        })
        .collect()
}

/// The standard deviation of `values` with n − 1 in the denominator (NaN for fewer than two).
pub fn standard_deviation(values: &[f64]) -> f64 {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    (values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0)).sqrt()
}

/// The standard error of a mean over `n` values drawn without repeats from `population`, whose
/// standard deviation is `sd`: `sd / √n · √(1 − n / population)` (the finite-population
/// correction: zero when the sample is the whole population).
pub fn standard_error(sd: f64, n: usize, population: usize) -> f64 {
    let (n, big_n) = (n as f64, population as f64);
    sd / n.sqrt() * (1.0 - n / big_n).max(0.0).sqrt()
}

/// A seeded sample of `most` of `curves` without repeats, in their order (all of them when
/// there are no more): a partial Fisher-Yates shuffle of their indices on the random stream
/// `[seed, 0x5a3e]` ([`pixel_rng`](crate::random_wavelengths::pixel_rng)), the chosen indices
/// then sorted.
pub fn sample(curves: &[Curve], most: usize, seed: u64) -> Vec<Curve> {
    use rand::RngExt;
    if curves.len() <= most {
        return curves.to_vec();
    }
    let mut rng = crate::random_wavelengths::pixel_rng(seed, &[0x5a3e]);
    let mut index: Vec<usize> = (0..curves.len()).collect();
    for i in 0..most {
        let j = rng.random_range(i..index.len());
        index.swap(i, j);
    }
    let mut chosen = index[..most].to_vec();
    chosen.sort_unstable();
    chosen.into_iter().map(|k| curves[k].clone()).collect()
}

/// The `q` quantile of sorted values (nearest rank).
fn percentile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let k = ((q * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
    sorted[k - 1]
}
