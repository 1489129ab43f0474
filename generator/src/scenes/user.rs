//! Sets for what the user really has: a light measured as a CSV file, the wavelengths a renderer
//! already samples, and a spectral sensor's channels.
//!
//! All three use the shared sets' model ([`crate::shared`]): the same prior on reflectances
//! (Matérn 5/2 plus the training reflectances' covariance), the same white condition (a constant
//! spectrum is integrated exactly: under a folded light, the light's own white is exact), the
//! same metric. What changes is what a sample is:
//!
//! - a light by file ([`UserLight`]) is folded like a built-in illuminant: `KQ_<LIGHT>_<n>`
//!   searches `n` wavelengths for it;
//! - fixed wavelengths (`fixed_set`) keep the user's wavelengths and get the best 3×N weights
//!   for them (no search);
//! - a sensor (`sensor_set`) has no wavelengths: each sample is a channel's reading
//!   `∫ S_k(λ) e(λ) dλ` of the radiance e, and the 3×N matrix from readings to XYZ (or AC1C2, or
//!   display RGB once folded) is the best linear estimate under the prior. [`least_squares`]
//!   gives the plain least-squares fit on training colours for comparison.

use std::string::{String, ToString};
use std::vec::Vec;

use crate::base::error::Error;
use crate::derivation::derive::Derivation;
use crate::derivation::display;
use crate::derivation::sets::WavelengthSet;
use crate::shared;
use spectral_quadrature_spectra::{
    read_error, Curve, DataError, EvalSet, Negatives, Spectra, ZeroedNegatives,
};

/// The most wavelengths or channels a fixed or sensor set may have (the runtime's largest
/// const-generic size the crate tests).
pub(crate) const MAX_SAMPLES: usize = 64;

/// Whether `name` can be a set or light name in generated code: upper snake case, starting with
/// a letter (`SHOP_LED`, `AS7341`).
pub(crate) fn is_const_name(name: &str) -> bool {
    let mut chars = name.chars();
    chars.next().is_some_and(|c| c.is_ascii_uppercase())
        && chars.all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_')
}

/// A file's text; an error names `label` and the path ([`crate::read_data`]'s error).
fn read_labelled(path: &std::path::Path, label: &str) -> Result<String, Error> {
    std::fs::read_to_string(path).map_err(|e| read_error(label, path, &e).into())
}

/// Whether every value of `curve`'s data inside `range_nm` is zero.
fn is_zero_over(curve: &Curve, range_nm: [f64; 2]) -> bool {
    curve
        .wavelengths
        .iter()
        .zip(&curve.values)
        .filter(|(l, _)| **l >= range_nm[0] && **l <= range_nm[1])
        .all(|(_, v)| *v == 0.0)
}

/// A light given by the user as a CSV file (wavelength in nm, one column of spectral power).
#[derive(Debug, Clone, PartialEq)]
pub struct UserLight {
    /// Its name in set names (`KQ_<name>_<n>`) and in the generated `Samples`.
    pub name: String,
    /// The file's label, for the tables' provenance.
    pub file: String,
    /// The spectral power, named `name`.
    pub curve: Curve,
    /// The negative values read as 0 ([`Spectra::zeroed`]), for the caller to report.
    pub zeroed: Option<ZeroedNegatives>,
}

impl UserLight {
    /// Parses a light file's text. Errors name `file` and the line: what [`Spectra::parse`]
    /// refuses, a file with more than one spectrum, data that do not cover `range_nm`, and a
    /// light that is zero over the range.
    #[cfg(test)]
    pub(crate) fn parse(
        name: &str,
        file: &str,
        text: &str,
        range_nm: [f64; 2],
    ) -> Result<UserLight, Error> {
        Self::parse_with(name, file, text, range_nm, Negatives::Refuse)
    }

    /// [`parse`](Self::parse) with the rule for negative values given ([`Spectra::parse_with`]).
    pub(crate) fn parse_with(
        name: &str,
        file: &str,
        text: &str,
        range_nm: [f64; 2],
        negatives: Negatives,
    ) -> Result<UserLight, Error> {
        let spectra = Spectra::parse_with(file, text, negatives)?;
        if spectra.len() != 1 {
            return Err(DataError {
                file: file.into(),
                line: 1,
                message: std::format!(
                    "a light file has one spectrum (wavelength_nm, power); this one has {} columns after the wavelength",
                    spectra.len()
                ),
            }
            .into());
        }
        let mut curve = spectra.curve(0, range_nm)?;
        if is_zero_over(&curve, range_nm) {
            return Err(DataError {
                file: file.into(),
                line: 0,
                message: std::format!(
                    "the light is zero everywhere in {}-{} nm",
                    range_nm[0],
                    range_nm[1]
                ),
            }
            .into());
        }
        curve.name = name.into();
        Ok(UserLight {
            name: name.into(),
            file: file.into(),
            curve,
            zeroed: spectra.zeroed().cloned(),
        })
    }

    /// Reads a light file (see [`parse_with`](Self::parse_with)); `label` names it in errors.
    pub(crate) fn read(
        name: &str,
        path: &std::path::Path,
        label: &str,
        range_nm: [f64; 2],
        negatives: Negatives,
    ) -> Result<UserLight, Error> {
        Self::parse_with(
            name,
            label,
            &read_labelled(path, label)?,
            range_nm,
            negatives,
        )
    }
}

/// A sensor's channels, read from a CSV file: wavelength in nm, one column of sensitivity per
/// channel, in the order the sensor reports them.
#[derive(Debug, Clone, PartialEq)]
pub struct Sensor {
    /// The file's label.
    pub file: String,
    /// One curve per channel, named by the header.
    pub channels: Vec<Curve>,
    /// The negative values read as 0 ([`Spectra::zeroed`]), for the caller to report.
    pub zeroed: Option<ZeroedNegatives>,
}

impl Sensor {
    /// Parses a sensor file's text. Errors name `file` and the line: what [`Spectra::parse`]
    /// refuses (negative sensitivities beyond the rounding noise among them), data that do not
    /// cover `range_nm`, more than [`MAX_SAMPLES`] channels, and a channel that is zero over the
    /// range.
    pub(crate) fn parse(
        file: &str,
        text: &str,
        range_nm: [f64; 2],
        negatives: Negatives,
    ) -> Result<Sensor, Error> {
        let spectra = Spectra::parse_with(file, text, negatives)?;
        if spectra.len() > MAX_SAMPLES {
            return Err(DataError {
                file: file.into(),
                line: 1,
                message: std::format!(
                    "{} channels; a sensor set has at most {MAX_SAMPLES}",
                    spectra.len()
                ),
            }
            .into());
        }
        let channels = spectra.curves(range_nm)?;
        for (k, c) in channels.iter().enumerate() {
            if is_zero_over(c, range_nm) {
                return Err(DataError {
                    file: file.into(),
                    line: 1,
                    message: std::format!(
                        "channel {} ({}, column {}) is zero everywhere in {}-{} nm: it reads nothing",
                        k + 1,
                        c.name,
                        k + 2,
                        range_nm[0],
                        range_nm[1]
                    ),
                }
                .into());
            }
        }
        Ok(Sensor {
            file: file.into(),
            channels,
            zeroed: spectra.zeroed().cloned(),
        })
    }

    /// Reads a sensor file: wavelength in nm, one column of sensitivity per channel. Errors name
    /// `label` and the line: what [`Spectra::parse`] refuses (negative sensitivities beyond the
    /// rounding noise among them), data that do not cover `range_nm`, more than `MAX_SAMPLES`
    /// channels, and a channel that is zero over the range.
    #[cfg(test)]
    pub(crate) fn read(
        path: &std::path::Path,
        label: &str,
        range_nm: [f64; 2],
    ) -> Result<Sensor, Error> {
        Self::read_with(path, label, range_nm, Negatives::Refuse)
    }

    /// `read` with the rule for negative values given ([`Spectra::parse_with`]).
    pub(crate) fn read_with(
        path: &std::path::Path,
        label: &str,
        range_nm: [f64; 2],
        negatives: Negatives,
    ) -> Result<Sensor, Error> {
        Self::parse(label, &read_labelled(path, label)?, range_nm, negatives)
    }

    /// Each channel's peak wavelength (the first maximum on the 1 nm grid of `range_nm`), in
    /// channel order: what a sensor set bakes in place of sampling wavelengths.
    pub(crate) fn peaks_nm(&self, range_nm: [f64; 2]) -> Vec<f64> {
        self.channels
            .iter()
            .map(|c| {
                let mut best = (f64::NEG_INFINITY, range_nm[0]);
                let mut nm = range_nm[0];
                while nm <= range_nm[1] + 1e-9 {
                    let v = c.at(nm);
                    if v > best.0 {
                        best = (v, nm);
                    }
                    nm += 1.0;
                }
                best.1
            })
            .collect()
    }
}

/// A set fitted to the user's samples: wavelengths (or a sensor's channel peaks) and folded XYZ
/// weights, and how to measure it.
#[derive(Debug, Clone, PartialEq)]
pub struct Fitted {
    /// The set's name.
    pub name: String,
    /// The light folded into the weights, `None` for radiances.
    pub light: Option<String>,
    /// The sensor's name for a sensor set.
    pub sensor: Option<String>,
    /// The sensor's channels, for a sensor set (to fit other matrices on the same readings).
    pub channels: Option<Sensor>,
    /// Sampling wavelengths in nm; for a sensor, each channel's peak.
    pub wavelengths_nm: Vec<f64>,
    /// `w[c][i]`: XYZ from the samples (reflectances under the light, radiances, or readings).
    pub xyz_weights: [Vec<f64>; 3],
    /// The expected linearised CIELAB error under the prior, as a shared set's
    /// ([`Shared::expected_error`](crate::shared::Shared::expected_error)).
    pub expected_error: f64,
    /// The set as the report measures it, on radiances.
    pub eval: EvalSet,
    /// The samples of white: a reflectance of 1 under the light (or a radiance of 1), at the
    /// luminance of a spectrum of constant 1. Ones for wavelengths; for a sensor, the golden
    /// device's reading of it in each channel, `white_readings` (the reference the scene's
    /// `tables::sensors::<NAME>_WHITE` bakes, the same numbers).
    pub white_samples: Vec<f64>,
}

impl Fitted {
    /// The set as the runtime bakes it: AC1C2 rows (Eq. 9 applied to the XYZ weights).
    pub(crate) fn wavelength_set(&self, d: &Derivation) -> WavelengthSet {
        let what = match (&self.sensor, &self.light) {
            (Some(s), Some(l)) => std::format!("samples are the readings of sensor {s}'s {} channels, in their order (the wavelengths are the channels' peaks, not sampling wavelengths), weights fitted for reflectances under {l}", self.wavelengths_nm.len()),
            (Some(s), None) => std::format!("samples are the readings of sensor {s}'s {} channels, in their order (the wavelengths are the channels' peaks, not sampling wavelengths), weights fitted for radiances", self.wavelengths_nm.len()),
            (None, Some(l)) => std::format!("the user's {} wavelengths; samples are reflectances under {l}, folded into the weights", self.wavelengths_nm.len()),
            (None, None) => std::format!("the user's {} wavelengths; samples are radiances", self.wavelengths_nm.len()),
        };
        WavelengthSet {
            name: self.name.clone(),
            doc: std::format!(
                "Weights fitted by kernel quadrature: {what}. Trained on the CIE test colour samples."
            ),
            wavelengths_nm: self.wavelengths_nm.clone(),
            weights: display::fold(&d.opponent.xyz_to_ac1c2, &self.xyz_weights, 1.0),
            light: self.light.clone(),
            sensor: self.sensor.clone(),
        }
    }
}

fn invalid(name: &str, message: String) -> Error {
    Error::InSet {
        name: name.into(),
        error: std::boxed::Box::new(Error::Settings(message)),
    }
}

/// The best 3×N weights for exactly `wavelengths_nm` (ascending, distinct, inside the
/// derivation's range, at most [`MAX_SAMPLES`]), for reflectances under `light` or for radiances
/// (`None`). Errors ([`Error::InSet`]) name the set and the wavelength at fault.
pub(crate) fn fixed_set(
    d: &Derivation,
    name: &str,
    wavelengths_nm: &[f64],
    light: Option<&Curve>,
) -> Result<Fitted, Error> {
    let [lo, hi] = d.settings.range_nm;
    if wavelengths_nm.is_empty() || wavelengths_nm.len() > MAX_SAMPLES {
        return Err(invalid(
            name,
            std::format!(
                "{} wavelengths; a fixed set has 1 to {MAX_SAMPLES}",
                wavelengths_nm.len()
            ),
        ));
    }
    if let Some(bad) = wavelengths_nm
        .iter()
        .find(|l| !(l.is_finite() && **l >= lo && **l <= hi))
    {
        return Err(invalid(
            name,
            std::format!("wavelength {bad} nm is outside the range {lo}-{hi} nm"),
        ));
    }
    if let Some(w) = wavelengths_nm.windows(2).find(|w| w[0] >= w[1]) {
        return Err(invalid(
            name,
            std::format!(
                "wavelengths must be strictly increasing: {} nm then {} nm",
                w[0],
                w[1]
            ),
        ));
    }
    let p = shared::problem_for(d, light)?;
    let rows = p
        .point_rows(wavelengths_nm)
        .ok_or_else(|| invalid(name, "a wavelength is off the grid".into()))?;
    let light_at: Vec<f64> = wavelengths_nm.iter().map(|&l| p.light_at(l)).collect();
    if let Some(i) = light_at.iter().position(|v| v.is_nan() || *v <= 0.0) {
        return Err(invalid(
            name,
            std::format!(
                "the light has no power at {} nm: a sample there says nothing about the colour",
                wavelengths_nm[i]
            ),
        ));
    }
    let (xyz_weights, expected_error) = p.solve_rows(&rows).ok_or_else(|| Error::InSet {
        name: name.into(),
        error: std::boxed::Box::new(Error::Numerical("the kriging system is singular".into())),
    })?;
    let eval = EvalSet {
        name: name.into(),
        family: "fixed".into(),
        orders: None,
        wavelengths_nm: wavelengths_nm.to_vec(),
        xyz_weights: xyz_weights
            .clone()
            .map(|row| row.iter().zip(&light_at).map(|(w, l)| w / l).collect()),
    };
    Ok(Fitted {
        name: name.into(),
        light: light.map(|l| l.name.clone()),
        sensor: None,
        channels: None,
        wavelengths_nm: wavelengths_nm.to_vec(),
        xyz_weights,
        expected_error,
        eval,
        white_samples: std::vec![1.0; wavelengths_nm.len()],
    })
}

/// The grid set that measures readings-to-XYZ weights `w` of `sensor` on radiances: on the 1 nm
/// grid, `Σ_k w[c][k] · S_k(λ)`.
fn sensor_eval(
    d: &Derivation,
    name: &str,
    family: &str,
    sensor: &Sensor,
    w: &[Vec<f64>; 3],
) -> Result<EvalSet, Error> {
    let grid = d
        .observer
        .full_integration(d.settings.range_nm, 1.0)?
        .wavelengths_nm;
    let xyz_weights = [0, 1, 2].map(|c| {
        grid.iter()
            .map(|&nm| {
                sensor
                    .channels
                    .iter()
                    .zip(&w[c])
                    .map(|(s, wk)| wk * s.at(nm))
                    .sum()
            })
            .collect()
    });
    Ok(EvalSet {
        name: name.into(),
        family: family.into(),
        orders: None,
        wavelengths_nm: grid,
        xyz_weights,
    })
}

/// The best 3×N matrix from `sensor`'s readings to XYZ under the prior, for reflectances under
/// `light` (the prior is on the reflectance, and the light's white is exact) or for radiances
/// (`None`). A reading is `∫ S_k(λ) e(λ) dλ` of the radiance e that reaches the sensor, in
/// the units of the sensor file's sensitivities times nm.
pub(crate) fn sensor_set(
    d: &Derivation,
    name: &str,
    sensor_name: &str,
    sensor: &Sensor,
    light: Option<&Curve>,
) -> Result<Fitted, Error> {
    let p = shared::problem_for(d, light)?;
    let rows = p.channel_rows(&sensor.channels);
    let white_samples = white_readings(d, sensor, light)?;
    let (xyz_weights, expected_error) = p.solve_rows(&rows).ok_or_else(|| Error::InSet {
        name: name.into(),
        error: std::boxed::Box::new(Error::Numerical(
            "the kriging system is singular (are two channels the same?)".into(),
        )),
    })?;
    // The problem's light is scaled to unit luminance; a real reading of r · L is that scale
    // times the row's, and so is XYZ: the weights apply to real readings as they are.
    let eval = sensor_eval(d, name, "sensor", sensor, &xyz_weights)?;
    Ok(Fitted {
        name: name.into(),
        light: light.map(|l| l.name.clone()),
        sensor: Some(sensor_name.to_string()),
        channels: Some(sensor.clone()),
        wavelengths_nm: sensor.peaks_nm(d.settings.range_nm),
        xyz_weights,
        expected_error,
        eval,
        white_samples,
    })
}

/// The factor that scales `light` (a constant 1 if `None`) so that a perfect white under it has
/// the luminance of a constant spectrum of 1 on the derivation's grid, with `light` integrated
/// at 1 nm.
fn light_scale(d: &Derivation, light: Option<&Curve>) -> Result<f64, Error> {
    let full = d.observer.full_integration(d.settings.range_nm, 1.0)?;
    let y = full.xyz(|nm| light.map_or(1.0, |l| l.at(nm)))[1];
    if !(y > 0.0 && y.is_finite()) {
        return Err(Error::Settings("the light has no luminance".into()));
    }
    Ok(d.unit_spectrum_y / y)
}

/// What the golden device (the sensor's channels exactly) reads on each of `reflectances` under
/// `light` (a constant 1 if `None`): `∫ S_k(λ) c L(λ) ρ(λ) dλ` at 1 nm over the derivation's
/// range, with `c` the factor that gives a perfect white under the light the luminance of a
/// constant spectrum of 1 ([`Derivation::unit_spectrum_y`]), which the folded sets show as the
/// display's white. `result[j][k]`: reflectance j, channel k.
pub fn golden_readings(
    d: &Derivation,
    sensor: &Sensor,
    light: Option<&Curve>,
    reflectances: &[Curve],
) -> Result<Vec<Vec<f64>>, Error> {
    let scale = light_scale(d, light)?;
    let grid = d
        .observer
        .full_integration(d.settings.range_nm, 1.0)?
        .wavelengths_nm;
    let lit: Vec<f64> = grid
        .iter()
        .map(|&nm| scale * light.map_or(1.0, |l| l.at(nm)))
        .collect();
    Ok(reflectances
        .iter()
        .map(|r| {
            sensor
                .channels
                .iter()
                .map(|s| {
                    grid.iter()
                        .zip(&lit)
                        .map(|(&nm, l)| s.at(nm) * l * r.at(nm))
                        .sum()
                })
                .collect()
        })
        .collect())
}

/// What the golden device reads on a perfect white under `light` (a constant 1 if `None`), in
/// the units of [`golden_readings`]: a sensor set's samples of white
/// ([`Fitted::white_samples`]), which set the scale of its integer form, and the reference of a
/// dark and white calibration at run time (`tables::sensors::<NAME>_WHITE`).
pub(crate) fn white_readings(
    d: &Derivation,
    sensor: &Sensor,
    light: Option<&Curve>,
) -> Result<Vec<f64>, Error> {
    let white = Curve::constant("white", 1.0, d.settings.range_nm);
    Ok(golden_readings(d, sensor, light, &[white])?.remove(0))
}

/// The plain least-squares matrix from `sensor`'s readings to XYZ, fitted on `training`
/// reflectances under `light` (no prior, no white condition): the usual hand fit, for
/// comparison. Measured like `sensor_set`'s. `None` when the normal equations are singular
/// (fewer training colours than channels).
pub fn least_squares(
    d: &Derivation,
    name: &str,
    sensor: &Sensor,
    light: &Curve,
    training: &[Curve],
) -> Result<Option<EvalSet>, Error> {
    let full = d.observer.full_integration(d.settings.range_nm, 1.0)?;
    let n = sensor.channels.len();
    let m = training.len();
    let grid = &full.wavelengths_nm;
    let readings = nalgebra::DMatrix::<f64>::from_fn(m, n, |j, k| {
        grid.iter()
            .map(|&nm| sensor.channels[k].at(nm) * light.at(nm) * training[j].at(nm))
            .sum()
    });
    let xyz = nalgebra::DMatrix::<f64>::from_fn(m, 3, |j, c| {
        grid.iter()
            .zip(&full.xyz_weights[c])
            .map(|(&nm, w)| w * light.at(nm) * training[j].at(nm))
            .sum()
    });
    let normal = readings.transpose() * &readings;
    let Some(x) = normal.lu().solve(&(readings.transpose() * xyz)) else {
        return Ok(None);
    };
    let w: [Vec<f64>; 3] = [0, 1, 2].map(|c| (0..n).map(|k| x[(k, c)]).collect());
    if w.iter().flatten().any(|v| !v.is_finite()) {
        return Ok(None);
    }
    sensor_eval(d, name, "sensor least squares", sensor, &w).map(Some)
}
