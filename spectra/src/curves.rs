//! Spectra read from CSV, as curves interpolated linearly, and the stimuli they make: a light
//! seen directly, or a surface under a light.

use std::string::{String, ToString};
use std::vec::Vec;

use crate::files::read_data_text;
use crate::table::{parse_table_with, read_text, Negatives, Spacing, Table, ZeroedNegatives};
use crate::DataError;

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
    /// [`parse_table`](crate::parse_table)), wavelengths outside (0, 100 µm], and values below
    /// zero by more than the tolerance ([`Negatives::Refuse`]: no reflectance or spectral power
    /// is negative; rounding noise is read as 0 and reported by [`zeroed`](Self::zeroed)).
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
        if !BUILTIN_FILES.contains(&file) {
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

    /// The number of spectra (the header's columns after the wavelength).
    pub fn len(&self) -> usize {
        self.table.columns.len()
    }

    /// Whether there are no spectra: never for a parsed file (a header without value columns is
    /// an error), here for the `len`/`is_empty` pair.
    pub fn is_empty(&self) -> bool {
        self.table.columns.is_empty()
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

/// The spectra files the runtime crate ships in its `data/`, by label (the path relative to that
/// crate), which [`Spectra::builtin`] reads.
pub const BUILTIN_FILES: &[&str] = &[
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
    BUILTIN_FILES
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
