//! The shared sets' model: the prior's parameters the crate's sets use are the leave-one-out
//! optimum on the training reflectances.

use crate::shared::{self, EMPIRICAL_WEIGHT, LENGTH_NM, TRAINING_FILE};
use crate::{derive, Settings};
use spectral_quadrature_spectra::Spectra;

/// The data files the derivation reads (the runtime crate's `data/`).
const DATA_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../data");

#[test]
fn the_hyperparameters_are_the_training_sets_leave_one_out_optimum() {
    let d = derive(&Settings::new(DATA_DIR)).unwrap();
    let tcs = Spectra::builtin(std::path::Path::new(DATA_DIR), TRAINING_FILE)
        .unwrap()
        .curves(d.settings.range_nm)
        .unwrap();
    let fit = shared::fit(
        &tcs,
        d.settings.range_nm,
        &shared::FIT_LENGTHS_NM,
        &shared::FIT_WEIGHTS,
    )
    .unwrap();
    assert_eq!(
        (fit.length_nm, fit.weight),
        (LENGTH_NM, EMPIRICAL_WEIGHT),
        "{fit:?}"
    );
    // The optimum is inside the grid, not on its edge.
    assert!(fit.length_nm > shared::FIT_LENGTHS_NM[0]);
    assert!(fit.length_nm < shared::FIT_LENGTHS_NM[shared::FIT_LENGTHS_NM.len() - 1]);
    assert!(fit.weight > 0.0 && fit.weight < shared::FIT_WEIGHTS[shared::FIT_WEIGHTS.len() - 1]);
}
