//! The planner's choice on made-up candidates: the fewest wavelengths that meet the budget,
//! ties to the lower error and then the name, a NaN error never meeting it, and the best set
//! with fewer wavelengths beside the choice.

use crate::plan::{self, Candidate, Metric, PlanError};
use spectral_quadrature_spectra::{builtin_illuminant, surfaces_under_lights, Spectra};

fn candidate(name: &str, n: usize, e: f64) -> Candidate {
    Candidate {
        name: name.into(),
        wavelengths: n,
        mean_de00: e,
        max_de00: 2.0 * e,
        mean_de76: e,
        max_de76: 2.0 * e,
    }
}

#[test]
fn ties_go_to_the_lower_error_then_the_name() {
    let c = candidate;
    let cands = [
        c("B", 4, 0.9),
        c("A", 4, 0.9),
        c("C", 4, 0.5),
        c("D", 3, 1.5),
        c("E", 3, f64::NAN),
        c("F", 5, 0.1),
    ];
    assert_eq!(plan::choose(&cands, 1.0, Metric::Mean).unwrap().name, "C");
    assert_eq!(plan::choose(&cands, 0.5, Metric::Mean).unwrap().name, "C");
    assert_eq!(plan::choose(&cands, 0.4, Metric::Mean).unwrap().name, "F");
    assert_eq!(plan::choose(&cands, 2.0, Metric::Mean).unwrap().name, "D");
    assert_eq!(plan::choose(&cands, 1.9, Metric::Max).unwrap().name, "C");
    let ties = [c("B", 4, 0.9), c("A", 4, 0.9)];
    assert_eq!(plan::choose(&ties, 1.0, Metric::Mean).unwrap().name, "A");
    let p = plan::plan_from(cands.to_vec(), 1, 1.0, Metric::Mean).unwrap();
    assert_eq!(p.runner_up_with_fewer.unwrap().name, "D");
    let names: Vec<&str> = p.candidates.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["B", "A", "C", "D", "E", "F"]);
    let p = plan::plan_from(cands.to_vec(), 1, 2.0, Metric::Mean).unwrap();
    assert_eq!(p.runner_up_with_fewer, None);
    assert!(matches!(
        plan::choose(&[], 1.0, Metric::Mean),
        Err(PlanError::NoCandidates)
    ));
    assert_eq!("MAX".parse::<Metric>(), Ok(Metric::Max));
    assert!("median".parse::<Metric>().is_err());
}

/// The planner measures every colour set of the catalogue, in its order, then the extra sets it
/// is given (here the shared sets), on a few ColorChecker patches under D65.
#[test]
fn every_catalogue_set_is_measured_once_in_order() {
    let data = concat!(env!("CARGO_MANIFEST_DIR"), "/../data");
    let d = crate::derive(&crate::Settings::new(data)).unwrap();
    let range = d.settings.range_nm;
    let patches = Spectra::builtin(
        std::path::Path::new(data),
        "data/reflectance_colorchecker_ohta.csv",
    )
    .and_then(|s| s.curves(range))
    .unwrap();
    let d65 = builtin_illuminant(std::path::Path::new(data), "D65", range).unwrap();
    let stimuli = surfaces_under_lights(&patches[..6], &[d65]);
    let extra = plan::shared_sets(&d, &stimuli, &[]).unwrap();
    let p = plan::plan(&d, &stimuli, &extra, f64::MAX, Metric::Max).unwrap();
    let names = crate::catalog::colour_set_names(&d);
    assert!(names.len() > 100, "{} sets", names.len());
    let expected: Vec<&str> = names
        .iter()
        .chain(extra.iter().map(|(name, _, _)| name))
        .map(String::as_str)
        .collect();
    let got: Vec<&str> = p.candidates.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(got, expected);
}
