//! The shared sets' node cache (data/shared_nodes.csv) cannot drift from the search: every
//! entry is re-searched from scratch here, and its fingerprint must match the current inputs.

use spectral_quadrature_spectra::{builtin_illuminant, builtin_lights, Curve};
use std::path::Path;
use std::sync::OnceLock;

use crate::scene::{Scene, DEFAULT_SHARED_SETS};
use crate::shared::{self, CacheEntry, CACHED, CACHED_GROUPS};
use crate::{derive, Derivation, Settings};

/// The data files the derivation reads (the runtime crate's `data/`).
const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../data");

fn derivation() -> &'static Derivation {
    static D: OnceLock<Derivation> = OnceLock::new();
    D.get_or_init(|| derive(&Settings::new(DATA_DIR)).expect("default derivation"))
}

fn cache() -> Vec<CacheEntry> {
    shared::read_cache(Path::new(DATA_DIR)).expect("data/shared_nodes.csv parses")
}

/// The checked-in cache, read and written again (through the `csv` crate's writer, as
/// `tables --shared-cache` writes it), is the same bytes.
#[test]
fn the_cache_file_round_trips_through_the_writer() {
    let text = std::fs::read_to_string(Path::new(DATA_DIR).join("shared_nodes.csv")).unwrap();
    assert!(
        shared::write_cache(&cache()) == text,
        "data/shared_nodes.csv is not what the writer makes of it"
    );
}

#[test]
fn the_cache_holds_every_cached_set_with_current_fingerprints() {
    let d = derivation();
    let cache = cache();
    assert_eq!(
        cache.len(),
        CACHED.len() + CACHED_GROUPS.len(),
        "one entry per shared::CACHED and shared::CACHED_GROUPS"
    );
    for &(light, n) in &CACHED {
        let name = shared::set_name(light, n);
        let e = cache
            .iter()
            .find(|e| e.name == name)
            .unwrap_or_else(|| panic!("{name} is not in data/shared_nodes.csv"));
        assert_eq!(e.wavelengths_nm.len(), n, "{name}");
        assert_eq!(
            e.fingerprint,
            shared::fingerprint(d, light).unwrap(),
            "{name}: stale fingerprint; regenerate with `cargo run --release -p spectral-quadrature-tools --bin tables -- --shared-cache > data/shared_nodes.csv`"
        );
    }
}

#[test]
fn a_fresh_search_finds_the_cached_nodes_or_worse_ones() {
    let d = derivation();
    let cache = cache();
    for light in [None, Some("C"), Some("D65"), Some("A"), Some("F11")] {
        let p = shared::problem(d, light).unwrap();
        for &(_, n) in CACHED.iter().filter(|(l, _)| *l == light) {
            let name = shared::set_name(light, n);
            let e = cache.iter().find(|e| e.name == name).unwrap();
            let (fresh, fresh_error) = p.optimize(n);
            let fresh_nm: Vec<f64> = fresh.iter().map(|&i| p.grid_nm[i]).collect();
            if fresh_nm == e.wavelengths_nm {
                continue;
            }
            let cached: Vec<usize> = e
                .wavelengths_nm
                .iter()
                .map(|nm| p.grid_nm.iter().position(|g| g == nm).unwrap())
                .collect();
            // A different answer is acceptable only if the cached nodes are at least as good
            // (the search's own comparison: relative 1e-12).
            let cached_error = p.objective(&cached);
            assert!(
                cached_error <= fresh_error * (1.0 + 1e-12),
                "{name}: the search now finds {fresh_nm:?} (error {fresh_error}), better than the cached {:?} ({cached_error}); regenerate the cache",
                e.wavelengths_nm
            );
        }
    }
}

#[test]
fn cached_sets_equal_searched_sets() {
    // The weights come from the same solve whichever way the nodes were found.
    let d = derivation();
    for (light, n) in [(Some("C"), 6), (None, 4)] {
        let cached = shared::cached_or_optimize(d, light, n).unwrap();
        let p = shared::problem(d, light).unwrap();
        let nodes: Vec<usize> = cached
            .wavelengths_nm
            .iter()
            .map(|nm| p.grid_nm.iter().position(|g| g == nm).unwrap())
            .collect();
        assert_eq!(p.set_at(&nodes).unwrap(), cached);
    }
}

#[test]
fn the_default_and_example_scenes_name_only_cached_shared_sets() {
    // So that building them never searches (README: build cost).
    let cached: Vec<String> = CACHED
        .iter()
        .map(|&(l, n)| shared::set_name(l, n))
        .collect();
    let mut named: Vec<String> = DEFAULT_SHARED_SETS.iter().map(|s| s.to_string()).collect();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/scenes");
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let text = std::fs::read_to_string(&path).unwrap();
        let scene = Scene::parse(&path.display().to_string(), &text, Path::new(DATA_DIR)).unwrap();
        // A light the scene reads from a file has no cache entry: its sets are searched
        // (README: build cost), and only those may be.
        let own: Vec<String> = scene
            .user
            .lights
            .iter()
            .map(|l| format!("KQ_{}_", l.name))
            .collect();
        named.extend(
            scene
                .sets
                .into_iter()
                .map(|(s, _)| s)
                .filter(|s| !own.iter().any(|p| s.starts_with(p.as_str()))),
        );
    }
    for name in named.iter().filter(|n| n.starts_with("KQ_")) {
        assert!(cached.contains(name), "{name} is not cached");
    }
}

#[test]
fn the_example_scenes_light_groups_are_cached() {
    // So that building them never searches: every group of built-in lights in examples/scenes
    // is in shared::CACHED_GROUPS (a group with a scene's own light is searched at build time).
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/scenes");
    let mut groups = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let text = std::fs::read_to_string(&path).unwrap();
        let scene = Scene::parse(&path.display().to_string(), &text, Path::new(DATA_DIR)).unwrap();
        let builtin = builtin_lights();
        for g in scene
            .user
            .groups
            .iter()
            .filter(|g| g.lights.iter().all(|l| builtin.contains(&l.as_str())))
        {
            groups += 1;
            assert!(
                CACHED_GROUPS.iter().any(|&(lights, n, objective)| {
                    lights == g.lights.as_slice()
                        && n == g.wavelengths
                        && objective == g.objective
                        && g.training == shared::GroupTraining::Reflectances
                }),
                "{}: group {} is not in shared::CACHED_GROUPS",
                path.display(),
                g.name
            );
        }
    }
    assert!(groups >= 2, "{groups} groups in the example scenes");
}

#[test]
fn a_stale_or_foreign_entry_is_not_used() {
    // A changed input changes the fingerprint, so the build searches instead of trusting the
    // cache: here, another light's fingerprint differs from C's.
    let d = derivation();
    assert_ne!(
        shared::fingerprint(d, Some("C")).unwrap(),
        shared::fingerprint(d, Some("D65")).unwrap()
    );
    assert_ne!(
        shared::fingerprint(d, Some("C")).unwrap(),
        shared::fingerprint(d, None).unwrap()
    );
}

#[test]
fn a_malformed_cache_names_file_and_line() {
    let bad = [
        ("name,fp,nodes\n", 1, "expected the header"),
        (
            "# c\nname,fingerprint,wavelengths_nm\nKQ_4,ab,450 500\nKQ_6,ab\n",
            4,
            "expected 3 fields",
        ),
        (
            "name,fingerprint,wavelengths_nm\nKQ_4,ab,450 x 600 700\n",
            2,
            "is not a wavelength",
        ),
        (
            "name,fingerprint,wavelengths_nm\nKQ_4,ab,450 440 600 700\n",
            2,
            "strictly increasing",
        ),
        (
            "name,fingerprint,wavelengths_nm\nKQ_2,ab,450\nKQ_2,ab,460\n",
            3,
            "appears twice",
        ),
    ];
    for (text, line, message) in bad {
        let e = shared::parse_cache("data/shared_nodes.csv", text).unwrap_err();
        let shown = e.to_string();
        assert!(
            shown.starts_with(&format!("data/shared_nodes.csv:{line}: "))
                && shown.contains(message),
            "{shown}"
        );
    }
}

#[test]
fn the_cache_file_round_trips() {
    let text = std::fs::read_to_string(Path::new(DATA_DIR).join("shared_nodes.csv")).unwrap();
    let entries = shared::parse_cache("data/shared_nodes.csv", &text).unwrap();
    assert_eq!(shared::write_cache(&entries), text);
}

/// The built-in lights of a cached group, as curves named as a scene names them.
fn group_lights(d: &Derivation, lights: &[&str]) -> Vec<Curve> {
    lights
        .iter()
        .map(|l| builtin_illuminant(&d.settings.data_dir, l, d.settings.range_nm).unwrap())
        .collect()
}

/// Wavelengths on the 1 nm grid of a group's fit, as grid indices.
fn grid_indices(fit: &shared::GroupFit, wavelengths_nm: &[f64]) -> Vec<usize> {
    let grid = &fit.problems()[0].grid_nm;
    wavelengths_nm
        .iter()
        .map(|nm| grid.iter().position(|g| g == nm).unwrap())
        .collect()
}

#[test]
fn the_cache_holds_every_cached_group_and_a_fresh_search_finds_it_or_worse() {
    let d = derivation();
    let cache = cache();
    for &(lights, n, objective) in &CACHED_GROUPS {
        let curves = group_lights(d, lights);
        let fit = shared::group_fit(d, &curves, shared::GroupTraining::Reflectances).unwrap();
        let name =
            shared::group_cache_name(&curves, n, objective, shared::GroupTraining::Reflectances);
        let e = cache
            .iter()
            .find(|e| e.name == name)
            .unwrap_or_else(|| panic!("{name} is not in data/shared_nodes.csv"));
        assert_eq!(
            e.fingerprint,
            shared::group_fingerprint(
                d,
                fit.problems(),
                objective,
                shared::GroupTraining::Reflectances,
            )
            .unwrap(),
            "{name}: stale fingerprint; regenerate with `cargo run --release -p spectral-quadrature-tools --bin tables -- --shared-cache > data/shared_nodes.csv`"
        );
        let fresh = shared::optimize_group(d, &fit, &curves, n, objective).unwrap();
        if fresh.wavelengths_nm == e.wavelengths_nm {
            continue;
        }
        // A different answer is acceptable only if the cached nodes are at least as good on
        // the search's own objective (the mean of the lights' training errors here, each
        // light's own set fixed).
        let nodes: Vec<usize> = grid_indices(&fit, &e.wavelengths_nm);
        let cached = fit
            .group_at(&nodes, objective, shared::Weights::PerLight)
            .unwrap();
        let mean = |g: &shared::Group| {
            g.members.iter().map(|m| m.training_de00).sum::<f64>() / g.members.len() as f64
        };
        assert!(
            mean(&cached) <= mean(&fresh) * (1.0 + 1e-9),
            "{name}: the search now finds {:?}, better than the cached {:?}; regenerate the cache",
            fresh.wavelengths_nm,
            e.wavelengths_nm
        );
    }
}

#[test]
fn a_cached_group_equals_the_searched_group() {
    // The weights come from the same least squares whichever way the nodes were found.
    let d = derivation();
    let &(lights, n, objective) = &CACHED_GROUPS[0];
    let curves = group_lights(d, lights);
    let cached = shared::cached_or_optimize_group(
        d,
        &curves,
        n,
        objective,
        shared::GroupTraining::Reflectances,
    )
    .unwrap();
    let fit = shared::group_fit(d, &curves, shared::GroupTraining::Reflectances).unwrap();
    let nodes: Vec<usize> = grid_indices(&fit, &cached.wavelengths_nm);
    assert_eq!(
        fit.group_at(&nodes, objective, shared::Weights::PerLight)
            .unwrap(),
        cached
    );
}
