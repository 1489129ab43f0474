//! Measuring wavelength sets: a set's XYZ weights against a reference integration, compared in
//! CIELAB (ΔE*ab and CIEDE2000).
//!
//! Error is a colour difference between a stimulus integrated by the reference (every grid
//! wavelength) and by a set. As in the paper's Table 2, the white of CIELAB is integrated by the
//! same rule as the stimulus: the reference white for the reference colour, the set's white for
//! the set's colour.

use std::string::String;
use std::vec::Vec;

use spectral_quadrature_math::{delta_e2000, delta_e76, lab_from_xyz};

use crate::curves::Stimulus;

/// A wavelength set as the report measures it: wavelengths and XYZ weights (any set, whatever
/// space it was derived in, integrates X, Y, Z in the end).
#[derive(Debug, Clone, PartialEq)]
pub struct EvalSet {
    /// Name in tables.
    pub name: String,
    /// The family, for grouping in tables and plots.
    pub family: String,
    /// Per-channel orders, where the set is a combination of per-channel Gauss rules.
    pub orders: Option<[usize; 3]>,
    /// Distinct wavelengths in nm, ascending.
    pub wavelengths_nm: Vec<f64>,
    /// `xyz_weights[c][i]`: X, Y, Z rows.
    pub xyz_weights: [Vec<f64>; 3],
}

impl EvalSet {
    /// From a set with weights in some tristimulus space and the matrix `to_xyz` from that space
    /// to XYZ.
    pub fn from_weights(
        name: &str,
        family: &str,
        orders: Option<[usize; 3]>,
        wavelengths_nm: &[f64],
        weights: &[Vec<f64>; 3],
        to_xyz: &[[f64; 3]; 3],
    ) -> EvalSet {
        EvalSet {
            name: name.into(),
            family: family.into(),
            orders,
            wavelengths_nm: wavelengths_nm.to_vec(),
            xyz_weights: [0, 1, 2].map(|r| {
                (0..wavelengths_nm.len())
                    .map(|i| (0..3).map(|k| to_xyz[r][k] * weights[k][i]).sum())
                    .collect()
            }),
        }
    }

    /// The number of distinct wavelengths.
    pub fn len(&self) -> usize {
        self.wavelengths_nm.len()
    }

    /// Whether the set has no wavelengths.
    pub fn is_empty(&self) -> bool {
        self.wavelengths_nm.is_empty()
    }

    /// XYZ of a spectrum given as a function of wavelength.
    pub fn xyz(&self, f: impl Fn(f64) -> f64) -> [f64; 3] {
        let s: Vec<f64> = self.wavelengths_nm.iter().map(|&l| f(l)).collect();
        [0, 1, 2].map(|c| self.xyz_weights[c].iter().zip(&s).map(|(w, v)| w * v).sum())
    }
}

/// Colour differences of one set over stimuli.
#[derive(Debug, Clone, PartialEq)]
pub struct Errors {
    /// ΔE*ab per stimulus.
    pub de76: Vec<f64>,
    /// ΔE00 per stimulus.
    pub de00: Vec<f64>,
}

impl Errors {
    /// Mean ΔE*ab.
    pub fn mean_de76(&self) -> f64 {
        mean(&self.de76)
    }
    /// Largest ΔE*ab.
    pub fn max_de76(&self) -> f64 {
        self.de76.iter().copied().fold(0.0, f64::max)
    }
    /// Mean ΔE00.
    pub fn mean_de00(&self) -> f64 {
        mean(&self.de00)
    }
    /// Largest ΔE00.
    pub fn max_de00(&self) -> f64 {
        self.de00.iter().copied().fold(0.0, f64::max)
    }
}

fn mean(v: &[f64]) -> f64 {
    if v.is_empty() {
        f64::NAN
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    }
}

/// CIELAB of a stimulus by a set, the white integrated by the same set. For lights seen
/// directly the white is equal energy at `equal_energy_level`.
fn lab_of(set: &EvalSet, s: &Stimulus, equal_energy_level: f64) -> [f64; 3] {
    let xyz = set.xyz(|l| s.radiance(l));
    let white = set.xyz(|l| s.white(l, equal_energy_level));
    lab_from_xyz(xyz, white)
}

/// The reference colours of a list of stimuli, computed once.
#[derive(Debug, Clone, PartialEq)]
pub struct Reference {
    /// The reference set (normally the full 1 nm integration).
    pub set: EvalSet,
    /// Per stimulus: the level of the equal-energy white used for lights seen directly (the
    /// light's reference luminance relative to a constant spectrum of 1).
    pub levels: Vec<f64>,
    /// Per stimulus: reference CIELAB.
    pub labs: Vec<[f64; 3]>,
}

impl Reference {
    /// Integrates every stimulus (and its white) with `set`.
    pub fn new(set: EvalSet, stimuli: &[Stimulus]) -> Reference {
        let unit = set.xyz(|_| 1.0)[1];
        let levels: Vec<f64> = stimuli
            .iter()
            .map(|s| set.xyz(|l| s.radiance(l))[1] / unit)
            .collect();
        let labs = stimuli
            .iter()
            .zip(&levels)
            .map(|(s, &level)| lab_of(&set, s, level))
            .collect();
        Reference { set, levels, labs }
    }

    /// ΔE of `set` against the reference over the same stimuli.
    pub fn errors(&self, set: &EvalSet, stimuli: &[Stimulus]) -> Errors {
        let mut e = Errors {
            de76: Vec::with_capacity(stimuli.len()),
            de00: Vec::with_capacity(stimuli.len()),
        };
        for ((s, &level), exact) in stimuli.iter().zip(&self.levels).zip(&self.labs) {
            let approx = lab_of(set, s, level);
            e.de76.push(delta_e76(*exact, approx));
            e.de00.push(delta_e2000(*exact, approx));
        }
        e
    }
}
