//! Wavelength sets: N distinct wavelengths and a 3×N weight matrix (rows A, C1, C2), built from
//! per-channel rules (Table 2).

use std::string::String;
use std::vec::Vec;

use super::quadrature::{interpolatory_weights, Measure, Rule};
use crate::base::error::{Error, SetNameProblem};

/// N distinct wavelengths (nm, ascending) and the weights that turn samples at them into A, C1
/// and C2: `ac1c2[c] = Σ_i weights[c][i] · sample[i]`.
#[derive(Debug, Clone, PartialEq)]
pub struct WavelengthSet {
    /// A name, used for the generated const (upper snake case).
    pub name: String,
    /// One line for the generated doc comment.
    pub doc: String,
    /// Distinct wavelengths in nm, ascending.
    pub wavelengths_nm: Vec<f64>,
    /// `weights[channel][i]` for channels A, C1, C2, for dλ in nm.
    pub weights: [Vec<f64>; 3],
    /// The light folded into the weights (the samples are reflectances under it), or `None`
    /// for a set that takes radiances.
    pub light: Option<String>,
    /// For a sensor set (a scene's `[sensors]` table): the sensor's name. Its samples are the
    /// channels' readings, and `wavelengths_nm` holds each channel's peak.
    pub sensor: Option<String>,
}

/// Two nodes closer than this (nm) are the same wavelength when rules are merged; nodes printed
/// to 0.1 nm that agree to 1e-9 nm are the same number.
pub const SAME_WAVELENGTH_NM: f64 = 1e-9;

impl WavelengthSet {
    /// The union of one rule per channel (`None`: the channel is not computed, its row is zero).
    /// Each rule must be defined.
    pub fn merge(name: &str, doc: &str, rules: [Option<&Rule>; 3]) -> Result<WavelengthSet, Error> {
        let mut wavelengths: Vec<f64> = Vec::new();
        for (c, rule) in rules.iter().enumerate() {
            if let Some(r) = rule {
                if !r.is_defined() {
                    return Err(Error::SetName {
                        name: name.into(),
                        problem: SetNameProblem::RuleUndefined {
                            channel: c,
                            order: r.order,
                            status: r.status.as_str(),
                            reason: r.reason.clone(),
                        },
                    });
                }
                wavelengths.extend(&r.nodes_nm);
            }
        }
        wavelengths.sort_by(f64::total_cmp);
        wavelengths.dedup_by(|a, b| (*a - *b).abs() <= SAME_WAVELENGTH_NM);
        let mut weights: [Vec<f64>; 3] = Default::default();
        for (c, rule) in rules.iter().enumerate() {
            weights[c] = std::vec![0.0; wavelengths.len()];
            if let Some(r) = rule {
                for (node, w) in r.nodes_nm.iter().zip(&r.weights) {
                    let i = position(&wavelengths, *node).expect("merged node present");
                    weights[c][i] += w;
                }
            }
        }
        Ok(WavelengthSet {
            name: name.into(),
            doc: doc.into(),
            wavelengths_nm: wavelengths,
            weights,
            light: None,
            sensor: None,
        })
    }

    /// Replaces `channel`'s own nodes by the nearest node of another channel within
    /// `snap_nm`, and gives that channel the interpolatory weights of `measure` on the nodes it
    /// ends up with (Table 2, second row: A borrows C1's 490.9 and 631.4 nm). Wavelengths no
    /// channel uses any more are dropped.
    pub(crate) fn snap_channel(
        &self,
        name: &str,
        doc: &str,
        channel: usize,
        measure: &Measure,
        snap_nm: f64,
    ) -> WavelengthSet {
        let own: Vec<usize> = (0..self.wavelengths_nm.len())
            .filter(|&i| self.weights[channel][i] != 0.0)
            .collect();
        let used_by_others = |i: usize| (0..3).any(|c| c != channel && self.weights[c][i] != 0.0);
        let mut nodes: Vec<f64> = own
            .iter()
            .map(|&i| {
                let here = self.wavelengths_nm[i];
                (0..self.wavelengths_nm.len())
                    .filter(|&k| used_by_others(k))
                    .map(|k| self.wavelengths_nm[k])
                    .filter(|l| (l - here).abs() <= snap_nm)
                    .min_by(|a, b| (a - here).abs().total_cmp(&(b - here).abs()))
                    .unwrap_or(here)
            })
            .collect();
        nodes.sort_by(f64::total_cmp);
        nodes.dedup_by(|a, b| (*a - *b).abs() <= SAME_WAVELENGTH_NM);
        let new_weights = interpolatory_weights(measure, &nodes);
        let keep: Vec<usize> = (0..self.wavelengths_nm.len())
            .filter(|&i| used_by_others(i) || position(&nodes, self.wavelengths_nm[i]).is_some())
            .collect();
        let wavelengths_nm: Vec<f64> = keep.iter().map(|&i| self.wavelengths_nm[i]).collect();
        let mut weights: [Vec<f64>; 3] = Default::default();
        for (c, row) in weights.iter_mut().enumerate() {
            *row = if c == channel {
                wavelengths_nm
                    .iter()
                    .map(|&l| position(&nodes, l).map_or(0.0, |k| new_weights[k]))
                    .collect()
            } else {
                keep.iter().map(|&i| self.weights[c][i]).collect()
            };
        }
        WavelengthSet {
            name: name.into(),
            doc: doc.into(),
            wavelengths_nm,
            weights,
            light: self.light.clone(),
            sensor: self.sensor.clone(),
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

    /// AC1C2 of a spectrum given as a function of wavelength.
    #[cfg(test)]
    pub(crate) fn apply(&self, spectrum: impl Fn(f64) -> f64) -> [f64; 3] {
        let samples: Vec<f64> = self.wavelengths_nm.iter().map(|&l| spectrum(l)).collect();
        [0, 1, 2].map(|c| {
            self.weights[c]
                .iter()
                .zip(&samples)
                .map(|(w, s)| w * s)
                .sum()
        })
    }
}

/// Channel names in row order.
pub(crate) const CHANNELS: [&str; 3] = ["A", "C1", "C2"];

fn position(list: &[f64], value: f64) -> Option<usize> {
    list.iter()
        .position(|&l| (l - value).abs() <= SAME_WAVELENGTH_NM)
}
