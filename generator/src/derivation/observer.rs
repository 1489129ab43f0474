//! CIE standard observers: colour-matching functions x̄, ȳ, z̄ read from the crate's `data/`.

use std::string::String;
use std::vec::Vec;

use spectral_quadrature_spectra::{
    parse_table, read_data_text, DataError, EvalSet, Spacing, ZeroedNegatives,
};

use super::opponent::MEYER_EQ1_XYZ_TO_SML;
use crate::base::error::Error;
use crate::base::files::sha256_hex;

/// The colour-matching functions the crate ships (all at 1 nm in `data/`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ObserverId {
    /// CIE 1931 2° (the paper's observer), 360-830 nm.
    Cie1931_2deg,
    /// CIE 1964 10°, 360-830 nm.
    Cie1964_10deg,
    /// CIE 2015 2° (CIE 170-2), 390-830 nm.
    Cie2015_2deg,
    /// CIE 2015 10° (CIE 170-2), 390-830 nm.
    Cie2015_10deg,
}

impl ObserverId {
    /// Every observer the crate ships.
    pub const ALL: [ObserverId; 4] = [
        ObserverId::Cie1931_2deg,
        ObserverId::Cie1964_10deg,
        ObserverId::Cie2015_2deg,
        ObserverId::Cie2015_10deg,
    ];

    /// The name used in settings, tables and CSV output, e.g. `cie1931_2deg`.
    pub fn name(self) -> &'static str {
        match self {
            ObserverId::Cie1931_2deg => "cie1931_2deg",
            ObserverId::Cie1964_10deg => "cie1964_10deg",
            ObserverId::Cie2015_2deg => "cie2015_2deg",
            ObserverId::Cie2015_10deg => "cie2015_10deg",
        }
    }

    /// Looks an observer up by [`name`](Self::name).
    pub(crate) fn from_name(name: &str) -> Option<ObserverId> {
        Self::ALL.into_iter().find(|o| o.name() == name)
    }

    /// The data file, relative to the crate root.
    pub(crate) fn file(self) -> &'static str {
        match self {
            ObserverId::Cie1931_2deg => "data/cmf_cie1931_2deg_1nm.csv",
            ObserverId::Cie1964_10deg => "data/cmf_cie1964_10deg_1nm.csv",
            ObserverId::Cie2015_2deg => "data/cmf_cie2015_2deg_1nm.csv",
            ObserverId::Cie2015_10deg => "data/cmf_cie2015_10deg_1nm.csv",
        }
    }

    /// XYZ → cone fundamentals (rows s̄, m̄, l̄) for this observer.
    ///
    /// * CIE 1931 2°: Eq. 1 of the paper (Vos-Walraven fundamentals). They satisfy the paper's
    ///   Eq. 21: l̄(570)/m̄(570) = 2 and s̄/(m̄ + l̄) = 1/16 at 475.5 nm.
    /// * CIE 2015 2° and 10°: the CIE 2006 cone fundamentals (the inverse of CIE 170-2's LMS →
    ///   XYZ matrix), scaled by the same Eq. 21 so that the three cones weigh as in the paper,
    ///   with m̄ + l̄ peaking at 1. (Each CIE 2006 fundamental peaks at 1 on its own, which
    ///   would give S the weight of L and M.)
    /// * CIE 1964 10°: no standard cone fundamentals are defined on its x̄ȳz̄, so Eq. 1 stands in
    ///   as an approximation; set [`Settings::cone_matrix`](crate::Settings::cone_matrix) to use
    ///   others.
    ///
    /// `table` is this observer's table ([`load`](Self::load)), from which the CIE 2015 scaling
    /// is computed.
    pub(crate) fn cone_matrix(self, table: &Observer) -> [[f64; 3]; 3] {
        match self {
            ObserverId::Cie1931_2deg | ObserverId::Cie1964_10deg => MEYER_EQ1_XYZ_TO_SML,
            ObserverId::Cie2015_2deg => Self::scaled_by_eq21(
                table,
                &[
                    [1.947_354_69, -1.414_451_23, 0.364_763_27],
                    [0.689_902_72, 0.348_321_89, 0.0],
                    [0.0, 0.0, 1.934_853_43],
                ],
            ),
            ObserverId::Cie2015_10deg => Self::scaled_by_eq21(
                table,
                &[
                    [1.939_864_43, -1.346_643_59, 0.430_449_35],
                    [0.692_839_32, 0.349_675_67, 0.0],
                    [0.0, 0.0, 2.146_879_45],
                ],
            ),
        }
    }

    /// XYZ → (s̄, m̄, l̄) from an LMS → XYZ matrix (columns L, M, S), each cone scaled so that
    /// l̄(570)/m̄(570) = 2 and s̄/(m̄ + l̄) = 1/16 at 475.5 nm (Eq. 21), and m̄ + l̄ peaks at 1.
    fn scaled_by_eq21(obs: &Observer, lms_to_xyz: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
        let inv = nalgebra::Matrix3::from_fn(|i, j| lms_to_xyz[i][j])
            .try_inverse()
            .expect("CIE 170-2's matrix is invertible");
        let lms = |v: &[f64; 3]| [0, 1, 2].map(|r| (0..3).map(|k| inv[(r, k)] * v[k]).sum::<f64>());
        let at = |nm: f64| {
            let i = obs.wavelengths.partition_point(|&l| l < nm);
            let (l0, l1) = (obs.wavelengths[i - 1], obs.wavelengths[i]);
            let f = if nm == l1 { 1.0 } else { (nm - l0) / (l1 - l0) };
            let (a, b) = (lms(&obs.xyz[i - 1]), lms(&obs.xyz[i]));
            [0, 1, 2].map(|c| a[c] + f * (b[c] - a[c]))
        };
        let [l570, m570, _] = at(570.0);
        let (a_l, a_m) = (1.0, l570 / (2.0 * m570));
        let [l475, m475, s475] = at(475.5);
        let a_s = (a_l * l475 + a_m * m475) / (16.0 * s475);
        let peak = obs
            .xyz
            .iter()
            .map(|v| {
                let c = lms(v);
                a_l * c[0] + a_m * c[1]
            })
            .fold(f64::MIN, f64::max);
        let scale = [a_s, a_m, a_l].map(|a| a / peak);
        [2, 1, 0]
            .into_iter()
            .zip(scale)
            .map(|(r, k)| [0, 1, 2].map(|c| k * inv[(r, c)]))
            .collect::<Vec<_>>()
            .try_into()
            .expect("three rows")
    }

    /// The spectral range the derivation uses by default: 380-770 nm (Eq. 2), or 390-770 nm for
    /// the CIE 2015 observers, whose tables start at 390 nm.
    pub(crate) fn default_range_nm(self) -> [f64; 2] {
        match self {
            ObserverId::Cie2015_2deg | ObserverId::Cie2015_10deg => [390.0, 770.0],
            _ => [380.0, 770.0],
        }
    }

    /// Reads and parses the table from `data_dir` (laid out like the runtime crate's `data/`).
    /// Errors name the file (its label `data/cmf_<observer>_1nm.csv`, as [`Observer::file`]
    /// holds it) and line.
    pub fn load(self, data_dir: &std::path::Path) -> Result<Observer, DataError> {
        let text = read_data_text(data_dir, self.file())?;
        Observer::parse(self.name(), self.file(), &text)
    }
}

/// Colour-matching functions on an evenly spaced wavelength grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Observer {
    /// Name used in tables, e.g. `cie1931_2deg`.
    pub name: String,
    /// Where the data came from (file label).
    pub file: String,
    /// Wavelengths in nm, evenly spaced.
    pub wavelengths: Vec<f64>,
    /// x̄, ȳ, z̄ at each wavelength.
    pub xyz: Vec<[f64; 3]>,
    /// SHA-256 of the file's text, for generated headers.
    pub sha256: String,
    /// The negative values within the tolerance that were read as 0
    /// ([`Negatives`](spectral_quadrature_spectra::Negatives)), for the caller to report; `None`
    /// when there were none.
    pub zeroed: Option<ZeroedNegatives>,
}

impl Observer {
    /// Parses an observer table: header plus rows `wavelength,x_bar,y_bar,z_bar`, evenly spaced,
    /// non-negative up to rounding noise (`spectral_quadrature_spectra::parse_table`). Errors
    /// name `file` and the offending line.
    pub(crate) fn parse(name: &str, file: &str, text: &str) -> Result<Observer, DataError> {
        let table = parse_table(file, text, Some(3), Spacing::Even)?;
        Ok(Observer {
            name: name.into(),
            file: table.file,
            wavelengths: table.wavelengths,
            xyz: table.values.iter().map(|r| [r[0], r[1], r[2]]).collect(),
            sha256: sha256_hex(text.as_bytes()),
            zeroed: table.zeroed,
        })
    }

    /// Reads an observer table from a file on disk.
    #[cfg(test)]
    pub(crate) fn read(name: &str, path: &std::path::Path) -> Result<Observer, DataError> {
        let (label, text) = spectral_quadrature_spectra::read_text(path)?;
        Self::parse(name, &label, &text)
    }

    /// The table's step in nm.
    pub(crate) fn step(&self) -> f64 {
        if self.wavelengths.len() < 2 {
            0.0
        } else {
            self.wavelengths[1] - self.wavelengths[0]
        }
    }

    /// Indices of the rows on the grid `start, start + step, ..., end` (inclusive), or an error
    /// saying why that grid is not a subset of this table.
    pub(crate) fn grid_rows(&self, start: f64, end: f64, step: f64) -> Result<Vec<usize>, Error> {
        let own = self.step();
        let first = *self
            .wavelengths
            .first()
            .ok_or_else(|| Error::Settings("empty observer table".into()))?;
        let last = *self
            .wavelengths
            .last()
            .ok_or_else(|| Error::Settings("empty observer table".into()))?;
        if !(start.is_finite() && end.is_finite() && step.is_finite())
            || start >= end
            || step <= 0.0
        {
            return Err(Error::Settings(std::format!(
                "range {start}-{end} nm with step {step} nm is not a valid grid"
            )));
        }
        if start < first - 1e-9 || end > last + 1e-9 {
            return Err(Error::Settings(std::format!(
                "range {start}-{end} nm is not covered by {} ({first}-{last} nm)",
                self.file
            )));
        }
        let ratio = step / own;
        let per = ratio.round();
        if per < 1.0 || (ratio - per).abs() > 1e-9 {
            return Err(Error::Settings(std::format!(
                "step {step} nm is not a whole multiple of {}'s {own} nm",
                self.file
            )));
        }
        let per = per as usize;
        let offset = (start - first) / own;
        if (offset - offset.round()).abs() > 1e-9 {
            return Err(Error::Settings(std::format!(
                "range start {start} nm is not on {}'s grid",
                self.file
            )));
        }
        let span = (end - start) / step;
        if (span - span.round()).abs() > 1e-9 {
            return Err(Error::Settings(std::format!(
                "range {start}-{end} nm is not a whole number of {step} nm steps"
            )));
        }
        let first_row = offset.round() as usize;
        Ok((0..=span.round() as usize)
            .map(|k| first_row + k * per)
            .collect())
    }

    /// Full integration: every wavelength of the grid `range_nm[0]..=range_nm[1]` at `step` nm of
    /// the table, weights x̄ȳz̄ · step (the reference the sets are measured against, and the
    /// baseline of the error-against-run-time table).
    pub fn full_integration(&self, range_nm: [f64; 2], step: f64) -> Result<EvalSet, Error> {
        let rows = self.grid_rows(range_nm[0], range_nm[1], step)?;
        let wavelengths: Vec<f64> = rows.iter().map(|&r| self.wavelengths[r]).collect();
        let xyz_weights = [0, 1, 2].map(|c| rows.iter().map(|&r| self.xyz[r][c] * step).collect());
        Ok(EvalSet {
            name: std::format!("full {step} nm"),
            family: "full".into(),
            orders: None,
            wavelengths_nm: wavelengths,
            xyz_weights,
        })
    }

    /// A uniform set: `n` wavelengths at the centres of `n` equal bins of `range_nm`, each weighted
    /// by the integral of x̄ȳz̄ over its bin (box filter, as spectral renderers sample), on the
    /// observer's own table.
    pub fn uniform_set(&self, range_nm: [f64; 2], n: usize) -> EvalSet {
        let width = (range_nm[1] - range_nm[0]) / n as f64;
        let centres: Vec<f64> = (0..n)
            .map(|i| range_nm[0] + (i as f64 + 0.5) * width)
            .collect();
        let step = self.step();
        let mut xyz_weights: [Vec<f64>; 3] = Default::default();
        for row in xyz_weights.iter_mut() {
            *row = std::vec![0.0; n];
        }
        for (l, v) in self.wavelengths.iter().zip(&self.xyz) {
            if *l < range_nm[0] - 1e-9 || *l > range_nm[1] + 1e-9 {
                continue;
            }
            // Trapezoid weights on the table: half at the range's ends.
            let edge = (*l - range_nm[0]).abs() < 1e-9 || (*l - range_nm[1]).abs() < 1e-9;
            let dl = if edge { 0.5 * step } else { step };
            let bin = (((*l - range_nm[0]) / width) as usize).min(n - 1);
            for c in 0..3 {
                xyz_weights[c][bin] += v[c] * dl;
            }
        }
        EvalSet {
            name: std::format!("uniform {n}"),
            family: "uniform".into(),
            orders: None,
            wavelengths_nm: centres,
            xyz_weights,
        }
    }
}
