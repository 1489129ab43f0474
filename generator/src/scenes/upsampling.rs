//! A scene's `[upsampling]` table: which colour sets and displays get an RGB → node reflectance
//! map baked ([`crate::upsampling`]), and on how fine a grid.
//!
//! ```toml
//! [upsampling]              # optional; the default scene has it for its KQ sets, every display
//! sets = ["KQ_C_8"]         # default: every colour set of the scene (sensor sets excepted)
//! displays = ["SRGB"]       # default: every display of the scene
//! grid = 9                  # points per axis, 2..=65 (default 9)
//! ```

use std::string::{String, ToString};
use std::vec::Vec;

use serde::Deserialize;
use toml::Spanned;

use super::user::UserLight;
use crate::base::error::Error;
use crate::derivation::derive::Derivation;
use crate::derivation::display::{DisplayMatrices, DisplaySpec};
use crate::derivation::sets::WavelengthSet;
use crate::upsampling::{
    self, Baked, CacheEntry, FitInputs, DEFAULT_GRID, GRID_SIZES, RADIANCE_REFERENCE_LIGHT,
};
use spectral_quadrature_spectra::{builtin_illuminant, Curve, DataError};

/// The `[upsampling]` table as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawUpsampling {
    sets: Option<Vec<Spanned<String>>>,
    displays: Option<Vec<Spanned<String>>>,
    grid: Option<Spanned<i64>>,
}

/// What a scene asks to upsample.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct UpsamplingRequest {
    /// Set names with their lines; `None`: every colour set of the scene that samples
    /// wavelengths.
    pub sets: Option<Vec<(String, usize)>>,
    /// Display names with their lines; `None`: every display of the scene.
    pub displays: Option<Vec<(String, usize)>>,
    /// Grid points per axis.
    pub grid: usize,
    /// The line of the `[upsampling]` table.
    pub line: usize,
}

impl UpsamplingRequest {
    /// The default scene's: `sets` (its shared sets and Table 2's rows) on every display of
    /// the scene, on the default grid.
    pub(crate) fn default_scene(sets: &[&str]) -> UpsamplingRequest {
        UpsamplingRequest {
            sets: Some(sets.iter().map(|s| (s.to_string(), 0)).collect()),
            displays: None,
            grid: DEFAULT_GRID,
            line: 0,
        }
    }

    /// Checks the table's form: a grid size in [`GRID_SIZES`]. Errors name `file` and the line.
    pub(crate) fn parse(
        file: &str,
        raw: Spanned<RawUpsampling>,
        at: &dyn Fn(core::ops::Range<usize>) -> usize,
    ) -> Result<UpsamplingRequest, Error> {
        let line = at(raw.span());
        let raw = raw.into_inner();
        let grid = match raw.grid {
            None => DEFAULT_GRID,
            Some(g) => {
                let v = *g.get_ref();
                usize::try_from(v)
                    .ok()
                    .filter(|v| GRID_SIZES.contains(v))
                    .ok_or_else(|| {
                        Error::Data(DataError {
                            file: file.into(),
                            line: at(g.span()) as u64,
                            message: std::format!(
                                "[upsampling] grid = {v}: a grid has {} to {} points per axis",
                                GRID_SIZES.start(),
                                GRID_SIZES.end()
                            ),
                        })
                    })?
            }
        };
        let names = |v: Option<Vec<Spanned<String>>>| {
            v.map(|v| {
                v.into_iter()
                    .map(|s| (s.get_ref().clone(), at(s.span())))
                    .collect()
            })
        };
        Ok(UpsamplingRequest {
            sets: names(raw.sets),
            displays: names(raw.displays),
            grid,
            line,
        })
    }

    /// Bakes the upsamplings the request names among the scene's resolved `sets` and
    /// `displays`; `lights`: the scene's own lights, for sets that fold one in. With `cached`, a
    /// map whose inputs' fingerprint matches an entry of the cache ([`upsampling::CACHE_FILE`])
    /// is taken from it (without its [`Baked::fit`]); every other map is fitted. Errors name
    /// `file`, the line and the valid choices: a set or display the scene does not bake, a
    /// sensor set (its samples are not wavelengths); a malformed cache names its file and line.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn resolve(
        &self,
        file: &str,
        d: &Derivation,
        sets: &[WavelengthSet],
        displays: &[(DisplaySpec, DisplayMatrices)],
        lights: &[UserLight],
        cached: bool,
    ) -> Result<Vec<Baked>, Error> {
        let at = |line: usize, message: String| {
            Error::Data(DataError {
                file: file.into(),
                line: line as u64,
                message,
            })
        };
        let candidates: Vec<&WavelengthSet> = sets.iter().filter(|s| s.sensor.is_none()).collect();
        let chosen_sets: Vec<&WavelengthSet> = match &self.sets {
            None => candidates.clone(),
            Some(names) => names
                .iter()
                .map(|(name, line)| {
                    candidates.iter().copied().find(|s| &s.name == name).ok_or_else(|| {
                        at(
                            *line,
                            std::format!(
                                "[upsampling] names set {name}, which is not among the scene's colour sets that sample wavelengths: {}",
                                candidates.iter().map(|s| s.name.as_str()).collect::<Vec<_>>().join(", ")
                            ),
                        )
                    })
                })
                .collect::<Result<_, _>>()?,
        };
        let chosen_displays: Vec<&(DisplaySpec, DisplayMatrices)> = match &self.displays {
            None => displays.iter().collect(),
            Some(names) => names
                .iter()
                .map(|(name, line)| {
                    displays.iter().find(|(s, _)| &s.name == name).ok_or_else(|| {
                        at(
                            *line,
                            std::format!(
                                "[upsampling] names display {name}, which the scene does not use; its displays: {}",
                                displays.iter().map(|(s, _)| s.name.as_str()).collect::<Vec<_>>().join(", ")
                            ),
                        )
                    })
                })
                .collect::<Result<_, _>>()?,
        };
        if chosen_sets.is_empty() || chosen_displays.is_empty() {
            return Ok(Vec::new());
        }
        let range = d.settings.range_nm;
        let cache = if cached {
            upsampling::read_cache(&d.settings.data_dir)?
        } else {
            Vec::new()
        };
        let inputs = if cache.is_empty() {
            None
        } else {
            Some(FitInputs::new(d)?)
        };
        // Read only if some map is fitted.
        let mut training: Option<Vec<Curve>> = None;
        let mut out = Vec::new();
        // The training colours under each (light, display), computed once for all sets.
        let mut training_rgb: Vec<(String, String, Vec<[f64; 3]>)> = Vec::new();
        for set in chosen_sets {
            let light = reference_light(d, set, lights)?;
            let folded = set.light.is_some();
            for (spec, m) in &chosen_displays {
                let in_set = |e: Error| Error::InSet {
                    name: set.name.clone(),
                    error: std::boxed::Box::new(e),
                };
                if let Some(inputs) = &inputs {
                    let at_nodes: Vec<f64> =
                        set.wavelengths_nm.iter().map(|&l| light.at(l)).collect();
                    let w = upsampling::encoding(d, set, m, (!folded).then_some(&at_nodes[..]))
                        .map_err(in_set)?;
                    let fp =
                        inputs.fingerprint(set, (&spec.name, m), &light, folded, &w, self.grid);
                    let hit = cache.iter().find(|e| {
                        e.set == set.name
                            && e.display == spec.name
                            && e.fingerprint == fp
                            && e.grid == self.grid
                            && e.codes.first().map(Vec::len) == Some(set.len())
                    });
                    if let Some(e) = hit {
                        out.push(e.baked(set, &light.name, w));
                        continue;
                    }
                }
                let training: &[Curve] = match &mut training {
                    Some(t) => t,
                    slot => slot.insert(upsampling::training(&d.settings.data_dir, range)?),
                };
                let known = training_rgb
                    .iter()
                    .position(|(l, s, _)| *l == light.name && *s == spec.name);
                let k = match known {
                    Some(k) => k,
                    None => {
                        let rgb = upsampling::exact_rgb(d, m, &light, training).map_err(in_set)?;
                        training_rgb.push((light.name.clone(), spec.name.clone(), rgb));
                        training_rgb.len() - 1
                    }
                };
                let baked = upsampling::bake_with(
                    d,
                    set,
                    (&spec.name, m),
                    &light,
                    folded,
                    training,
                    &training_rgb[k].2,
                    self.grid,
                )
                .map_err(in_set)?;
                out.push(baked);
            }
        }
        Ok(out)
    }
}

/// The light `set` is upsampled under: its folded light (the scene's own by that name, else the
/// built-in one), or [`RADIANCE_REFERENCE_LIGHT`] for a set for radiances.
fn reference_light(
    d: &Derivation,
    set: &WavelengthSet,
    lights: &[UserLight],
) -> Result<Curve, Error> {
    let name = set.light.as_deref().unwrap_or(RADIANCE_REFERENCE_LIGHT);
    Ok(match lights.iter().find(|l| l.name == name) {
        Some(l) => {
            let mut c = l.curve.clone();
            c.name = name.to_string();
            c
        }
        None => builtin_illuminant(&d.settings.data_dir, name, d.settings.range_nm)?,
    })
}

/// The cache entries ([`upsampling::CACHE_FILE`]) of `upsamplings`, baked for the scene whose
/// colour sets are `sets`, on `displays`, with the scene's own `lights`: each one's codes and
/// figures with the fingerprint of its inputs. Errors if an upsampling's set or display is not
/// among them.
pub(crate) fn cache_entries(
    d: &Derivation,
    upsamplings: &[Baked],
    sets: &[WavelengthSet],
    displays: &[(DisplaySpec, DisplayMatrices)],
    lights: &[UserLight],
) -> Result<Vec<CacheEntry>, Error> {
    let inputs = FitInputs::new(d)?;
    upsamplings
        .iter()
        .map(|b| {
            let set = sets.iter().find(|s| s.name == b.set).ok_or_else(|| {
                Error::Settings(std::format!(
                    "the upsampling's set {} is not the scene's",
                    b.set
                ))
            })?;
            let (spec, m) = displays
                .iter()
                .find(|(s, _)| s.name == b.display)
                .ok_or_else(|| Error::UnknownDisplay {
                    name: b.display.clone(),
                    valid: displays.iter().map(|(s, _)| s.name.clone()).collect(),
                })?;
            let light = reference_light(d, set, lights)?;
            let folded = set.light.is_some();
            let fp = inputs.fingerprint(set, (&spec.name, m), &light, folded, &b.encoding, b.grid);
            Ok(CacheEntry::new(b, fp))
        })
        .collect()
}
