//! Measuring wavelength sets: spectra read from CSV, resampled, integrated exactly and with a
//! set, and compared in CIELAB (ΔE*ab and CIEDE2000).
//!
//! Error is a colour difference between a stimulus integrated by the reference (every grid
//! wavelength) and by a set. As in the paper's Table 2, the white of CIELAB is integrated by the
//! same rule as the stimulus: the reference white for the reference colour, the set's white for
//! the set's colour.

use std::string::{String, ToString};
use std::vec::Vec;

use super::display;
use super::observer::Observer;
use super::sets::WavelengthSet;
use crate::base::error::{DataError, Error};
use crate::base::files::read_data_text;
use crate::base::table::{parse_table_with, read_text, Negatives, Spacing, Table, ZeroedNegatives};

/// CIELAB and the colour differences: one copy, shared with the runtime.
pub use spectral_quadrature_math::{delta_e2000, delta_e76, lab_from_xyz};

/// The longest wavelength a spectra file may give, nm (100 µm, far infrared): a larger or a
/// non-positive one is a unit or typing mistake, and wavelengths that far apart would overflow the
/// interpolation.
pub(crate) const MAX_WAVELENGTH_NM: f64 = 1e5;

/// One or more spectra read from a CSV file (first column wavelength in nm, one column per
/// spectrum, any strictly increasing spacing).
#[derive(Debug, Clone, PartialEq)]
pub struct Spectra {
    table: Table,
}

impl Spectra {
    /// Parses CSV text. Errors name `file` and the line: malformed rows (see
    /// `base::table::parse_table`), wavelengths outside (0, 100 µm], and values below zero by
    /// more than the tolerance ([`crate::Negatives::Refuse`]: no reflectance or spectral
    /// power is negative; rounding noise is read as 0 and reported by [`zeroed`](Self::zeroed)).
    pub fn parse(file: &str, text: &str) -> Result<Spectra, DataError> {
        Self::parse_with(file, text, Negatives::Refuse)
    }

    /// [`parse`](Self::parse) with the rule for negative values given: [`Negatives::Clamp`]
    /// reads every negative value as 0 (and reports it), for measured data whose noise is larger
    /// than the tolerance.
    pub fn parse_with(file: &str, text: &str, negatives: Negatives) -> Result<Spectra, DataError> {
        let table = parse_table_with(file, text, None, Spacing::Any, negatives)?;
        for (nm, line) in table.wavelengths.iter().zip(&table.lines) {
            if !(*nm > 0.0 && *nm <= MAX_WAVELENGTH_NM) {
                return Err(DataError {
                    file: file.into(),
                    line: *line,
                    message: std::format!(
                        "wavelength {nm} nm is outside (0, {MAX_WAVELENGTH_NM}] nm; is the first column in nm?"
                    ),
                });
            }
        }
        Ok(Spectra { table })
    }

    /// Reads a CSV file ([`parse`](Self::parse)); errors name the path and line.
    pub fn read(path: &std::path::Path) -> Result<Spectra, DataError> {
        Self::read_with(path, Negatives::Refuse)
    }

    /// Reads a CSV file (`parse_with`); errors name the path and line.
    pub fn read_with(path: &std::path::Path, negatives: Negatives) -> Result<Spectra, DataError> {
        let (label, text) = read_text(path)?;
        Self::parse_with(&label, &text, negatives)
    }

    /// The negative values read as 0, for the caller to report once as a warning (its
    /// `Display` names the file, the first value's line and column, and how many); `None` when
    /// the file has none.
    pub fn zeroed(&self) -> Option<&ZeroedNegatives> {
        self.table.zeroed.as_ref()
    }

    /// One of the spectra files the runtime crate ships in `data/`, by its label, read from
    /// `data_dir`: an illuminant `data/illuminant_<name>.csv` (a name of [`builtin_lights`]:
    /// `data/illuminant_C.csv`, ...), or the reflectances `data/reflectance_colorchecker_ohta.csv`,
    /// `data/reflectance_cie_tcs.csv` and `data/reflectance_rawtoaces_190.csv`. Errors name the
    /// label and line.
    pub fn builtin(data_dir: &std::path::Path, file: &str) -> Result<Spectra, DataError> {
        if !BUILTIN.contains(&file) {
            return Err(DataError {
                file: file.into(),
                line: 0,
                message: "not one of the crate's data files".into(),
            });
        }
        let text = read_data_text(data_dir, file)?;
        Self::parse(file, &text)
    }

    /// The file label.
    pub fn file(&self) -> &str {
        &self.table.file
    }

    /// The spectra's names (the header's columns after the wavelength).
    pub fn names(&self) -> &[String] {
        &self.table.columns
    }

    /// The number of spectra.
    pub(crate) fn len(&self) -> usize {
        self.table.columns.len()
    }

    /// Spectrum `k` as a curve, after checking that it covers `range_nm`; the error names the
    /// file and the first or last data line.
    pub fn curve(&self, k: usize, range_nm: [f64; 2]) -> Result<Curve, DataError> {
        let t = &self.table;
        let (first, last) = (t.wavelengths[0], t.wavelengths[t.wavelengths.len() - 1]);
        let eps = 1e-9;
        if first > range_nm[0] + eps || last < range_nm[1] - eps {
            let line = if first > range_nm[0] + eps {
                t.lines[0]
            } else {
                t.lines[t.lines.len() - 1]
            };
            return Err(DataError {
                file: t.file.clone(),
                line,
                message: std::format!(
                    "the data cover {first}-{last} nm; the observer needs {}-{} nm",
                    range_nm[0],
                    range_nm[1]
                ),
            });
        }
        Ok(Curve {
            name: t.columns[k].clone(),
            wavelengths: t.wavelengths.clone(),
            values: t.values.iter().map(|r| r[k]).collect(),
        })
    }

    /// Every spectrum as a curve (see [`curve`](Self::curve)).
    pub fn curves(&self, range_nm: [f64; 2]) -> Result<Vec<Curve>, DataError> {
        (0..self.len()).map(|k| self.curve(k, range_nm)).collect()
    }
}

/// A spectrum known at some wavelengths, linearly interpolated in between.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    /// The spectrum's name.
    pub name: String,
    /// Wavelengths in nm, strictly increasing.
    pub wavelengths: Vec<f64>,
    /// Values at those wavelengths.
    pub values: Vec<f64>,
}

impl Curve {
    /// The value at `nm`, interpolated linearly; outside the data, the nearest end value.
    pub fn at(&self, nm: f64) -> f64 {
        let w = &self.wavelengths;
        let i = w.partition_point(|&l| l < nm);
        if i == 0 {
            return self.values[0];
        }
        if i >= w.len() {
            return self.values[w.len() - 1];
        }
        let f = (nm - w[i - 1]) / (w[i] - w[i - 1]);
        self.values[i - 1] + f * (self.values[i] - self.values[i - 1])
    }

    /// A constant curve.
    pub fn constant(name: &str, value: f64, range_nm: [f64; 2]) -> Curve {
        Curve {
            name: name.into(),
            wavelengths: std::vec![range_nm[0], range_nm[1]],
            values: std::vec![value, value],
        }
    }
}

/// What reaches the eye: a light, possibly reflected by a surface, and the white of CIELAB.
#[derive(Debug, Clone, PartialEq)]
pub struct Stimulus {
    /// `surface under light`, or the light's name.
    pub name: String,
    /// The light's spectral power.
    pub light: Curve,
    /// The surface's reflectance, if any.
    pub reflectance: Option<Curve>,
}

impl Stimulus {
    /// The stimulus' spectral radiance at `nm`.
    pub fn radiance(&self, nm: f64) -> f64 {
        self.light.at(nm) * self.reflectance.as_ref().map_or(1.0, |r| r.at(nm))
    }

    /// The CIELAB white at `nm`: the light itself for a surface (a perfect white reflector); for
    /// a light seen directly, equal energy of the same luminance (so that errors in luminance
    /// and in chromaticity both show).
    pub fn white(&self, nm: f64, equal_energy_level: f64) -> f64 {
        match self.reflectance {
            Some(_) => self.light.at(nm),
            None => equal_energy_level,
        }
    }
}

/// Every surface under every light.
pub fn surfaces_under_lights(surfaces: &[Curve], lights: &[Curve]) -> Vec<Stimulus> {
    lights
        .iter()
        .flat_map(|l| {
            surfaces.iter().map(move |s| Stimulus {
                name: std::format!("{} under {}", s.name, l.name),
                light: l.clone(),
                reflectance: Some(s.clone()),
            })
        })
        .collect()
}

/// Lights seen directly.
pub fn emissions(lights: &[Curve]) -> Vec<Stimulus> {
    lights
        .iter()
        .map(|l| Stimulus {
            name: l.name.clone(),
            light: l.clone(),
            reflectance: None,
        })
        .collect()
}

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
            xyz_weights: display::fold(to_xyz, weights, 1.0),
        }
    }

    /// A derived set (its name, wavelengths and AC1C2 rows) with the matrix `ac1c2_to_xyz`.
    pub fn from_set(set: &WavelengthSet, family: &str, ac1c2_to_xyz: &[[f64; 3]; 3]) -> EvalSet {
        EvalSet::from_weights(
            &set.name,
            family,
            None,
            &set.wavelengths_nm,
            &set.weights,
            ac1c2_to_xyz,
        )
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

/// Full integration: every wavelength of the grid `start..=end` at `step` nm of the observer's
/// table, weights x̄ȳz̄ · step (the reference the sets are measured against, and the baseline
/// of the error-against-run-time table).
pub fn full_integration(
    observer: &Observer,
    range_nm: [f64; 2],
    step: f64,
) -> Result<EvalSet, Error> {
    let rows = observer.grid_rows(range_nm[0], range_nm[1], step)?;
    let wavelengths: Vec<f64> = rows.iter().map(|&r| observer.wavelengths[r]).collect();
    let xyz_weights = [0, 1, 2].map(|c| rows.iter().map(|&r| observer.xyz[r][c] * step).collect());
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
pub fn uniform(observer: &Observer, range_nm: [f64; 2], n: usize) -> EvalSet {
    let width = (range_nm[1] - range_nm[0]) / n as f64;
    let centres: Vec<f64> = (0..n)
        .map(|i| range_nm[0] + (i as f64 + 0.5) * width)
        .collect();
    let step = observer.step();
    let mut xyz_weights: [Vec<f64>; 3] = Default::default();
    for row in xyz_weights.iter_mut() {
        *row = std::vec![0.0; n];
    }
    for (l, v) in observer.wavelengths.iter().zip(&observer.xyz) {
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
pub(crate) fn lab_of(set: &EvalSet, s: &Stimulus, equal_energy_level: f64) -> [f64; 3] {
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

/// The spectra files the runtime crate ships in `data/`, by label (path relative to that crate).
pub(crate) const BUILTIN: &[&str] = &[
    "data/reflectance_colorchecker_ohta.csv",
    "data/reflectance_cie_tcs.csv",
    "data/reflectance_rawtoaces_190.csv",
    "data/illuminant_A.csv",
    "data/illuminant_C.csv",
    "data/illuminant_D50.csv",
    "data/illuminant_D65.csv",
    "data/illuminant_E.csv",
    "data/illuminant_F1.csv",
    "data/illuminant_F2.csv",
    "data/illuminant_F3.csv",
    "data/illuminant_F4.csv",
    "data/illuminant_F5.csv",
    "data/illuminant_F6.csv",
    "data/illuminant_F7.csv",
    "data/illuminant_F8.csv",
    "data/illuminant_F9.csv",
    "data/illuminant_F10.csv",
    "data/illuminant_F11.csv",
    "data/illuminant_F12.csv",
    "data/illuminant_LED_B1.csv",
    "data/illuminant_LED_B2.csv",
    "data/illuminant_LED_B3.csv",
    "data/illuminant_LED_B4.csv",
    "data/illuminant_LED_B5.csv",
    "data/illuminant_LED_BH1.csv",
    "data/illuminant_LED_RGB1.csv",
    "data/illuminant_LED_V1.csv",
    "data/illuminant_LED_V2.csv",
];

/// The built-in illuminants: the short names (`A`, `C`, `D65`, `F11`, `LED_B2`, ...) of the
/// `data/illuminant_<name>.csv` files the runtime crate ships, which a `KQ_<light>_<n>` set may
/// name.
pub fn builtin_lights() -> Vec<&'static str> {
    BUILTIN
        .iter()
        .filter_map(|f| f.strip_prefix("data/illuminant_")?.strip_suffix(".csv"))
        .collect()
}

/// A built-in illuminant by its short name (`A`, `C`, `D65`, `F11`, `LED_B2`, ...) as a curve
/// named after it.
pub fn builtin_illuminant(
    data_dir: &std::path::Path,
    name: &str,
    range_nm: [f64; 2],
) -> Result<Curve, DataError> {
    let file = std::format!("data/illuminant_{name}.csv");
    let mut c = Spectra::builtin(data_dir, &file)?.curve(0, range_nm)?;
    c.name = name.to_string();
    Ok(c)
}
