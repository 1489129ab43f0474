//! The report's node cache: the nodes its node searches find on its default inputs, in
//! `tools/data/report_nodes.csv` (compiled into the tools), each with a fingerprint of everything
//! the search reads.
//!
//! The report searches nodes in several sections: each shared set of sections 4, 5 and 10
//! (`Problem::shared`), each light's own folded set that sections 8, 9 and 10 compare a group
//! with and start its search from, and every light group of sections 8, 9 and 10, for each fold
//! of the cross-validations ([`GroupFit::optimize`]). On the default inputs those searches are
//! most of the report's run time, and they find the same nodes in every run. A [`NodeCache`]
//! takes the nodes from the file when the entry's fingerprint matches the search's inputs and
//! computes only the weights at them (`Problem::set_at`, [`GroupFit::group_at`]: what the search
//! returns for the nodes it finds, so the report's figures are the same either way); on any
//! mismatch (a user's reflectances or lights, a changed data file or search constant) it runs
//! the search as before. A search run once is kept for the rest of the run: section 10's
//! cross-validation at N = 8 is section 9's plain fit, fold by fold, and several sections
//! search the same lights' sets.
//!
//! `cargo run --release -p spectral-quadrature-tools --bin tables -- --report-cache >
//! tools/data/report_nodes.csv` writes the file ([`report_cache_file`]). A test runs the
//! report's default searches through the file and checks that each finds its entry, fingerprint
//! and all, and that every entry is used (seconds); another, ignored by `cargo test` (minutes of
//! CPU in a test build), runs every search afresh and compares with the file, which catches a
//! change to the search's code that no fingerprint sees. CI makes that comparison with the
//! release build's `tables --report-cache`.

use std::sync::{Mutex, OnceLock};

use sha2::{Digest, Sha256};
use spectral_quadrature_generator::shared::{
    problem_for, search_fingerprint, Group, GroupFit, GroupObjective, Problem, Shared, Weights,
};
use spectral_quadrature_generator::{Derivation, Error};
use spectral_quadrature_spectra::{Curve, DataError, Spectra};

/// The cache file, relative to the workspace's root.
pub const FILE: &str = "tools/data/report_nodes.csv";

/// The file's text, as this build of the tools was compiled with it.
const TEXT: &str = include_str!("../data/report_nodes.csv");

/// The file's header row.
const HEADER: &str = "name,fingerprint,wavelengths_nm";

/// One search's nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    /// What was searched: `KQ_<light>_<n>` (`KQ_<n>` for radiances) for a shared set,
    /// `<what>_<lights>_<n>_<objective>_<weights>` for a light group.
    pub name: String,
    /// The SHA-256 of everything the search read besides its code.
    pub fingerprint: String,
    /// The nodes in nm, ascending, on the 1 nm grid.
    pub wavelengths_nm: Vec<f64>,
}

/// Node searches with their results kept: those of a cache file, and those run since.
pub struct NodeCache {
    /// The file's entries.
    cached: Vec<Entry>,
    /// The searches this cache has run, in the order they finished.
    found: Mutex<Vec<Entry>>,
    /// The names of the file's entries used so far.
    used: Mutex<Vec<String>>,
}

impl NodeCache {
    /// The report's cache: [`FILE`]'s entries, then every search the process runs. Shared by
    /// every section of a run.
    pub fn report() -> Result<&'static NodeCache, Error> {
        static CACHE: OnceLock<NodeCache> = OnceLock::new();
        if let Some(c) = CACHE.get() {
            return Ok(c);
        }
        let cached = parse(FILE, TEXT).map_err(Error::Data)?;
        Ok(CACHE.get_or_init(|| NodeCache::with(cached)))
    }

    /// A cache without entries: every search runs once (what [`report_cache_file`] writes).
    pub fn empty() -> NodeCache {
        NodeCache::with(Vec::new())
    }

    /// A cache of the entries of a cache file's `text` (`file` names it in errors).
    pub fn from_text(file: &str, text: &str) -> Result<NodeCache, DataError> {
        Ok(NodeCache::with(parse(file, text)?))
    }

    /// The names of the entries of the file that have been used, in no particular order.
    pub fn used(&self) -> Vec<String> {
        self.used.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }

    /// How many searches this cache has run (each once).
    pub fn searches(&self) -> usize {
        self.found.lock().unwrap_or_else(|e| e.into_inner()).len()
    }

    fn with(cached: Vec<Entry>) -> NodeCache {
        NodeCache {
            cached,
            found: Mutex::new(Vec::new()),
            used: Mutex::new(Vec::new()),
        }
    }

    /// The nodes of an entry named `name` with `fingerprint`: from the file, or from a search
    /// run before by this cache.
    fn lookup(&self, name: &str, fingerprint: &str) -> Option<Vec<f64>> {
        let hit = |e: &Entry| e.name == name && e.fingerprint == fingerprint;
        if let Some(e) = self.cached.iter().find(|e| hit(e)) {
            let mut used = self.used.lock().unwrap_or_else(|e| e.into_inner());
            if !used.contains(&e.name) {
                used.push(e.name.clone());
            }
            return Some(e.wavelengths_nm.clone());
        }
        let found = self.found.lock().unwrap_or_else(|e| e.into_inner());
        found
            .iter()
            .find(|e| e.fingerprint == fingerprint)
            .map(|e| e.wavelengths_nm.clone())
    }

    fn record(&self, name: String, fingerprint: String, wavelengths_nm: Vec<f64>) {
        let mut found = self.found.lock().unwrap_or_else(|e| e.into_inner());
        if !found.iter().any(|e| e.fingerprint == fingerprint) {
            found.push(Entry {
                name,
                fingerprint,
                wavelengths_nm,
            });
        }
    }

    /// `problem.shared(n)`: the shared set of `n` wavelengths, its nodes from the cache where an
    /// entry's fingerprint matches (the weights computed at them), else searched.
    pub fn shared(&self, d: &Derivation, problem: &Problem, n: usize) -> Result<Shared, Error> {
        let name = match &problem.light_name {
            Some(l) => format!("KQ_{l}_{n}"),
            None => format!("KQ_{n}"),
        };
        let mut h = Hasher::new(d)?;
        h.text(&format!("shared set n {n}\n"));
        h.problem(problem);
        let fingerprint = h.finish();
        if let Some(nm) = self.lookup(&name, &fingerprint) {
            let nodes = grid_indices(&problem.grid_nm, &nm, &name)?;
            return problem.set_at(&nodes).ok_or_else(|| {
                Error::Numerical(format!(
                    "{name}: the kriging system is singular at the cached nodes"
                ))
            });
        }
        let set = problem.shared(n)?;
        self.record(name, fingerprint, set.wavelengths_nm.clone());
        Ok(set)
    }

    /// `GroupFit::new(problems, training)?.optimize(n, own, objective, kind)`: the light
    /// group's nodes from the cache where an entry named `name` has a matching fingerprint (the
    /// weights fitted at them), else searched.
    #[allow(clippy::too_many_arguments)]
    pub fn group(
        &self,
        d: &Derivation,
        name: &str,
        problems: Vec<Problem>,
        training: &[Curve],
        n: usize,
        own: &[Vec<usize>],
        objective: GroupObjective,
        kind: Weights,
    ) -> Result<Group, Error> {
        let mut h = Hasher::new(d)?;
        h.text(&format!(
            "light group n {n} objective {objective:?} weights {kind:?}\n"
        ));
        for p in &problems {
            h.problem(p);
        }
        h.text(&format!("training {}\n", training.len()));
        for c in training {
            h.values(&c.wavelengths);
            h.values(&c.values);
        }
        h.text(&format!("own {own:?}\n"));
        let fingerprint = h.finish();
        let grid = problems
            .first()
            .map(|p| p.grid_nm.clone())
            .unwrap_or_default();
        let fit = GroupFit::new(problems, training)?;
        if let Some(nm) = self.lookup(name, &fingerprint) {
            let nodes = grid_indices(&grid, &nm, name)?;
            return fit.group_at(&nodes, objective, kind);
        }
        let g = fit.optimize(n, own, objective, kind)?;
        self.record(name.to_string(), fingerprint, g.wavelengths_nm.clone());
        Ok(g)
    }

    /// The file's text with every search this cache has run, by name.
    pub fn text(&self) -> String {
        let mut found = self.found.lock().unwrap_or_else(|e| e.into_inner()).clone();
        found.sort_by(|a, b| a.name.cmp(&b.name));
        write(&found)
    }
}

/// Grid indices of `nm` on `grid` (every one must be a grid point).
fn grid_indices(grid: &[f64], nm: &[f64], name: &str) -> Result<Vec<usize>, Error> {
    nm.iter()
        .map(|&v| {
            grid.iter()
                .position(|&g| (g - v).abs() < 1e-9)
                .ok_or_else(|| {
                    Error::Numerical(format!("{name}: {v} nm of {FILE} is not a grid wavelength"))
                })
        })
        .collect()
}

/// A SHA-256 of a search's inputs: the generator's fingerprint of what every search reads
/// (observer, range, the kernel model's training, kernel and search constants), then the
/// search's own.
struct Hasher(Sha256);

impl Hasher {
    fn new(d: &Derivation) -> Result<Hasher, Error> {
        let mut h = Hasher(Sha256::new());
        h.text(&search_fingerprint(d)?);
        h.text("\n");
        Ok(h)
    }

    fn text(&mut self, t: &str) {
        self.0.update(t.as_bytes());
    }

    /// Exact: each value's bits.
    fn values(&mut self, v: &[f64]) {
        self.0.update((v.len() as u64).to_le_bytes());
        for x in v {
            self.0.update(x.to_bits().to_le_bytes());
        }
    }

    /// A light's problem: its grid and its light on it (the rest follows from the generator's
    /// fingerprint).
    fn problem(&mut self, p: &Problem) {
        self.text(&format!(
            "light {}\n",
            p.light_name.as_deref().unwrap_or("(radiances)")
        ));
        self.values(&p.grid_nm);
        self.values(&p.light);
    }

    fn finish(self) -> String {
        self.0
            .finalize()
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect()
    }
}

/// Parses a cache file's text; `file` names it in errors.
pub fn parse(file: &str, text: &str) -> Result<Vec<Entry>, DataError> {
    let err = |line: usize, message: String| DataError {
        file: file.into(),
        line: line as u64,
        message,
    };
    let mut out: Vec<Entry> = Vec::new();
    let mut header = false;
    for (i, l) in text.lines().enumerate() {
        let line = i + 1;
        if l.starts_with('#') || l.trim().is_empty() {
            continue;
        }
        if !header {
            if l != HEADER {
                return Err(err(line, format!("expected the header {HEADER}")));
            }
            header = true;
            continue;
        }
        let fields: Vec<&str> = l.split(',').collect();
        let [name, fingerprint, nodes] = fields[..] else {
            return Err(err(
                line,
                format!("expected 3 fields ({HEADER}), found {}", fields.len()),
            ));
        };
        let wavelengths_nm = nodes
            .split_whitespace()
            .map(|v| match v.parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(x),
                _ => Err(err(line, format!("{name}: {v:?} is not a wavelength"))),
            })
            .collect::<Result<Vec<f64>, _>>()?;
        if wavelengths_nm.is_empty() || wavelengths_nm.windows(2).any(|w| w[0] >= w[1]) {
            return Err(err(
                line,
                format!("{name}: the wavelengths must be strictly increasing"),
            ));
        }
        if out.iter().any(|e| e.name == name) {
            return Err(err(line, format!("{name} appears twice")));
        }
        out.push(Entry {
            name: name.into(),
            fingerprint: fingerprint.into(),
            wavelengths_nm,
        });
    }
    if !header {
        return Err(err(1, format!("no header ({HEADER})")));
    }
    Ok(out)
}

/// The text of a cache file with `entries`.
pub fn write(entries: &[Entry]) -> String {
    let mut t = String::from(
        "# Generated by `cargo run --release -p spectral-quadrature-tools --bin tables -- --report-cache > tools/data/report_nodes.csv`.\n\
         # The nodes (nm) the report's node searches find on its default inputs; the report reuses an entry while its fingerprint matches the search's inputs.\n",
    );
    t += HEADER;
    t.push('\n');
    for e in entries {
        let nodes: Vec<String> = e.wavelengths_nm.iter().map(|v| format!("{v}")).collect();
        t += &format!("{},{},{}\n", e.name, e.fingerprint, nodes.join(" "));
    }
    t
}

/// The text of [`FILE`]: every node search of the report's default run, searched afresh with
/// its default inputs ([`report_searches`] through [`NodeCache::empty`]). `searching` is told
/// what is being searched, for a progress line.
pub fn report_cache_file(d: &Derivation, searching: impl Fn(&str)) -> Result<String, Error> {
    let cache = NodeCache::empty();
    report_searches(d, &cache, searching)?;
    Ok(cache.text())
}

/// Every node search of the report's default run, through `cache`, with the report's default
/// inputs: sections 4 and 5's shared sets for radiances at every budget, section 5's folded for
/// each of its lights at every budget, section 8's light groups of each fold, section 9's
/// cross-validation, section 10's fixed sets and cross-validation (the judging left out).
pub fn report_searches(
    d: &Derivation,
    cache: &NodeCache,
    searching: impl Fn(&str),
) -> Result<(), Error> {
    let range = d.settings.range_nm;
    let dir = &d.settings.data_dir;
    searching("sections 4 and 5: the shared sets for radiances");
    let radiances = problem_for(d, None)?;
    let sizes: Vec<usize> = crate::budget::BUDGETS.collect();
    for r in crate::par_map(&sizes, |&n| cache.shared(d, &radiances, n)) {
        r?;
    }
    searching("section 5: the shared sets folded for each of its lights");
    for light in crate::budget::LIGHTS {
        let curve = spectral_quadrature_spectra::builtin_illuminant(dir, light, range)?;
        let problem = problem_for(d, Some(&curve))?;
        for r in crate::par_map(&sizes, |&n| cache.shared(d, &problem, n)) {
            r?;
        }
    }
    let training = Spectra::builtin(dir, spectral_quadrature_generator::shared::TRAINING_FILE)?
        .curves(range)?;
    let (judged, _) = crate::light_groups::judged_reflectances(d, None)?;
    let builtin = |names: &[&str]| crate::light_groups::builtin_lights(d, names);
    let group = builtin(&crate::light_groups::LIGHTS)?;
    searching("section 8: the light groups of each fold");
    crate::upsampling::groups::default_searches(d, cache)?;
    searching("section 9: the light groups of each fold");
    crate::light_groups::compare_with(
        d,
        cache,
        &group,
        &training,
        &judged,
        &crate::light_groups::SIZES,
        &|_| {},
    )?;
    searching("section 10: the fixed sets and groups");
    let lights = builtin(&crate::interreflection::LIGHTS)?;
    crate::interreflection::fixed_sets_with(
        d,
        cache,
        &lights,
        &crate::light_groups::LIGHTS,
        &training,
        &crate::light_groups::SIZES,
    )?;
    searching("section 10: the light groups of each fold");
    crate::interreflection::cross_validated_groups(
        d,
        cache,
        &group,
        &training,
        &judged,
        crate::interreflection::CV_SIZE,
    )?;
    Ok(())
}
