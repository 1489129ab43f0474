//! A sensor's white reference and a device's calibration fitted at build time.
//!
//! The golden device is the sensor of the scene's file: its channels' curves exactly. A real
//! device reads `gain_k · golden_k + dark_k` plus noise, channel by channel. At run time the
//! runtime's `Calibration::from_dark_white` finds the dark offsets and gains from a dark reading
//! and a reading of a white reference; the reference is what `white_readings` bakes. At build
//! time, `[sensors.X] calibration = "readings.csv"` gives the device's readings of known
//! reflectances under the sensor's light, and [`fit`] finds each channel's gain and offset by
//! least squares against what the golden device reads on the same reflectances
//! ([`golden_readings`]). Either way the device's readings are corrected before the golden
//! device's matrix applies: the correction sits on top of it and the matrix stays the same.
//!
//! Units: the golden readings are those of the light scaled so that a perfect white has the
//! luminance of a constant spectrum of 1 ([`Derivation::unit_spectrum_y`](crate::Derivation::unit_spectrum_y)), which the folded
//! sets show as the display's white. So a corrected white reads as display white.

use std::string::{String, ToString};
use std::vec::Vec;

pub use super::user::golden_readings;
pub(crate) use super::user::white_readings;
use crate::base::error::{CalibrationProblem, Error};
use spectral_quadrature_spectra::{Curve, DataError, Spectra};

/// The reflectances a calibration's readings name when the scene gives none: the ColorChecker
/// of the crate's data.
pub const DEFAULT_REFLECTANCES: &str = "data/reflectance_colorchecker_ohta.csv";

/// The fewest readings a fit takes: two unknowns a channel, and at least one reading more to
/// tell a misfit.
pub(crate) const MIN_READINGS: usize = 3;

/// A device's dark offsets and gains: `(reading − dark) · gain` is the golden device's reading.
#[derive(Debug, Clone, PartialEq)]
pub struct ChannelFit {
    /// Each channel's reading at zero light, in the device's units.
    pub dark: Vec<f64>,
    /// Each channel's gain, golden units per device unit.
    pub gain: Vec<f64>,
    /// Each channel's root-mean-square residual, in the device's units.
    pub rms_residual: Vec<f64>,
}

/// What the build bakes for one sensor besides its sets: the white reference and, where the
/// scene gives readings, the fitted calibration.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct SensorTables {
    /// The sensor's name.
    pub name: String,
    /// The golden device's readings of a perfect white under the sensor's light (illuminant E
    /// for a sensor fitted for radiances), in the units of this module.
    pub white: Vec<f64>,
    /// The calibration fitted to the scene's readings, if it gave any.
    pub calibration: Option<ChannelFit>,
}

/// A device's readings of known reflectances: one row per reading, its first field naming a
/// reflectance, then one value per channel.
#[derive(Debug, Clone, PartialEq)]
pub struct Readings {
    /// The file's label.
    pub file: String,
    /// The reflectance each row names.
    pub patches: Vec<String>,
    /// `values[j][k]`: row j, channel k.
    pub values: Vec<Vec<f64>>,
    /// Each row's 1-based line.
    pub lines: Vec<u64>,
}

impl Readings {
    /// Parses a readings file. Lines starting with `#` are comments. The header is a name for
    /// the first column (`patch`), then the sensor's channel names in its order, `channels`;
    /// each row names a reflectance and gives one finite, non-negative reading per channel (the
    /// device's raw readings, dark offset included). Errors name `file` and the line: a header
    /// that does not list the channels, a missing or extra field, a value that is not a
    /// finite, non-negative number, an empty line, fewer than `MIN_READINGS` rows.
    pub fn parse(file: &str, text: &str, channels: &[String]) -> Result<Readings, DataError> {
        let err = |line: u64, message: String| DataError {
            file: file.into(),
            line,
            message,
        };
        let mut out = Readings {
            file: file.into(),
            patches: Vec::new(),
            values: Vec::new(),
            lines: Vec::new(),
        };
        let mut header_seen = false;
        let lines: Vec<&str> = text.lines().collect();
        let last = lines
            .iter()
            .rposition(|l| !l.trim().is_empty())
            .unwrap_or(0);
        for (i, raw) in lines.iter().enumerate().take(last + 1) {
            let line = i as u64 + 1;
            let trimmed = raw.trim();
            if trimmed.starts_with('#') {
                continue;
            }
            if trimmed.is_empty() {
                return Err(err(line, "empty line inside the readings".into()));
            }
            let fields = split_csv_line(raw).map_err(|e| err(line, e.to_string()))?;
            if !header_seen {
                header_seen = true;
                let names: Vec<&str> = fields.iter().skip(1).map(String::as_str).collect();
                if names != channels.iter().map(String::as_str).collect::<Vec<_>>() {
                    return Err(err(
                        line,
                        std::format!(
                            "the header must name the reflectance column, then the sensor's channels in its order: {}; it has {}",
                            channels.join(", "),
                            names.join(", ")
                        ),
                    ));
                }
                continue;
            }
            if fields.len() != channels.len() + 1 {
                return Err(err(
                    line,
                    std::format!(
                        "{} fields; a row has the reflectance's name and {} readings",
                        fields.len(),
                        channels.len()
                    ),
                ));
            }
            let mut row = Vec::with_capacity(channels.len());
            for (k, f) in fields.iter().skip(1).enumerate() {
                let v: f64 = f.parse().map_err(|_| {
                    err(
                        line,
                        std::format!("column {} ({}): {f:?} is not a number", k + 2, channels[k]),
                    )
                })?;
                if !(v.is_finite() && v >= 0.0) {
                    return Err(err(
                        line,
                        std::format!(
                            "column {} ({}): {f:?} is not a finite, non-negative reading",
                            k + 2,
                            channels[k]
                        ),
                    ));
                }
                row.push(v);
            }
            out.patches.push(fields[0].clone());
            out.values.push(row);
            out.lines.push(line);
        }
        if !header_seen {
            return Err(err(0, "empty file: expected a header row".into()));
        }
        if out.values.len() < MIN_READINGS {
            return Err(err(
                0,
                std::format!(
                    "{} readings; a calibration needs at least {MIN_READINGS}",
                    out.values.len()
                ),
            ));
        }
        Ok(out)
    }

    /// The reflectance of each row, looked up by name in `reflectances`. The error names the
    /// row's line and the names there are.
    pub(crate) fn reflectances(
        &self,
        reflectances: &Spectra,
        range_nm: [f64; 2],
    ) -> Result<Vec<Curve>, DataError> {
        let names = reflectances.names();
        self.patches
            .iter()
            .zip(&self.lines)
            .map(|(p, &line)| match names.iter().position(|n| n == p) {
                Some(k) => reflectances.curve(k, range_nm),
                None => Err(DataError {
                    file: self.file.clone(),
                    line,
                    message: std::format!(
                        "{p:?} is not a reflectance of {}; its reflectances: {}",
                        reflectances.file(),
                        names.join(", ")
                    ),
                }),
            })
            .collect()
    }
}

/// The fields of one CSV line (quotes as RFC 4180 has them), trimmed.
fn split_csv_line(line: &str) -> Result<Vec<String>, csv::Error> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(line.as_bytes());
    match reader.records().next() {
        Some(Ok(r)) => Ok(r.iter().map(ToString::to_string).collect()),
        Some(Err(e)) => Err(e),
        None => Ok(Vec::new()),
    }
}

/// Each channel's gain and dark offset, by least squares: the device's readings against the
/// golden device's on the same reflectances (`golden[j][k]`, `device[j][k]`: reading j,
/// channel k), `device ≈ golden / gain + dark`. Errors (naming the channel, counted from 1):
/// the golden readings do not vary in a channel (no slope to fit), or the device's do not grow
/// with them (a slope that is not positive: a wrong channel order or a dead channel).
pub fn fit(golden: &[Vec<f64>], device: &[Vec<f64>]) -> Result<ChannelFit, Error> {
    let n = golden.first().map_or(0, Vec::len);
    let m = golden.len() as f64;
    let mut out = ChannelFit {
        dark: Vec::with_capacity(n),
        gain: Vec::with_capacity(n),
        rms_residual: Vec::with_capacity(n),
    };
    for k in 0..n {
        let g: Vec<f64> = golden.iter().map(|r| r[k]).collect();
        let x: Vec<f64> = device.iter().map(|r| r[k]).collect();
        let (mg, mx) = (g.iter().sum::<f64>() / m, x.iter().sum::<f64>() / m);
        let sgg: f64 = g.iter().map(|v| (v - mg).powi(2)).sum();
        let sgx: f64 = g.iter().zip(&x).map(|(a, b)| (a - mg) * (b - mx)).sum();
        if sgg <= 0.0 || sgg.is_nan() {
            return Err(Error::Calibration {
                channel: k + 1,
                problem: CalibrationProblem::GoldenFlat,
            });
        }
        let slope = sgx / sgg;
        if !(slope > 0.0 && slope.is_finite()) {
            return Err(Error::Calibration {
                channel: k + 1,
                problem: CalibrationProblem::NotGrowing { slope },
            });
        }
        let dark = mx - slope * mg;
        let rss: f64 = g
            .iter()
            .zip(&x)
            .map(|(a, b)| (b - (dark + slope * a)).powi(2))
            .sum();
        out.dark.push(dark);
        out.gain.push(1.0 / slope);
        out.rms_residual.push((rss / m).sqrt());
    }
    Ok(out)
}
