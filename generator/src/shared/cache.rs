//! The node cache: the nodes the search found for the sets the default and example scenes
//! bake, in a data file, each with a fingerprint of what the search read. A build takes the
//! nodes from it and computes only the weights, because the search is too slow for a build
//! script at Cargo's default opt-level 0 (README, "Build cost", measures both).

use std::string::String;
use std::vec::Vec;

use super::group::{
    bounce_forms, Group, GroupFit, GroupObjective, GroupTraining, Weights, GROUP_TRAINING_FILES,
};
use super::model::{
    problem, problem_for, Problem, Shared, EMPIRICAL_WEIGHT, LENGTH_NM, NUGGET, TRAINING_FILE,
};
use super::search::{optimize, MAX_MOVE, RANDOM_STARTS};
use crate::base::error::Error;
use crate::base::files::{cache_rows, read_data, read_optional_text, sha256_hex};
use crate::derivation::derive::Derivation;
use spectral_quadrature_spectra::{builtin_illuminant, builtin_lights, Curve, DataError, Spectra};

/// The shared sets' node cache, a file in the data directory: the nodes
/// `Problem::optimize` found for each set in [`CACHED`],
/// with a fingerprint of everything the search depends on.
/// `cargo run --release -p spectral-quadrature-tools --bin tables -- --shared-cache` writes it,
/// and a test re-runs every search and checks that it finds the same nodes (or worse ones).
pub(crate) const CACHE_FILE: &str = "data/shared_nodes.csv";

/// The sets whose nodes `CACHE_FILE` holds: radiances and the lights C, D65, A and F11, at 4, 6
/// and 8 wavelengths (the default scene's sets and the example scenes' among them).
pub(crate) const CACHED: [(Option<&str>, usize); 15] = [
    (None, 4),
    (None, 6),
    (None, 8),
    (Some("C"), 4),
    (Some("C"), 6),
    (Some("C"), 8),
    (Some("D65"), 4),
    (Some("D65"), 6),
    (Some("D65"), 8),
    (Some("A"), 4),
    (Some("A"), 6),
    (Some("A"), 8),
    (Some("F11"), 4),
    (Some("F11"), 6),
    (Some("F11"), 8),
];

/// The catalog name of a shared set: `KQ_<n>` or `KQ_<light>_<n>`.
pub(crate) fn set_name(light: Option<&str>, n: usize) -> String {
    match light {
        Some(l) => std::format!("KQ_{l}_{n}"),
        None => std::format!("KQ_{n}"),
    }
}

/// One line of `CACHE_FILE`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct CacheEntry {
    /// The set's name (`set_name`).
    pub name: String,
    /// `fingerprint` of the inputs the nodes were found with.
    pub fingerprint: String,
    /// The nodes in nm, ascending, on the 1 nm grid.
    pub wavelengths_nm: Vec<f64>,
    /// The line in the file.
    pub line: u64,
}

/// A SHA-256 over everything the node search for `light` depends on besides its code: the
/// observer table, the range, the training reflectances, the light's file, and the kernel and
/// search constants. A cached entry is used only while its fingerprint matches.
pub(crate) fn fingerprint(d: &Derivation, light: Option<&str>) -> Result<String, Error> {
    let read = |label: &str| read_data(&d.settings.data_dir, label);
    let mut text = std::format!(
        "observer {} {}\nrange {:?}\ntraining {}\nkernel matern52 {LENGTH_NM} empirical {EMPIRICAL_WEIGHT} nugget {NUGGET}\nsearch starts {RANDOM_STARTS} move {MAX_MOVE}\n",
        d.observer.file,
        d.observer.sha256,
        d.settings.range_nm,
        sha256_hex(&read(TRAINING_FILE)?),
    );
    if let Some(l) = light {
        let label = std::format!("data/illuminant_{l}.csv");
        text += &std::format!("light {l} {}\n", sha256_hex(&read(&label)?));
    }
    Ok(sha256_hex(text.as_bytes()))
}

/// A SHA-256 over what every node search reads besides its lights and a light group's training
/// reflectances: the observer table, the range, the kernel model's training reflectances, and
/// the kernel and search constants (the fingerprint of `data/shared_nodes.csv` for radiances).
/// For a node cache kept outside the generator (the report's, in the desk tools), which adds
/// its own inputs.
pub fn search_fingerprint(d: &Derivation) -> Result<String, Error> {
    fingerprint(d, None)
}

/// Reads [`CACHE_FILE`] from `data_dir`: no file is an empty cache; a malformed one is an error
/// naming the file and line.
pub(crate) fn read_cache(data_dir: &std::path::Path) -> Result<Vec<CacheEntry>, DataError> {
    match read_optional_text(data_dir, CACHE_FILE)? {
        Some(text) => parse_cache(CACHE_FILE, &text),
        None => Ok(Vec::new()),
    }
}

/// Parses the text of a node cache (see [`CACHE_FILE`]); `file` labels errors.
pub(crate) fn parse_cache(file: &str, text: &str) -> Result<Vec<CacheEntry>, DataError> {
    let err = |line: u64, message: String| DataError {
        file: file.into(),
        line,
        message,
    };
    let mut out: Vec<CacheEntry> = Vec::new();
    for (line, l) in cache_rows(file, text, "name,fingerprint,wavelengths_nm")? {
        let fields: Vec<&str> = l.split(',').collect();
        let [name, fingerprint, nodes] = fields[..] else {
            return Err(err(
                line,
                std::format!(
                    "expected 3 fields (name,fingerprint,wavelengths_nm), found {}",
                    fields.len()
                ),
            ));
        };
        let wavelengths_nm = nodes
            .split_whitespace()
            .map(|v| match v.parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(x),
                _ => Err(err(line, std::format!("{name}: {v:?} is not a wavelength"))),
            })
            .collect::<Result<Vec<f64>, _>>()?;
        if wavelengths_nm.is_empty() || wavelengths_nm.windows(2).any(|w| w[0] >= w[1]) {
            return Err(err(
                line,
                std::format!("{name}: the wavelengths must be strictly increasing"),
            ));
        }
        if out.iter().any(|e| e.name == name) {
            return Err(err(line, std::format!("{name} appears twice")));
        }
        out.push(CacheEntry {
            name: name.into(),
            fingerprint: fingerprint.into(),
            wavelengths_nm,
            line,
        });
    }
    Ok(out)
}

/// The text of `CACHE_FILE` for `entries`.
pub(crate) fn write_cache(entries: &[CacheEntry]) -> String {
    let rows: Vec<Vec<String>> = entries
        .iter()
        .map(|e| {
            let nodes: Vec<String> = e
                .wavelengths_nm
                .iter()
                .map(|v| std::format!("{v}"))
                .collect();
            std::vec![e.name.clone(), e.fingerprint.clone(), nodes.join(" ")]
        })
        .collect();
    crate::base::files::write_csv(
        &[
            "Generated by `cargo run --release -p spectral-quadrature-tools --bin tables -- --shared-cache > data/shared_nodes.csv`.",
            "The nodes (nm) the shared-set search found; the build reuses an entry while its fingerprint matches the inputs.",
        ],
        "name,fingerprint,wavelengths_nm",
        &rows,
    )
}

/// The shared set of `n` wavelengths for a built-in light (`None`: radiances): the nodes from
/// [`CACHE_FILE`] when it has the set with a matching [`fingerprint`] (only the weights are
/// computed then), otherwise [`optimize`]'s search.
pub(crate) fn cached_or_optimize(
    d: &Derivation,
    light: Option<&str>,
    n: usize,
) -> Result<Shared, Error> {
    let name = set_name(light, n);
    let cache = read_cache(&d.settings.data_dir)?;
    let Some(entry) = cache.iter().find(|e| e.name == name) else {
        return optimize(d, light, n);
    };
    if entry.fingerprint != fingerprint(d, light)? || entry.wavelengths_nm.len() != n {
        return optimize(d, light, n);
    }
    let p = problem(d, light)?;
    let nodes = entry
        .wavelengths_nm
        .iter()
        .map(|&nm| {
            p.grid_nm
                .iter()
                .position(|&g| (g - nm).abs() < 1e-9)
                .filter(|&i| p.allowed[i])
                .ok_or_else(|| {
                    Error::Data(DataError {
                        file: CACHE_FILE.into(),
                        line: entry.line,
                        message: std::format!("{name}: {nm} nm is not a usable grid wavelength"),
                    })
                })
        })
        .collect::<Result<Vec<usize>, Error>>()?;
    p.set_at(&nodes).ok_or_else(|| {
        Error::Numerical("the kriging system is singular".into()).at(CACHE_FILE, entry.line)
    })
}

/// The cache entry for one set, by a fresh search (`Problem::optimize`).
pub(crate) fn cache_entry(
    d: &Derivation,
    light: Option<&str>,
    n: usize,
) -> Result<CacheEntry, Error> {
    let s = optimize(d, light, n)?;
    Ok(CacheEntry {
        name: set_name(light, n),
        fingerprint: fingerprint(d, light)?,
        wavelengths_nm: s.wavelengths_nm,
        line: 0,
    })
}

/// The light groups whose nodes `CACHE_FILE` holds (by their lights, size and objective): the
/// default scene's (daylight, tungsten, a spiky fluorescent and a phosphor LED at 8
/// wavelengths) and `examples/scenes/window_and_lamp.toml`'s (daylight and tungsten at 8).
pub(crate) const CACHED_GROUPS: [(&[&str], usize, GroupObjective); 2] = [
    (&["D65", "A", "F11", "LED_B2"], 8, GroupObjective::Mean),
    (&["D65", "A"], 8, GroupObjective::Mean),
];

/// The cache name of a light group: `GROUP_<light>+<light>…_<n>_<objective>`.
pub(crate) fn group_cache_name(
    lights: &[Curve],
    n: usize,
    objective: GroupObjective,
    training: GroupTraining,
) -> String {
    let names: Vec<&str> = lights.iter().map(|l| l.name.as_str()).collect();
    let suffix = match training {
        GroupTraining::Reflectances => "",
        GroupTraining::Bounces => "_bounces",
    };
    std::format!("GROUP_{}_{n}_{}{suffix}", names.join("+"), objective.name())
}

/// A SHA-256 over everything a light group's node search depends on besides its code: what a
/// single light's search reads (observer, range, the kernel model's training and constants,
/// the search constants), the group's training files, and each light's values on the 1 nm grid
/// (a built-in illuminant and a scene's own light alike).
pub(crate) fn group_fingerprint(
    d: &Derivation,
    problems: &[Problem],
    objective: GroupObjective,
    training: GroupTraining,
) -> Result<String, Error> {
    let mut text = fingerprint(d, None)?;
    text += &std::format!("\ngroup objective {}\n", objective.name());
    if training != GroupTraining::Reflectances {
        text += &std::format!("group training {}\n", training.name());
    }
    for f in GROUP_TRAINING_FILES {
        text += &std::format!(
            "training {f} {}\n",
            sha256_hex(&read_data(&d.settings.data_dir, f)?)
        );
    }
    for p in problems {
        let values: Vec<String> = p.light.iter().map(|v| std::format!("{v:e}")).collect();
        text += &std::format!(
            "light {} {}\n",
            p.light_name.as_deref().unwrap_or(""),
            sha256_hex(values.join(" ").as_bytes())
        );
    }
    Ok(sha256_hex(text.as_bytes()))
}

/// The group's fit on the crate's training reflectances ([`GROUP_TRAINING_FILES`]), and each
/// light's problem.
pub(crate) fn group_fit(
    d: &Derivation,
    lights: &[Curve],
    training_kind: GroupTraining,
) -> Result<GroupFit, Error> {
    group_fit_with(d, lights, training_kind, true)
}

/// [`group_fit`], with each light's problem the light alone (`prior` false: no kernel matrix)
/// where only the weights at given nodes are wanted, as from the cache.
fn group_fit_with(
    d: &Derivation,
    lights: &[Curve],
    training_kind: GroupTraining,
    prior: bool,
) -> Result<GroupFit, Error> {
    let problems = lights
        .iter()
        .map(|l| {
            if prior {
                problem_for(d, Some(l))
            } else {
                Problem::light_only(d, l)
            }
        })
        .collect::<Result<Vec<_>, Error>>()?;
    let mut training = Vec::new();
    for f in GROUP_TRAINING_FILES {
        training.extend(Spectra::builtin(&d.settings.data_dir, f)?.curves(d.settings.range_nm)?);
    }
    if training_kind == GroupTraining::Bounces {
        training = bounce_forms(&training, d.settings.range_nm);
    }
    GroupFit::new(problems, &training)
}

/// Searches a light group's nodes: each light's own folded set (from the cache where it has
/// it), then [`GroupFit::optimize`].
pub(crate) fn optimize_group(
    d: &Derivation,
    fit: &GroupFit,
    lights: &[Curve],
    n: usize,
    objective: GroupObjective,
) -> Result<Group, Error> {
    let own = fit
        .problems()
        .iter()
        .zip(lights)
        .map(|(p, l)| {
            let set = if builtin_lights().contains(&l.name.as_str()) {
                cached_or_optimize(d, Some(&l.name), n)?
            } else {
                p.shared(n)?
            };
            Ok(super::group::nodes_of(p, &set))
        })
        .collect::<Result<Vec<_>, Error>>()?;
    fit.optimize(n, &own, objective, Weights::PerLight)
}

/// A light group of `n` wavelengths for `lights` (curves named as the scene names them): the
/// nodes from [`CACHE_FILE`] when it holds the group with a matching fingerprint (only the
/// weights are fitted then), otherwise the search.
pub(crate) fn cached_or_optimize_group(
    d: &Derivation,
    lights: &[Curve],
    n: usize,
    objective: GroupObjective,
    training: GroupTraining,
) -> Result<Group, Error> {
    // The weights at cached nodes need only the lights (the search needs each light's prior
    // too): at a build script's opt-level 0 the four priors of the default scene's group cost
    // about a quarter of a second.
    let fit = group_fit_with(d, lights, training, false)?;
    let name = group_cache_name(lights, n, objective, training);
    let cache = read_cache(&d.settings.data_dir)?;
    let search = || -> Result<Group, Error> {
        let fit = group_fit(d, lights, training)?;
        optimize_group(d, &fit, lights, n, objective).map(|g| Group { training, ..g })
    };
    let Some(entry) = cache.iter().find(|e| e.name == name) else {
        return search();
    };
    if entry.fingerprint != group_fingerprint(d, fit.problems(), objective, training)?
        || entry.wavelengths_nm.len() != n
    {
        return search();
    }
    let grid = &fit.problems()[0].grid_nm;
    let nodes = entry
        .wavelengths_nm
        .iter()
        .map(|&nm| {
            grid.iter()
                .position(|&g| (g - nm).abs() < 1e-9)
                .ok_or_else(|| {
                    Error::Data(DataError {
                        file: CACHE_FILE.into(),
                        line: entry.line,
                        message: std::format!("{name}: {nm} nm is not a grid wavelength"),
                    })
                })
        })
        .collect::<Result<Vec<usize>, Error>>()?;
    fit.group_at(&nodes, objective, Weights::PerLight)
        .map(|g| Group { training, ..g })
        .map_err(|e| e.at(CACHE_FILE, entry.line))
}

/// The cache entry for one light group of built-in lights, by a fresh search.
pub(crate) fn group_cache_entry(
    d: &Derivation,
    lights: &[&str],
    n: usize,
    objective: GroupObjective,
) -> Result<CacheEntry, Error> {
    let curves = lights
        .iter()
        .map(|l| builtin_illuminant(&d.settings.data_dir, l, d.settings.range_nm))
        .collect::<Result<Vec<_>, _>>()?;
    let training = GroupTraining::Reflectances;
    let fit = group_fit(d, &curves, training)?;
    let g = optimize_group(d, &fit, &curves, n, objective)?;
    Ok(CacheEntry {
        name: group_cache_name(&curves, n, objective, training),
        fingerprint: group_fingerprint(d, fit.problems(), objective, training)?,
        wavelengths_nm: g.wavelengths_nm,
        line: 0,
    })
}

/// The text of the node cache (`data/shared_nodes.csv`) with every set it holds (radiances and
/// the lights C, D65, A and F11, at 4, 6 and 8 wavelengths) and every light group of
/// `CACHED_GROUPS` searched afresh: what the build reuses instead of searching. `searching` is
/// told each set's name (`KQ_<n>`, `KQ_<light>_<n>`, `GROUP_<light>+…_<n>_<objective>`) before
/// its search, which takes seconds.
pub fn cache_file(d: &Derivation, mut searching: impl FnMut(&str)) -> Result<String, Error> {
    let mut entries = Vec::new();
    for &(light, n) in &CACHED {
        searching(&set_name(light, n));
        entries.push(cache_entry(d, light, n)?);
    }
    for &(lights, n, objective) in &CACHED_GROUPS {
        searching(&std::format!(
            "GROUP_{}_{n}_{}",
            lights.join("+"),
            objective.name()
        ));
        entries.push(group_cache_entry(d, lights, n, objective)?);
    }
    Ok(write_cache(&entries))
}
