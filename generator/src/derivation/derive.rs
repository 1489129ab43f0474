//! The derivation, step by step as the paper takes it: the observer's x̄ȳz̄ on the grid, the cone
//! fundamentals (Eq. 1), the covariance (Eq. 4-5) and the KL transform (Eq. 9-10), each channel's
//! recurrence (Eq. 16) and Gauss rules, Table 2's merged sets, and the standard displays'
//! matrices.

use std::vec::Vec;

use spectral_quadrature_spectra::EvalSet;

use super::display::{self, DisplayMatrices, DisplaySpec};
use super::observer::Observer;
use super::opponent::{self, Opponent};
use super::quadrature::{self, Measure, Recurrence, Rule};
use super::sets::WavelengthSet;
use super::settings::Settings;
use crate::base::error::Error;

/// Everything the derivation produces.
#[derive(Debug, Clone, PartialEq)]
pub struct Derivation {
    /// The settings it was run with.
    pub settings: Settings,
    /// The observer table at its native 1 nm.
    pub observer: Observer,
    /// Grid wavelengths in nm.
    pub grid_nm: Vec<f64>,
    /// x̄, ȳ, z̄ on the grid.
    pub xyz: Vec<[f64; 3]>,
    /// s̄, m̄, l̄ on the grid (Eq. 1).
    pub cones: Vec<[f64; 3]>,
    /// The covariance matrix of Eq. 4.
    pub covariance: [[f64; 3]; 3],
    /// The KL transform (Eq. 9, 10).
    pub opponent: Opponent,
    /// ā, c̄1, c̄2 on the grid.
    pub sensitivities: Vec<[f64; 3]>,
    /// The measure of each channel's weight function.
    pub measures: [Measure; 3],
    /// The recurrence of each channel.
    pub recurrences: [Recurrence; 3],
    /// `rules[c][n - 1]`: channel c's rule of order n, for n = 1..=max_order.
    pub rules: [Vec<Rule>; 3],
    /// Table 2's two sets: row 1 (A 3, C1 2, C2 1) and row 2 (A on C1's nodes).
    pub table2: [WavelengthSet; 2],
    /// ∫ ȳ dλ on the grid: the luminance Y of a spectrum of constant value 1. Folded sets divide
    /// by it, so that such a spectrum has Y = 1 (display white).
    pub unit_spectrum_y: f64,
    /// The standard displays (`SRGB`, `DISPLAY_P3`, `REC2020`, `MEYER_1987`) and their
    /// matrices, derived once here; scenes, code generation, shaders and the tools take them from
    /// here.
    pub displays: Vec<(DisplaySpec, DisplayMatrices)>,
}

impl Derivation {
    /// A set folded for a display: `rgb = weights · samples` gives linear RGB, with a constant
    /// spectrum of 1 at Y = 1 (AC1C2 → XYZ → RGB and 1 / [`unit_spectrum_y`](Self::unit_spectrum_y)
    /// multiplied into the weights in f64).
    pub fn folded(&self, set: &WavelengthSet, matrices: &DisplayMatrices) -> [Vec<f64>; 3] {
        let m = display::mul3(&matrices.xyz_to_rgb, &self.opponent.ac1c2_to_xyz);
        display::fold(&m, &set.weights, 1.0 / self.unit_spectrum_y)
    }

    /// A set as it is measured (`spectral_quadrature_spectra::EvalSet`): its name, its
    /// wavelengths and its AC1C2 rows turned into XYZ rows by the derivation's
    /// [`Opponent::ac1c2_to_xyz`], under `family` (for grouping in tables and plots).
    pub fn eval_set(&self, set: &WavelengthSet, family: &str) -> EvalSet {
        EvalSet::from_weights(
            &set.name,
            family,
            None,
            &set.wavelengths_nm,
            &set.weights,
            &self.opponent.ac1c2_to_xyz,
        )
    }

    /// The display called `name` and its matrices, or [`Error::UnknownDisplay`] listing the
    /// valid names.
    pub fn display(&self, name: &str) -> Result<&(DisplaySpec, DisplayMatrices), Error> {
        self.displays
            .iter()
            .find(|(s, _)| s.name == name)
            .ok_or_else(|| Error::UnknownDisplay {
                name: name.into(),
                valid: self.displays.iter().map(|(s, _)| s.name.clone()).collect(),
            })
    }
}

/// Table 2: how far (nm) an A node may move to reuse another channel's wavelength. The paper's A
/// nodes 483.0 and 632.3 nm lie 7.9 and 0.9 nm from C1's 490.9 and 631.4 nm.
pub(crate) const TABLE2_SNAP_NM: f64 = 10.0;

/// Runs the derivation with the observer's embedded table.
pub fn derive(settings: &Settings) -> Result<Derivation, Error> {
    let observer = settings.observer.load(&settings.data_dir)?;
    derive_with(settings, observer)
}

/// Runs the derivation on a given observer table (for example one read from a user's file).
pub fn derive_with(settings: &Settings, mut observer: Observer) -> Result<Derivation, Error> {
    if let Some(k) = settings.observer_decimals {
        let scale = 10f64.powi(k.min(15) as i32);
        for v in observer.xyz.iter_mut().flatten() {
            *v = (*v * scale).round() / scale;
        }
    }
    let [lo, hi] = settings.range_nm;
    let rows = observer.grid_rows(lo, hi, settings.step_nm)?;
    if settings.max_order == 0 {
        return Err(Error::Settings("max_order must be at least 1".into()));
    }
    if settings.max_order >= rows.len() {
        return Err(Error::Settings(std::format!(
            "max_order {} needs more than {} grid points",
            settings.max_order,
            rows.len()
        )));
    }
    let grid_nm: Vec<f64> = rows.iter().map(|&r| observer.wavelengths[r]).collect();
    let xyz: Vec<[f64; 3]> = rows.iter().map(|&r| observer.xyz[r]).collect();
    let cones = opponent::cone_fundamentals(&xyz, &settings.cone_matrix);
    let covariance =
        opponent::covariance_matrix(&cones, &grid_nm, settings.step_nm, &settings.covariance)?;
    // Peaks are read off the observer's own (finest) table inside the range.
    let fine: Vec<[f64; 3]> = observer
        .wavelengths
        .iter()
        .zip(&observer.xyz)
        .filter(|(l, _)| **l >= lo - 1e-9 && **l <= hi + 1e-9)
        .map(|(_, v)| *v)
        .collect();
    let opponent = opponent::karhunen_loeve(&covariance, &settings.cone_matrix, &fine)?;
    let sensitivities = opponent::sensitivities(&opponent, &xyz);
    let measures = [0, 1, 2].map(|c| {
        let w: Vec<f64> = sensitivities.iter().map(|s| s[c]).collect();
        Measure::new(&grid_nm, &w, settings.step_nm, settings.range_nm)
    });
    let recurrences = [0, 1, 2].map(|c| quadrature::stieltjes(&measures[c], settings.max_order));
    let rules = [0, 1, 2].map(|c| {
        (1..=settings.max_order)
            .map(|n| quadrature::gauss_rule(&measures[c], &recurrences[c], n, settings.range_nm))
            .collect::<Vec<_>>()
    });
    let row1 = WavelengthSet::merge(
        "TABLE2_ROW1",
        "Table 2, first row: Gauss rules A order 3, C1 order 2, C2 order 1 (6 wavelengths).",
        [rules[0].get(2), rules[1].get(1), rules[2].first()],
    )?;
    let row2 = row1.snap_channel(
        "TABLE2_ROW2",
        "Table 2, second row: as row 1, with A's outer nodes moved onto C1's and A's weights made interpolatory (4 wavelengths).",
        0,
        &measures[0],
        TABLE2_SNAP_NM,
    );
    let unit_spectrum_y = xyz.iter().map(|v| v[1]).sum::<f64>() * settings.step_nm;
    let displays = display::standard_displays()
        .into_iter()
        .map(|spec| display::display_matrices(&spec).map(|m| (spec, m)))
        .collect::<Result<Vec<_>, Error>>()?;
    Ok(Derivation {
        unit_spectrum_y,
        displays,
        settings: settings.clone(),
        observer,
        grid_nm,
        xyz,
        cones,
        covariance: [0, 1, 2].map(|i| [0, 1, 2].map(|j| covariance[(i, j)])),
        opponent,
        sensitivities,
        measures,
        recurrences,
        rules,
        table2: [row1, row2],
    })
}
