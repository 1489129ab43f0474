//! Light groups (one node set shared by D65, A, F11 and LED_B2, a weight matrix per light),
//! judged by five-fold cross-validation on the ColorChecker and the 190 rawtoaces patches, which
//! no fit in a fold sees: the targets the report's section 9 states at N = 8.

use spectral_quadrature_generator::shared::{
    nodes_of, problem_for, GroupFit, GroupObjective, Weights, TRAINING_FILE,
};
use spectral_quadrature_generator::{derive, Settings};
use spectral_quadrature_spectra::{builtin_illuminant, Spectra};
use spectral_quadrature_tools::light_groups::{self, GROUP_MEAN, OWN, RADIANCE};

const DATA_DIR: &str = spectral_quadrature_tools::DATA_DIR;

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

#[test]
fn a_group_of_four_lights_at_8_nodes_meets_its_targets_on_held_out_reflectances() {
    let d = derive(&Settings::new(DATA_DIR)).unwrap();
    let range = d.settings.range_nm;
    let dir = &d.settings.data_dir;
    let lights: Vec<_> = light_groups::LIGHTS
        .iter()
        .map(|n| builtin_illuminant(dir, n, range).unwrap())
        .collect();
    let training = Spectra::builtin(dir, TRAINING_FILE)
        .unwrap()
        .curves(range)
        .unwrap();
    let mut judged = Vec::new();
    for f in [
        "data/reflectance_colorchecker_ohta.csv",
        "data/reflectance_rawtoaces_190.csv",
    ] {
        judged.extend(Spectra::builtin(dir, f).unwrap().curves(range).unwrap());
    }
    let c = &light_groups::compare(&d, &lights, &training, &judged, &[8]).unwrap()[0];
    assert_eq!(c.judged, 214);
    let own = &c.method(OWN).unwrap().mean_de00;
    let group = &c.method(GROUP_MEAN).unwrap().mean_de00;
    let radiance = &c.method(RADIANCE).unwrap().mean_de00;
    // The targets (docs/light-groups.md): the group's mean within 15 % of the own sets' mean
    // (measured 1.024), no light above 1.5 times its own set (measured 1.26, F11), every light
    // below one radiance set fitted on the same lights (measured 0.26-0.39 against 0.63-1.11).
    let ratio = mean(group) / mean(own);
    assert!(ratio <= 1.15, "group/own mean {ratio}");
    for l in 0..4 {
        assert!(
            group[l] <= 1.5 * own[l],
            "{}: {} against {}",
            c.lights[l],
            group[l],
            own[l]
        );
        assert!(
            group[l] < radiance[l],
            "{}: {} against the radiance set's {}",
            c.lights[l],
            group[l],
            radiance[l]
        );
    }
}

#[test]
fn a_groups_weights_integrate_each_lights_white_exactly() {
    // A reflectance of 1 gives each light's white, as every folded set does: the weights are
    // fitted with the white pinned. Tolerance: f64 rounding of an 8×8 solve on values near 1e2
    // (the white's X, Y, Z scale), far below any colour difference.
    let d = derive(&Settings::new(DATA_DIR)).unwrap();
    let range = d.settings.range_nm;
    let dir = &d.settings.data_dir;
    let lights: Vec<_> = ["C", "F11"]
        .iter()
        .map(|n| builtin_illuminant(dir, n, range).unwrap())
        .collect();
    let problems: Vec<_> = lights
        .iter()
        .map(|l| problem_for(&d, Some(l)).unwrap())
        .collect();
    let training = Spectra::builtin(dir, TRAINING_FILE)
        .unwrap()
        .curves(range)
        .unwrap();
    let own: Vec<Vec<usize>> = problems
        .iter()
        .map(|p| nodes_of(p, &p.shared(6).unwrap()))
        .collect();
    let fit = GroupFit::new(problems.clone(), &training).unwrap();
    let reference = d.observer.full_integration(range, 1.0).unwrap();
    for kind in [Weights::PerLight, Weights::Radiance] {
        let g = fit.optimize(6, &own, GroupObjective::Mean, kind).unwrap();
        assert_eq!(g.wavelengths_nm.len(), 6);
        for (m, light) in g.members.iter().zip(&lights) {
            let set = spectral_quadrature_tools::evaluate::member_on_radiance(
                m,
                &g.wavelengths_nm,
                "g",
                "g",
            );
            let approx = set.xyz(|nm| light.at(nm));
            let exact = reference.xyz(|nm| light.at(nm));
            for c in 0..3 {
                assert!(
                    (approx[c] - exact[c]).abs() <= 1e-9 * exact[1],
                    "{kind:?} {}: {approx:?} against {exact:?}",
                    light.name
                );
            }
        }
    }
}
