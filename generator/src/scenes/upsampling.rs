//! A scene's `[upsampling]` table: which colour sets, light groups and displays get an RGB → node
//! reflectance map baked ([`crate::upsampling`]), and on how fine a grid.
//!
//! ```toml
//! [upsampling]              # optional; the default scene has it for its KQ sets, every display
//! sets = ["KQ_C_8"]         # default: every colour set (sensor sets excepted) and light group
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
use crate::shared::Group;
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
    /// Set and light group names with their lines; `None`: every colour set of the scene that
    /// samples wavelengths, then every light group.
    pub sets: Option<Vec<(String, usize)>>,
    /// Display names with their lines; `None`: every display of the scene.
    pub displays: Option<Vec<(String, usize)>>,
    /// Grid points per axis.
    pub grid: usize,
    /// The line of the `[upsampling]` table.
    pub line: usize,
}

impl UpsamplingRequest {
    /// The default scene's: `sets` (its shared sets, Table 2's rows and its light group) on
    /// every display of the scene, on the default grid.
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

    /// Bakes the upsamplings the request names among the scene's resolved `sets`, `groups` and
    /// `displays`; `lights`: the scene's own lights, for sets and groups that fold one in. A
    /// light group's map takes RGB under the group's first light and is fitted for every light
    /// of the group ([`upsampling::bake_group`]). With `cached`, a map whose inputs' fingerprint
    /// matches an entry of the cache ([`upsampling::CACHE_FILE`]) is taken from it (without its
    /// [`Baked::fit`]); every other map is fitted. Errors name `file`, the line and the valid
    /// choices: a set, group or display the scene does not bake, a sensor set (its samples are
    /// not wavelengths); a malformed cache names its file and line.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn resolve(
        &self,
        file: &str,
        d: &Derivation,
        sets: &[WavelengthSet],
        groups: &[(String, Group)],
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
        let chosen: Vec<Chosen> = match &self.sets {
            None => candidates
                .iter()
                .map(|s| Chosen::Set(s))
                .chain(groups.iter().map(|(n, g)| Chosen::Group(n, g)))
                .collect(),
            Some(names) => names
                .iter()
                .map(|(name, line)| {
                    if let Some(s) = candidates.iter().find(|s| &s.name == name) {
                        return Ok(Chosen::Set(s));
                    }
                    if let Some((n, g)) = groups.iter().find(|(n, _)| n == name) {
                        return Ok(Chosen::Group(n, g));
                    }
                    Err(at(*line, not_among(name, &candidates, groups)))
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
        if chosen.is_empty() || chosen_displays.is_empty() {
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
        for choice in chosen {
            let set = match choice {
                Chosen::Set(set) => set,
                Chosen::Group(name, group) => {
                    let curves = group_lights(d, group, lights)?;
                    let members = member_sets(d, name, group);
                    for (spec, m) in &chosen_displays {
                        let in_group = |e: Error| Error::InSet {
                            name: name.to_string(),
                            error: std::boxed::Box::new(e),
                        };
                        if let Some(inputs) = &inputs {
                            let fp = inputs
                                .group_fingerprint(
                                    d,
                                    name,
                                    &members,
                                    (&spec.name, m),
                                    &curves,
                                    self.grid,
                                )
                                .map_err(in_group)?;
                            let hit = cache.iter().find(|e| {
                                e.set == *name
                                    && e.display == spec.name
                                    && e.fingerprint == fp
                                    && e.grid == self.grid
                                    && e.codes.first().map(Vec::len)
                                        == Some(group.wavelengths_nm.len())
                            });
                            if let Some(e) = hit {
                                out.push(e.baked_group(d, &members, m, &curves).map_err(in_group)?);
                                continue;
                            }
                        }
                        let training: &[Curve] = match &mut training {
                            Some(t) => t,
                            slot => slot.insert(upsampling::training(&d.settings.data_dir, range)?),
                        };
                        out.push(
                            upsampling::bake_group(
                                d,
                                name,
                                &members,
                                (&spec.name, m),
                                &curves,
                                training,
                                self.grid,
                            )
                            .map_err(in_group)?,
                        );
                    }
                    continue;
                }
            };
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

/// A set or a light group that `[upsampling]` names.
enum Chosen<'a> {
    Set(&'a WavelengthSet),
    Group(&'a str, &'a Group),
}

/// The error for an `[upsampling]` name that is neither a colour set nor a light group of the
/// scene: the valid names of each kind.
fn not_among(name: &str, candidates: &[&WavelengthSet], groups: &[(String, Group)]) -> String {
    let list = |v: Vec<&str>| {
        if v.is_empty() {
            "none".to_string()
        } else {
            v.join(", ")
        }
    };
    let sets = list(candidates.iter().map(|s| s.name.as_str()).collect());
    if groups.is_empty() {
        std::format!(
            "[upsampling] names {name}, which is neither among the scene's colour sets that sample wavelengths ({sets}) nor a light group (the scene has no [groups.*])"
        )
    } else {
        std::format!(
            "[upsampling] names {name}, which is neither among the scene's colour sets that sample wavelengths ({sets}) nor its light groups ({})",
            list(groups.iter().map(|(n, _)| n.as_str()).collect())
        )
    }
}

/// The curves of `group`'s lights, in its order: the scene's own by that name, else the
/// built-in ones.
fn group_lights(d: &Derivation, group: &Group, lights: &[UserLight]) -> Result<Vec<Curve>, Error> {
    group
        .members
        .iter()
        .map(|m| light_named(d, &m.light, lights))
        .collect()
}

/// The members of the light group `group` (called `name`) as sets, in its order.
fn member_sets(d: &Derivation, name: &str, group: &Group) -> Vec<WavelengthSet> {
    group
        .members
        .iter()
        .map(|m| m.wavelength_set(d, name, &group.wavelengths_nm))
        .collect()
}

/// The light called `name`: the scene's own by that name, else the built-in one.
fn light_named(d: &Derivation, name: &str, lights: &[UserLight]) -> Result<Curve, Error> {
    Ok(match lights.iter().find(|l| l.name == name) {
        Some(l) => {
            let mut c = l.curve.clone();
            c.name = name.to_string();
            c
        }
        None => builtin_illuminant(&d.settings.data_dir, name, d.settings.range_nm)?,
    })
}

/// The light `set` is upsampled under: its folded light (the scene's own by that name, else the
/// built-in one), or [`RADIANCE_REFERENCE_LIGHT`] for a set for radiances.
fn reference_light(
    d: &Derivation,
    set: &WavelengthSet,
    lights: &[UserLight],
) -> Result<Curve, Error> {
    light_named(
        d,
        set.light.as_deref().unwrap_or(RADIANCE_REFERENCE_LIGHT),
        lights,
    )
}

/// The cache entries ([`upsampling::CACHE_FILE`]) of `upsamplings`, baked for the scene whose
/// colour sets are `sets` and light groups `groups`, on `displays`, with the scene's own
/// `lights`: each one's codes and figures with the fingerprint of its inputs. Errors if an
/// upsampling's set, group or display is not among them.
pub(crate) fn cache_entries(
    d: &Derivation,
    upsamplings: &[Baked],
    sets: &[WavelengthSet],
    groups: &[(String, Group)],
    displays: &[(DisplaySpec, DisplayMatrices)],
    lights: &[UserLight],
) -> Result<Vec<CacheEntry>, Error> {
    let inputs = FitInputs::new(d)?;
    upsamplings
        .iter()
        .map(|b| {
            let (spec, m) = displays
                .iter()
                .find(|(s, _)| s.name == b.display)
                .ok_or_else(|| Error::UnknownDisplay {
                    name: b.display.clone(),
                    valid: displays.iter().map(|(s, _)| s.name.clone()).collect(),
                })?;
            if b.group_lights.is_some() {
                let (name, group) = groups.iter().find(|(n, _)| *n == b.set).ok_or_else(|| {
                    Error::Settings(std::format!(
                        "the upsampling's light group {} is not the scene's",
                        b.set
                    ))
                })?;
                let curves = group_lights(d, group, lights)?;
                let members = member_sets(d, name, group);
                let fp = inputs.group_fingerprint(
                    d,
                    name,
                    &members,
                    (&spec.name, m),
                    &curves,
                    b.grid,
                )?;
                return Ok(CacheEntry::new(b, fp));
            }
            let set = sets.iter().find(|s| s.name == b.set).ok_or_else(|| {
                Error::Settings(std::format!(
                    "the upsampling's set {} is not the scene's",
                    b.set
                ))
            })?;
            let light = reference_light(d, set, lights)?;
            let folded = set.light.is_some();
            let fp = inputs.fingerprint(set, (&spec.name, m), &light, folded, &b.encoding, b.grid);
            Ok(CacheEntry::new(b, fp))
        })
        .collect()
}
