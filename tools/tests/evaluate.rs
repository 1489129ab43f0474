//! Many sets judged at once (`evaluate::Sampled`, sections 2-4 of the report) against the
//! spectra crate's `Reference::errors`, set by set: the same errors, bit for bit.

use proptest::prelude::*;
use spectral_quadrature_generator::{derive, Settings};
use spectral_quadrature_spectra::{
    builtin_illuminant, emissions, surfaces_under_lights, Curve, Errors, EvalSet, Reference,
    Spectra, Stimulus,
};
use spectral_quadrature_tools::{budget, evaluate};

const DATA_DIR: &str = spectral_quadrature_tools::DATA_DIR;
const RANGE: [f64; 2] = [380.0, 770.0];

/// The errors' bits: equal errors are equal bits (NaN included).
fn bits(e: &Errors) -> (Vec<u64>, Vec<u64>) {
    (
        e.de76.iter().map(|v| v.to_bits()).collect(),
        e.de00.iter().map(|v| v.to_bits()).collect(),
    )
}

fn assert_same(reference: &Reference, stimuli: &[Stimulus], sets: &[EvalSet]) {
    let sampled = evaluate::Sampled::new(reference, stimuli);
    for set in sets {
        assert_eq!(
            bits(&sampled.errors(set)),
            bits(&reference.errors(set, stimuli)),
            "{}",
            set.name
        );
    }
    let all = evaluate::errors_of_sets(reference, stimuli, sets, &|_| true, &|_| {});
    for (set, e) in sets.iter().zip(&all) {
        assert_eq!(
            bits(e),
            bits(&reference.errors(set, stimuli)),
            "{}",
            set.name
        );
    }
    // ΔE*ab alone for every other set: the same ΔE*ab, no CIEDE2000.
    let odd = evaluate::errors_of_sets(reference, stimuli, sets, &|k| k % 2 == 0, &|_| {});
    for (k, (set, e)) in sets.iter().zip(&odd).enumerate() {
        let exact = bits(&reference.errors(set, stimuli)).0;
        assert_eq!(bits(e).0, exact, "{}", set.name);
        assert_eq!(e.de00.is_empty(), k % 2 == 1, "{}", set.name);
        let de76: Vec<u64> = sampled.de76(set).iter().map(|v| v.to_bits()).collect();
        assert_eq!(de76, exact, "{}", set.name);
    }
}

#[test]
fn the_reports_sets_on_surfaces_and_on_lights_seen_directly() {
    let d = derive(&Settings::new(DATA_DIR)).unwrap();
    let data = std::path::Path::new(DATA_DIR);
    let cc = Spectra::builtin(data, "data/reflectance_colorchecker_ohta.csv")
        .unwrap()
        .curves(RANGE)
        .unwrap();
    let lights: Vec<Curve> = ["C", "F11", "LED_B2"]
        .iter()
        .map(|n| builtin_illuminant(data, n, RANGE).unwrap())
        .collect();
    let mut sets: Vec<EvalSet> = budget::rule_spaces(&d, 4)
        .unwrap()
        .into_iter()
        .flat_map(|(_, s)| s)
        .collect();
    sets.extend([3, 8, 32].map(|n| d.observer.uniform_set(RANGE, n)));
    sets.push(d.observer.full_integration(RANGE, 5.0).unwrap());
    let full = d.observer.full_integration(RANGE, 1.0).unwrap();
    sets.push(full.clone());
    for stimuli in [surfaces_under_lights(&cc, &lights), emissions(&lights)] {
        let reference = Reference::new(full.clone(), &stimuli);
        assert_same(&reference, &stimuli, &sets);
    }
}

/// A curve named `name` with `values` spread over 370-780 nm.
fn curve(name: &str, values: &[f64]) -> Curve {
    let step = 410.0 / (values.len() - 1) as f64;
    Curve {
        name: name.into(),
        wavelengths: (0..values.len()).map(|k| 370.0 + k as f64 * step).collect(),
        values: values.to_vec(),
    }
}

proptest! {
    /// Any sets (nodes anywhere, repeated or not, weights of any sign) on any surfaces under
    /// any lights (two surfaces sharing a name) and on the lights seen directly.
    #[test]
    fn any_sets_on_any_stimuli(
        lights in prop::collection::vec(prop::collection::vec(0.01f64..2.0, 2..12), 1..4),
        surfaces in prop::collection::vec(prop::collection::vec(0.0f64..1.0, 2..12), 1..6),
        sets in prop::collection::vec(
            prop::collection::vec((375.0f64..775.0, -1.0f64..2.0, -1.0f64..2.0, -1.0f64..2.0), 1..10),
            1..6,
        ),
    ) {
        let lights: Vec<Curve> = lights.iter().enumerate().map(|(k, v)| curve(&format!("L{k}"), v)).collect();
        // Every other surface has the name of the one before it: curves of one name that differ.
        let surfaces: Vec<Curve> = surfaces.iter().enumerate().map(|(k, v)| curve(&format!("S{}", k / 2), v)).collect();
        let set = |name: &str, nodes: &[(f64, f64, f64, f64)]| EvalSet {
            name: name.into(),
            family: "test".into(),
            orders: None,
            wavelengths_nm: nodes.iter().map(|n| n.0).collect(),
            xyz_weights: [
                nodes.iter().map(|n| n.1).collect(),
                nodes.iter().map(|n| n.2).collect(),
                nodes.iter().map(|n| n.3).collect(),
            ],
        };
        let sets: Vec<EvalSet> = sets.iter().enumerate().map(|(k, n)| set(&format!("set {k}"), n)).collect();
        let reference_set = set("reference", &[(450.0, 0.3, 0.1, 1.5), (550.0, 0.5, 1.0, 0.1), (600.0, 1.0, 0.6, 0.0)]);
        for stimuli in [surfaces_under_lights(&surfaces, &lights), emissions(&lights)] {
            let reference = Reference::new(reference_set.clone(), &stimuli);
            let sampled = evaluate::Sampled::new(&reference, &stimuli);
            for s in &sets {
                prop_assert_eq!(bits(&sampled.errors(s)), bits(&reference.errors(s, &stimuli)));
            }
        }
    }
}
