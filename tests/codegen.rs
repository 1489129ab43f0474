//! The baked tables equal a fresh derivation: every f64 value rounded to f32 exactly as the code
//! generator does (`as f32`), so the comparisons are exact.

use spectral_quadrature_derive as sqd;

/// The data files the derivation reads (the runtime crate's `data/`).
const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data");

use spectral_quadrature::{tables, Channel, RuleStatus, WavelengthSet};
use sqd::{derive, Derivation, Settings};
use std::sync::OnceLock;

fn fresh() -> &'static Derivation {
    static D: OnceLock<Derivation> = OnceLock::new();
    D.get_or_init(|| derive(&Settings::new(DATA_DIR)).expect("default derivation"))
}

fn f32s(v: &[f64]) -> Vec<f32> {
    v.iter().map(|&x| x as f32).collect()
}

#[test]
fn header_constants() {
    let d = fresh();
    assert_eq!(tables::OBSERVER, d.settings.observer.name());
    assert_eq!(tables::SETTINGS, d.settings.describe());
    assert_eq!(tables::RANGE_NM, [380.0, 770.0]);
    assert_eq!(tables::STEP_NM, 5.0);
    assert_eq!(tables::MAX_ORDER, d.settings.max_order);
    assert_eq!(tables::INPUTS.len(), 1);
    assert_eq!(tables::INPUTS[0].0, d.settings.observer.file());
    assert_eq!(tables::INPUTS[0].1, d.observer.sha256);
}

#[test]
fn matrices_eigenvalues_grid_and_sensitivities() {
    let d = fresh();
    for r in 0..3 {
        assert_eq!(
            tables::XYZ_TO_AC1C2[r].to_vec(),
            f32s(&d.opponent.xyz_to_ac1c2[r])
        );
        assert_eq!(
            tables::AC1C2_TO_XYZ[r].to_vec(),
            f32s(&d.opponent.ac1c2_to_xyz[r])
        );
    }
    assert_eq!(tables::EIGENVALUES.to_vec(), f32s(&d.opponent.eigenvalues));
    assert_eq!(tables::GRID_NM.to_vec(), f32s(&d.grid_nm));
    assert_eq!(tables::SENSITIVITIES.len(), d.sensitivities.len());
    for (baked, s) in tables::SENSITIVITIES.iter().zip(&d.sensitivities) {
        assert_eq!(baked.to_vec(), f32s(s));
    }
}

#[test]
fn every_rule_and_its_status() {
    let d = fresh();
    let mut defined = 0;
    for (c, channel) in Channel::ALL.into_iter().enumerate() {
        assert_eq!(tables::RULES[c].len(), d.rules[c].len());
        for (baked, rule) in tables::RULES[c].iter().zip(&d.rules[c]) {
            assert_eq!(baked.channel, channel);
            assert_eq!(usize::from(baked.order), rule.order);
            assert_eq!(baked.status.as_str(), rule.status.as_str());
            if baked.status == RuleStatus::Defined {
                defined += 1;
                assert_eq!(baked.wavelengths_nm, f32s(&rule.nodes_nm).as_slice());
                assert_eq!(baked.weights, f32s(&rule.weights).as_slice());
            } else {
                assert!(baked.wavelengths_nm.is_empty() && baked.weights.is_empty());
            }
        }
    }
    assert!(defined >= 30, "{defined} defined rules");
}

fn assert_set<const N: usize>(baked: &WavelengthSet<N>, fresh: &sqd::WavelengthSet) {
    assert_eq!(baked.wavelengths_nm.to_vec(), f32s(&fresh.wavelengths_nm));
    for c in 0..3 {
        assert_eq!(baked.weights[c].to_vec(), f32s(&fresh.weights[c]));
    }
}

#[test]
fn table2_sets_and_rule_sets() {
    let d = fresh();
    assert_set(&tables::TABLE2_ROW1, &d.table2[0]);
    assert_set(&tables::TABLE2_ROW2, &d.table2[1]);
    // A few of the per-rule sets: the rule's own row, the other rows zero.
    for (set_nm, set_w, c, order) in [
        (
            tables::rules::A_3.wavelengths_nm.to_vec(),
            tables::rules::A_3.weights.map(|r| r.to_vec()),
            0,
            3,
        ),
        (
            tables::rules::C1_2.wavelengths_nm.to_vec(),
            tables::rules::C1_2.weights.map(|r| r.to_vec()),
            1,
            2,
        ),
        (
            tables::rules::C2_1.wavelengths_nm.to_vec(),
            tables::rules::C2_1.weights.map(|r| r.to_vec()),
            2,
            1,
        ),
        (
            tables::rules::A_16.wavelengths_nm.to_vec(),
            tables::rules::A_16.weights.map(|r| r.to_vec()),
            0,
            16,
        ),
    ] {
        let rule = &d.rules[c][order - 1];
        assert_eq!(set_nm, f32s(&rule.nodes_nm));
        for (k, row) in set_w.iter().enumerate() {
            if k == c {
                assert_eq!(*row, f32s(&rule.weights));
            } else {
                assert!(row.iter().all(|&w| w == 0.0));
            }
        }
    }
}

#[test]
fn generated_source_is_what_the_generator_writes_now() {
    // The whole file, byte for byte: nothing in it comes from anywhere but the derivation.
    let d = fresh();
    let inputs = vec![(
        d.settings.observer.file().to_string(),
        d.observer.sha256.clone(),
    )];
    let scene = sqd::scene::Scene::default_scene(std::path::Path::new(DATA_DIR))
        .resolve(d)
        .unwrap();
    let regenerated = sqd::codegen::tables_rs(d, &inputs, &scene).unwrap();
    let baked = include_str!(concat!(env!("OUT_DIR"), "/tables.rs"));
    assert_eq!(regenerated, baked);
    assert!(!baked.contains("NaN") && !baked.contains("inf"));
}

#[test]
fn embedded_data_matches_the_file_in_data() {
    // The checksum in the header is that of the file shipped in data/.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(tables::INPUTS[0].0);
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(sqd::sha256_hex(&bytes), tables::INPUTS[0].1);
}
