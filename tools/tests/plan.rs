//! The planner on small fixtures (6 ColorChecker patches under D65, see
//! `tests/fixtures/plan/README.md`): the chosen set meets the budget, measured again here
//! without the planner, and no set with fewer wavelengths does.

/// The data files the derivation reads (the runtime crate's `data/`).
const DATA_DIR: &str = spectral_quadrature_tools::DATA_DIR;

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use spectral_quadrature_generator::plan::{self, Candidate, Metric, PlanError};
use spectral_quadrature_generator::{catalog, Derivation, Settings};
use spectral_quadrature_spectra::{emissions, Curve, Negatives, Reference, Stimulus};
use spectral_quadrature_tools::scene_file;

const BUDGETS: [(Metric, f64); 5] = [
    (Metric::Mean, 2.0),
    (Metric::Mean, 1.0),
    (Metric::Mean, 0.5),
    (Metric::Max, 3.0),
    (Metric::Max, 1.0),
];

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/plan")
        .join(name)
}

struct Fixture {
    d: Derivation,
    stimuli: Vec<Stimulus>,
    candidates: Vec<Candidate>,
    /// The full 1 nm integration, built here rather than by the planner.
    reference: Reference,
}

/// Derived, read and measured once for all tests.
fn fixture_data() -> &'static Fixture {
    static F: OnceLock<Fixture> = OnceLock::new();
    F.get_or_init(|| {
        let d = spectral_quadrature_generator::derive(&Settings::new(DATA_DIR)).unwrap();
        let (stimuli, zeroed) = plan::stimuli_from_files(
            d.settings.range_nm,
            Some(&fixture("reflectances.csv")),
            Some(&fixture("illuminant.csv")),
            None,
            Negatives::Refuse,
        )
        .unwrap();
        assert_eq!(zeroed, []);
        assert_eq!(stimuli.len(), 6);
        // Every set the planner measures: a plan's candidates (for a budget any set meets).
        let candidates = plan::plan(&d, &stimuli, &[], f64::MAX, Metric::Max)
            .unwrap()
            .candidates;
        let reference = Reference::new(
            d.observer
                .full_integration(d.settings.range_nm, 1.0)
                .unwrap(),
            &stimuli,
        );
        Fixture {
            d,
            stimuli,
            candidates,
            reference,
        }
    })
}

/// A set built from its name and measured directly: (distinct wavelengths, mean ΔE00, max ΔE00).
fn measure(f: &Fixture, name: &str) -> (usize, f64, f64) {
    let set = catalog::resolve(&f.d, name).unwrap();
    let mut nm = set.wavelengths_nm.clone();
    nm.sort_by(f64::total_cmp);
    nm.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    assert_eq!(
        nm.len(),
        set.wavelengths_nm.len(),
        "{name}: repeated wavelengths"
    );
    assert_eq!(set.name, name);
    let eval = f.d.eval_set(&set, "test");
    let e = f.reference.errors(&eval, &f.stimuli);
    (nm.len(), e.mean_de00(), e.max_de00())
}

fn stat(mean: f64, max: f64, metric: Metric) -> f64 {
    match metric {
        Metric::Mean => mean,
        Metric::Max => max,
    }
}

/// Every set is measured: the catalogue's (that they are all of them, in order, is the
/// generator's unit test `tests::plan::`), each with finite errors.
#[test]
fn every_catalogue_set_is_measured() {
    let f = fixture_data();
    assert!(f.candidates.len() > 100, "{} sets", f.candidates.len());
    for c in &f.candidates {
        assert!(c.wavelengths > 0, "{}", c.name);
        for e in [c.mean_de00, c.max_de00, c.mean_de76, c.max_de76] {
            assert!(e.is_finite() && e >= 0.0, "{}: {e}", c.name);
        }
        assert!(c.mean_de00 <= c.max_de00 + 1e-12, "{}", c.name);
    }
}

#[test]
fn parallel_measurements_match_sequential_ones() {
    let f = fixture_data();
    for c in f.candidates.iter().step_by(7) {
        let (n, mean, max) = measure(f, &c.name);
        assert_eq!(n, c.wavelengths, "{}", c.name);
        assert!((mean - c.mean_de00).abs() < 1e-12, "{}", c.name);
        assert!((max - c.max_de00).abs() < 1e-12, "{}", c.name);
    }
}

#[test]
fn chosen_set_meets_the_budget_and_no_smaller_set_does() {
    let f = fixture_data();
    // Every set's count and errors, measured here without the planner.
    let measured: Vec<(String, usize, f64, f64)> = f
        .candidates
        .iter()
        .map(|c| {
            let (n, mean, max) = measure(f, &c.name);
            (c.name.clone(), n, mean, max)
        })
        .collect();
    for (metric, budget) in BUDGETS {
        let chosen = plan::choose(&f.candidates, budget, metric).unwrap();
        let (n, mean, max) = measure(f, &chosen.name);
        let e = stat(mean, max, metric);
        assert_eq!(n, chosen.wavelengths);
        assert!(
            e <= budget,
            "{metric} {budget}: {} measures {e}",
            chosen.name
        );
        for (name, n, mean, max) in &measured {
            if *n < chosen.wavelengths {
                let e = stat(*mean, *max, metric);
                assert!(
                    e > budget,
                    "{metric} {budget}: {name} has {n} < {} wavelengths and measures {e}",
                    chosen.wavelengths
                );
            } else if *n == chosen.wavelengths {
                // Among sets as small, the chosen one has the lowest error.
                assert!(stat(*mean, *max, metric) >= chosen.error(metric) - 1e-12);
            }
        }
        println!(
            "{metric} ΔE00 <= {budget}: {} ({} wavelengths) measures {e:.4}",
            chosen.name, chosen.wavelengths
        );
    }
}

#[test]
fn plan_names_the_best_set_with_fewer_wavelengths() {
    let f = fixture_data();
    for (metric, budget) in BUDGETS {
        let p = plan::plan(&f.d, &f.stimuli, &[], budget, metric).unwrap();
        assert_eq!(
            &p.chosen,
            plan::choose(&f.candidates, budget, metric).unwrap()
        );
        assert_eq!(p.candidates, f.candidates);
        assert_eq!((p.budget, p.metric, p.stimuli), (budget, metric, 6));
        let fewer: Vec<&Candidate> = f
            .candidates
            .iter()
            .filter(|c| c.wavelengths < p.chosen.wavelengths)
            .collect();
        match &p.runner_up_with_fewer {
            None => assert!(fewer.is_empty()),
            Some(r) => {
                assert!(r.wavelengths < p.chosen.wavelengths);
                assert!(r.error(metric) > budget, "{} meets the budget", r.name);
                let lowest = fewer
                    .iter()
                    .map(|c| c.error(metric))
                    .fold(f64::INFINITY, f64::min);
                assert_eq!(r.error(metric), lowest);
                let (_, mean, max) = measure(f, &r.name);
                assert!(stat(mean, max, metric) > budget);
                println!(
                    "{metric} ΔE00 <= {budget}: runner-up {} ({} wavelengths) measures {:.4}",
                    r.name,
                    r.wavelengths,
                    r.error(metric)
                );
            }
        }
    }
}

#[test]
fn plan_end_to_end_agrees_with_choose() {
    let f = fixture_data();
    let p = plan::plan(&f.d, &f.stimuli, &[], 1.0, Metric::Mean).unwrap();
    assert_eq!(
        &p.chosen,
        plan::choose(&f.candidates, 1.0, Metric::Mean).unwrap()
    );
}

#[test]
fn an_impossible_budget_states_the_best_achievable() {
    let f = fixture_data();
    for metric in [Metric::Mean, Metric::Max] {
        let e = plan::choose(&f.candidates, 1e-9, metric).unwrap_err();
        let lowest = f
            .candidates
            .iter()
            .map(|c| c.error(metric))
            .fold(f64::INFINITY, f64::min);
        match &e {
            PlanError::Unreachable {
                budget,
                metric: m,
                best,
                evaluated,
            } => {
                assert_eq!(
                    (*budget, *m, *evaluated),
                    (1e-9, metric, f.candidates.len())
                );
                assert_eq!(best.error(metric), lowest);
            }
            other => panic!("{other:?}"),
        }
        let PlanError::Unreachable { best, .. } = &e else {
            unreachable!()
        };
        let msg = e.to_string();
        println!("{msg}");
        assert!(
            msg.contains(&std::format!("no set meets {metric} ΔE00 <= 0.000000001")),
            "{msg}"
        );
        assert!(msg.contains(&plan::fmt_de(lowest)), "{msg}");
        assert!(msg.contains(&best.name), "{msg}");
        assert!(
            msg.contains(&std::format!("with {} wavelengths", best.wavelengths)),
            "{msg}"
        );
        // plan() reports the same.
        let e = plan::plan(&f.d, &f.stimuli, &[], 1e-9, metric).unwrap_err();
        assert!(
            matches!(
                &e,
                spectral_quadrature_generator::Error::Plan(PlanError::Unreachable { .. })
            ),
            "{e:?}"
        );
        assert_eq!(e.to_string(), msg);
    }
}

#[test]
fn bad_budgets_are_rejected() {
    let f = fixture_data();
    for b in [0.0, -0.0, -1.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert!(matches!(
            plan::choose(&f.candidates, b, Metric::Mean),
            Err(PlanError::BadBudget(_))
        ));
        let e = plan::plan(&f.d, &f.stimuli, &[], b, Metric::Max).unwrap_err();
        assert!(
            matches!(
                &e,
                spectral_quadrature_generator::Error::Plan(PlanError::BadBudget(_))
            ),
            "{e:?}"
        );
        assert!(e.to_string().starts_with("bad budget: "), "{e}");
    }
}

#[test]
fn the_scene_names_the_chosen_set() {
    let f = fixture_data();
    let p = plan::plan(&f.d, &f.stimuli, &[], 1.0, Metric::Mean).unwrap();
    let text = scene_file::scene_toml(
        &p,
        f.d.settings.observer.name(),
        &["SRGB", "DISPLAY_P3"],
        "fixtures\nsecond line of the note",
    );
    println!("{text}");
    let keys: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(
        keys,
        [
            "observer = \"cie1931_2deg\"".to_string(),
            std::format!("sets = [\"{}\"]", p.chosen.name),
            "displays = [\"SRGB\", \"DISPLAY_P3\"]".to_string(),
        ]
    );
    let comments: Vec<&str> = text.lines().filter(|l| l.starts_with('#')).collect();
    assert!(comments[0].contains("fixtures second line of the note"));
    assert!(comments
        .iter()
        .any(|l| l.contains("mean ΔE00 <= 1 on 6 stimuli")));
    if let Some(r) = &p.runner_up_with_fewer {
        assert!(comments.iter().any(|l| l.contains(&r.name)));
    }
    // The scene parser accepts it and bakes the chosen set.
    let scene = spectral_quadrature_generator::scene::Scene::parse(
        "planned.toml",
        &text,
        std::path::Path::new(DATA_DIR),
    )
    .unwrap();
    let resolved = scene.resolve(&f.d).unwrap();
    let names: Vec<&str> = resolved
        .colour_sets
        .iter()
        .map(|s| s.name.as_str())
        .collect();
    assert_eq!(names, [p.chosen.name.as_str()]);
    assert_eq!(scene_file::toml_string("a\"b\\c\n"), "\"a\\\"b\\\\c\\n\"");
}

#[test]
fn a_scene_plan_table_resolves_to_the_planners_choice() {
    let f = fixture_data();
    let scene_file = fixture("scene.toml"); // need not exist: paths are relative to it
    let text = "displays = [\"SRGB\"]\n\n[plan]\nmax_delta_e00 = 3.0\nmetric = \"max\"\nreflectances = \"reflectances.csv\"\nilluminants = \"illuminant.csv\"\n";
    let scene = spectral_quadrature_generator::scene::Scene::parse(
        &scene_file.to_string_lossy(),
        text,
        std::path::Path::new(DATA_DIR),
    )
    .unwrap();
    let resolved = scene.resolve(&f.d).unwrap();
    // The planner considers the shared sets beside the catalogue's: here KQ_4 (4 wavelengths)
    // meets the budget where the catalogue needs UNIFORM_7.
    let shared = plan::shared_sets(&f.d, &f.stimuli, &[]).unwrap();
    let chosen = &plan::plan(&f.d, &f.stimuli, &shared, 3.0, Metric::Max)
        .unwrap()
        .chosen;
    let catalogue_only = plan::choose(&f.candidates, 3.0, Metric::Max).unwrap();
    eprintln!(
        "chosen {} ({}); the catalogue alone: {} ({})",
        chosen.name, chosen.wavelengths, catalogue_only.name, catalogue_only.wavelengths
    );
    assert!(chosen.wavelengths <= catalogue_only.wavelengths);
    let names: Vec<&str> = resolved
        .colour_sets
        .iter()
        .map(|s| s.name.as_str())
        .collect();
    assert_eq!(names, [chosen.name.as_str()]);
    let sentence = resolved.planned.unwrap();
    assert!(sentence.contains(&chosen.name), "{sentence}");
}

#[test]
fn input_errors_name_the_file() {
    let f = fixture_data();
    let missing = fixture("no_such_file.csv");
    let e = plan::stimuli_from_files(
        f.d.settings.range_nm,
        Some(&missing),
        Some(&fixture("illuminant.csv")),
        None,
        Negatives::Refuse,
    )
    .unwrap_err();
    let (file, _) = e.location().expect("a missing file names it");
    assert!(file.contains("no_such_file.csv"), "{e}");
    let e = plan::stimuli_from_files(
        f.d.settings.range_nm,
        Some(&missing),
        None,
        None,
        Negatives::Refuse,
    )
    .unwrap_err();
    assert_eq!(
        e,
        spectral_quadrature_generator::Error::Plan(PlanError::NoSpectra)
    );
    assert!(e.to_string().contains("emission"), "{e}");
    let e = plan::plan(&f.d, &[], &[], 1.0, Metric::Mean).unwrap_err();
    assert_eq!(
        e,
        spectral_quadrature_generator::Error::Plan(PlanError::NoStimuli)
    );
    assert!(e.to_string().contains("no stimuli"), "{e}");
    // A light that is zero everywhere has no colour to compare with.
    let dark = Curve::constant("dark", 0.0, f.d.settings.range_nm);
    let e = plan::plan(&f.d, &emissions(&[dark]), &[], 1.0, Metric::Mean).unwrap_err();
    assert!(
        matches!(&e, spectral_quadrature_generator::Error::Plan(PlanError::NoReference { stimulus, .. }) if stimulus == "dark"),
        "{e:?}"
    );
    assert!(e.to_string().contains("\"dark\""), "{e}");
}

/// The `plan` program, as Cargo built it for these tests.
const PLAN: &str = env!("CARGO_BIN_EXE_plan");

/// Runs `plan --emission <file> --max-delta-e 5 --out -` plus `extra`: exit code and standard
/// error.
fn plan_on(file: &Path, extra: &[&str]) -> (Option<i32>, String) {
    let out = std::process::Command::new(PLAN)
        .arg("--emission")
        .arg(file)
        .args(["--max-delta-e", "5", "--out", "-"])
        .args(extra)
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn the_planner_reads_noise_as_zero_refuses_negatives_and_clamps_on_request() {
    let path = std::env::temp_dir().join(format!("sq-plan-negatives-{}.csv", std::process::id()));
    let file = |value: &str| {
        let mut text = String::from("wavelength_nm,led\n");
        for nm in (380..=780).step_by(20) {
            let v = if nm == 420 {
                value.to_string()
            } else {
                format!("{}", 1.0 + f64::from(nm - 380) / 400.0)
            };
            text.push_str(&format!("{nm},{v}\n"));
        }
        std::fs::write(&path, text).unwrap();
        path.display().to_string()
    };
    // 420 nm is the file's fourth line.
    let label = file("-4e-17");
    let (code, err) = plan_on(&path, &[]);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        err.contains(&format!("plan: warning: {label}:4: column 2 (led): 1 negative value read as 0, the first here (-4e-17)")),
        "{err}"
    );
    let label = file("-0.3");
    let (code, err) = plan_on(&path, &[]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains(&format!(
            "plan: error: {label}:4: column 2 (led): -0.3 is negative"
        )),
        "{err}"
    );
    assert!(err.contains("--clamp-negatives"), "{err}");
    let (code, err) = plan_on(&path, &["--clamp-negatives"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(err.contains("1 value beyond the tolerance"), "{err}");
    assert!(err.contains("clamped as asked"), "{err}");
    std::fs::remove_file(&path).ok();
}
