//! Resolving a parsed scene against a derivation ([`Scene::resolve`]): the catalog's sets by
//! name, the planner's choice, the user's lights, fixed and sensor sets, the sensors' white
//! references and calibrations, and the upsamplings: the [`Resolved`] scene that the emitters
//! bake.

use std::string::{String, ToString};
use std::vec::Vec;

use super::parse::{Extras, PlanRequest, Scene, DEFAULT_GROUPS, DEFAULT_SHARED_SETS};
use crate::base::error::Error;
use crate::derivation::derive::Derivation;
use crate::derivation::display::{DisplayMatrices, DisplaySpec};
use crate::derivation::sets::WavelengthSet;
use crate::scenes::calibration::{self, SensorTables};
use crate::scenes::catalog;
use crate::scenes::plan;
use crate::scenes::user::{fixed_set, sensor_set, Fitted, Sensor, UserLight};
use crate::shared::{cached_or_optimize_group, Group, GroupObjective, GroupTraining};
use crate::upsampling::{Baked, CacheEntry};
use spectral_quadrature_spectra::{
    builtin_illuminant, read_error, Curve, Negatives, Spectra, Stimulus, ZeroedNegatives,
};

/// A scene resolved against a derivation: the very sets and displays to bake.
#[derive(Debug, Clone, PartialEq)]
pub struct Resolved {
    /// The scene file, or `default`.
    pub file: String,
    /// Sets serving all three channels, baked at the top of `tables` (and folded for each
    /// display).
    pub colour_sets: Vec<WavelengthSet>,
    /// Per-channel rules as sets, baked in `tables::rules`.
    pub rule_sets: Vec<WavelengthSet>,
    /// Displays and their matrices.
    pub displays: Vec<(DisplaySpec, DisplayMatrices)>,
    /// Optional tables.
    pub(crate) extras: Extras,
    /// What the planner chose, as a sentence for the generated header, if it ran.
    pub planned: Option<String>,
    /// The upsamplings the scene asks for, baked.
    pub upsamplings: Vec<Baked>,
    /// The negative values read as 0 in the files the scene names (its lights, sensors and plan
    /// spectra), one entry per file that has any: the build prints each as a warning.
    pub warnings: Vec<ZeroedNegatives>,
    /// Each sensor's white reference and fitted calibration, baked in `tables::sensors`.
    pub(crate) sensors: Vec<SensorTables>,
    /// The samples of white of the scene's own sets, by name, where they are not all 1: a
    /// sensor set's readings of a reflectance of 1 under its light (or of a radiance of 1), at
    /// the luminance of a spectrum of constant 1 (`Fitted::white_samples`, from
    /// `calibration::white_readings`: for a sensor, the same numbers as its `SensorTables`'s
    /// `white`).
    pub white_samples: Vec<(String, Vec<f64>)>,
    /// The light groups, by name (`[groups.NAME]`, and the default scene's), baked in
    /// `tables::groups` for each display.
    pub groups: Vec<(String, Group)>,
    /// The scene's lights: the built-in ones its sets and groups fold in, then its own
    /// (`[lights]`), each named as the scene names it. `tables::lights` bakes each one's samples
    /// at each set for radiances.
    pub lights: Vec<Curve>,
}

impl Resolved {
    /// Fills [`Resolved::lights`]: the built-in lights the colour sets and groups fold in, in
    /// their order, then `own`, the scene's `[lights]`.
    fn with_lights(mut self, d: &Derivation, own: &[Curve]) -> Result<Resolved, Error> {
        let mut names: Vec<String> = Vec::new();
        let folded = self.colour_sets.iter().filter_map(|s| s.light.clone());
        let grouped = self
            .groups
            .iter()
            .flat_map(|(_, g)| g.members.iter().map(|m| m.light.clone()));
        for n in folded.chain(grouped) {
            if !names.contains(&n) && !own.iter().any(|l| l.name == n) {
                names.push(n);
            }
        }
        let range = d.settings.range_nm;
        for n in names {
            self.lights
                .push(builtin_illuminant(&d.settings.data_dir, &n, range)?);
        }
        self.lights.extend(own.iter().cloned());
        Ok(self)
    }

    /// The text of the upsampling cache (`data/upsampling_codes.csv`) for the scene's
    /// upsamplings: each one's codes and figures, with the fingerprint of its inputs. For the
    /// default scene after [`Scene::resolve_fitting`], this is the file the build reuses
    /// instead of fitting. The lights are looked up among the built-in ones: for a set that
    /// folds in a scene's own light, this is an error.
    pub fn upsampling_cache_file(&self, d: &Derivation) -> Result<String, Error> {
        Ok(crate::upsampling::write_cache(&self.upsampling_cache(d)?))
    }

    /// The entries of [`upsampling_cache_file`](Self::upsampling_cache_file), one per
    /// upsampling.
    pub(crate) fn upsampling_cache(&self, d: &Derivation) -> Result<Vec<CacheEntry>, Error> {
        crate::scenes::upsampling::cache_entries(
            d,
            &self.upsamplings,
            &self.colour_sets,
            &self.groups,
            &self.displays,
            &[],
        )
    }
}

impl Scene {
    /// Resolves the set names (and the plan, if any) against `d`, which must have been derived
    /// with [`Scene::settings`]. The displays' matrices are the derivation's
    /// ([`crate::Derivation::displays`]), with the scene's transfer functions. Errors name the
    /// file, the line and the valid choices ([`Error::At`]).
    ///
    /// The upsamplings come from the cache (`crate::upsampling::CACHE_FILE`) where their
    /// inputs match an entry; [`Scene::resolve_fitting`] fits every one instead.
    pub fn resolve(&self, d: &Derivation) -> Result<Resolved, Error> {
        self.resolve_with(d, true)
    }

    /// [`Scene::resolve`] with every upsampling fitted afresh, the cache ignored: what the
    /// cache's test compares it with, and what regenerates it.
    pub fn resolve_fitting(&self, d: &Derivation) -> Result<Resolved, Error> {
        self.resolve_with(d, false)
    }

    fn resolve_with(&self, d: &Derivation, cached: bool) -> Result<Resolved, Error> {
        let err = |line: usize| move |e: Error| e.at(&self.file, line as u64);
        let displays = self
            .displays
            .iter()
            .map(|spec| {
                d.display(&spec.name)
                    .map(|(_, m)| (spec.clone(), *m))
                    .map_err(err(0))
            })
            .collect::<Result<Vec<_>, _>>()?;
        if self.is_default {
            let rule_sets = catalog::rule_names(d)
                .iter()
                .map(|n| catalog::resolve(d, n).map_err(err(0)))
                .collect::<Result<Vec<_>, _>>()?;
            let mut colour_sets = d.table2.to_vec();
            for name in DEFAULT_SHARED_SETS {
                colour_sets.push(catalog::resolve(d, name).map_err(err(0))?);
            }
            let groups = self.default_groups(d).map_err(err(0))?;
            let upsamplings = self.upsamplings(d, &colour_sets, &groups, &displays, &[], cached)?;
            return Resolved {
                file: self.file.clone(),
                colour_sets,
                rule_sets,
                displays,
                extras: self.extras,
                planned: None,
                upsamplings,
                warnings: Vec::new(),
                sensors: Vec::new(),
                white_samples: Vec::new(),
                groups,
                lights: Vec::new(),
            }
            .with_lights(d, &[])
            .map_err(err(0));
        }
        let user = self.resolve_user(d)?;
        let lights = &user.0;
        let mut warnings = user_warnings(&user.0, &user.1);
        let mut names = self.sets.clone();
        let mut planned = None;
        if let Some(p) = &self.plan {
            let (name, sentence, zeroed) = p
                .resolve(d, &user.0, &user.1, self.negatives)
                .map_err(err(p.line))?;
            warnings.extend(zeroed);
            planned = Some(sentence);
            // A scene's own set is baked anyway.
            if !user.1.iter().any(|f| f.name == name) {
                names.push((name, p.line));
            }
        }
        let (mut colour_sets, mut rule_sets) = (Vec::new(), Vec::new());
        for (name, line) in &names {
            let set = catalog::resolve_with(d, name, lights).map_err(|e| Error::At {
                file: self.file.clone(),
                line: *line as u64,
                hint: Some(catalog::valid_choices_for(d, name, lights, &e)),
                error: std::boxed::Box::new(e),
            })?;
            let target = if catalog::is_single_channel(name) {
                &mut rule_sets
            } else {
                &mut colour_sets
            };
            if !target.iter().any(|s: &WavelengthSet| s.name == set.name) {
                target.push(set);
            }
        }
        let mut white_samples = Vec::new();
        for set in user.1 {
            if set.white_samples.iter().any(|&w| w != 1.0) {
                white_samples.push((set.name.clone(), set.white_samples.clone()));
            }
            colour_sets.push(set.wavelength_set(d));
        }
        let groups = self.resolve_groups(d, &user.0)?;
        let upsamplings = self.upsamplings(d, &colour_sets, &groups, &displays, &user.0, cached)?;
        let sensors = self.resolve_sensors(d, &user.0)?;
        Resolved {
            file: self.file.clone(),
            colour_sets,
            rule_sets,
            displays,
            extras: self.extras,
            planned,
            upsamplings,
            warnings,
            sensors,
            white_samples,
            groups,
            lights: Vec::new(),
        }
        .with_lights(
            d,
            &user.0.iter().map(|l| l.curve.clone()).collect::<Vec<_>>(),
        )
        .map_err(err(0))
    }

    /// The default scene's light groups ([`DEFAULT_GROUPS`]), nodes from the cache.
    fn default_groups(&self, d: &Derivation) -> Result<Vec<(String, Group)>, Error> {
        DEFAULT_GROUPS
            .iter()
            .map(|(name, lights, n)| {
                let curves = lights
                    .iter()
                    .map(|l| builtin_illuminant(&d.settings.data_dir, l, d.settings.range_nm))
                    .collect::<Result<Vec<_>, _>>()?;
                let group = cached_or_optimize_group(
                    d,
                    &curves,
                    *n,
                    GroupObjective::Mean,
                    GroupTraining::Reflectances,
                )?;
                Ok(((*name).to_string(), group))
            })
            .collect()
    }

    /// The scene's `[groups.*]`: each light read (a scene's own or built in), the nodes from
    /// the cache where it holds the group, else searched. Errors name the group's line.
    fn resolve_groups(
        &self,
        d: &Derivation,
        lights: &[UserLight],
    ) -> Result<Vec<(String, Group)>, Error> {
        let range = d.settings.range_nm;
        self.user
            .groups
            .iter()
            .map(|g| {
                let within = |e: Error| e.at(&self.file, g.line as u64);
                let curves =
                    g.lights
                        .iter()
                        .map(|n| match lights.iter().find(|l| &l.name == n) {
                            Some(l) => Ok(l.curve.clone()),
                            None => builtin_illuminant(&d.settings.data_dir, n, range)
                                .map_err(Error::from),
                        })
                        .collect::<Result<Vec<_>, Error>>()
                        .map_err(within)?;
                let group =
                    cached_or_optimize_group(d, &curves, g.wavelengths, g.objective, g.training)
                        .map_err(within)?;
                Ok((g.name.clone(), group))
            })
            .collect()
    }

    /// Bakes the `[upsampling]` table's maps, if any.
    fn upsamplings(
        &self,
        d: &Derivation,
        sets: &[WavelengthSet],
        groups: &[(String, Group)],
        displays: &[(DisplaySpec, DisplayMatrices)],
        lights: &[UserLight],
        cached: bool,
    ) -> Result<Vec<Baked>, Error> {
        match &self.upsampling {
            Some(u) => u.resolve(&self.file, d, sets, groups, displays, lights, cached),
            None => Ok(Vec::new()),
        }
    }

    /// Each sensor's white reference and, where the scene gives readings, the calibration
    /// fitted to them ([`calibration`]). Errors name the scene's line that declares the sensor,
    /// around the file's own error (which names its line).
    pub(crate) fn resolve_sensors(
        &self,
        d: &Derivation,
        lights: &[UserLight],
    ) -> Result<Vec<SensorTables>, Error> {
        let range = d.settings.range_nm;
        let mut out = Vec::new();
        for s in &self.user.sensors {
            let within = |e: Error| Error::At {
                file: self.file.clone(),
                line: s.line as u64,
                error: std::boxed::Box::new(e),
                hint: None,
            };
            let sensor = Sensor::read_with(
                &s.path,
                &s.path.display().to_string(),
                range,
                self.negatives,
            )
            .map_err(within)?;
            let light = match &s.light {
                None => None,
                Some(n) => match lights.iter().find(|l| &l.name == n) {
                    Some(l) => Some(l.curve.clone()),
                    None => Some(
                        builtin_illuminant(&d.settings.data_dir, n, range)
                            .map_err(|e| within(e.into()))?,
                    ),
                },
            };
            let white = calibration::white_readings(d, &sensor, light.as_ref()).map_err(within)?;
            let fitted = match &s.calibration {
                None => None,
                Some(path) => {
                    let label = path.display().to_string();
                    let text = std::fs::read_to_string(path)
                        .map_err(|e| within(read_error(&label, path, &e).into()))?;
                    let names: Vec<String> =
                        sensor.channels.iter().map(|c| c.name.clone()).collect();
                    let readings = calibration::Readings::parse(&label, &text, &names)
                        .map_err(|e| within(e.into()))?;
                    let chart = match &s.calibration_reflectances {
                        Some(r) => Spectra::read(r),
                        None => Spectra::builtin(
                            &d.settings.data_dir,
                            calibration::DEFAULT_REFLECTANCES,
                        ),
                    }
                    .map_err(|e| within(e.into()))?;
                    let reflectances = readings
                        .reflectances(&chart, range)
                        .map_err(|e| within(e.into()))?;
                    let golden =
                        calibration::golden_readings(d, &sensor, light.as_ref(), &reflectances)
                            .map_err(within)?;
                    let fit = calibration::fit(&golden, &readings.values)
                        .map_err(|e| within(e.at(&label, 0)))?;
                    Some(fit)
                }
            };
            out.push(SensorTables {
                name: s.name.clone(),
                white,
                calibration: fitted,
            });
        }
        Ok(out)
    }

    /// Reads the scene's lights and builds its fixed and sensor sets. Errors name the scene's
    /// line that declares the input, around the file's own error (which names its line). The
    /// negative values read as 0 in the lights' and sensors' files are in each
    /// [`UserLight::zeroed`] and [`Sensor::zeroed`] ([`user_warnings`] gathers them).
    pub fn resolve_user(&self, d: &Derivation) -> Result<(Vec<UserLight>, Vec<Fitted>), Error> {
        let range = d.settings.range_nm;
        let err = |line: usize| move |e: Error| e.at(&self.file, line as u64);
        let lights = self
            .user
            .lights
            .iter()
            .map(|l| {
                let label = l.path.display().to_string();
                UserLight::read(&l.name, &l.path, &label, range, self.negatives).map_err(|e| {
                    Error::At {
                        file: self.file.clone(),
                        line: l.line as u64,
                        error: std::boxed::Box::new(e),
                        hint: None,
                    }
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let curve = |name: &Option<String>, line: usize| -> Result<Option<Curve>, Error> {
            let Some(n) = name else {
                return Ok(None);
            };
            if let Some(l) = lights.iter().find(|l| &l.name == n) {
                return Ok(Some(l.curve.clone()));
            }
            builtin_illuminant(&d.settings.data_dir, n, range)
                .map(Some)
                .map_err(|e| err(line)(e.into()))
        };
        let mut sets = Vec::new();
        for f in &self.user.fixed {
            let light = curve(&f.light, f.line)?;
            sets.push(
                fixed_set(d, &f.name, &f.wavelengths_nm, light.as_ref()).map_err(err(f.line))?,
            );
        }
        for s in &self.user.sensors {
            let light = curve(&s.light, s.line)?;
            let label = s.path.display().to_string();
            let sensor =
                Sensor::read_with(&s.path, &label, range, self.negatives).map_err(|e| {
                    Error::At {
                        file: self.file.clone(),
                        line: s.line as u64,
                        error: std::boxed::Box::new(e),
                        hint: None,
                    }
                })?;
            sets.push(
                sensor_set(d, &s.name, &s.name, &sensor, light.as_ref()).map_err(err(s.line))?,
            );
        }
        Ok((lights, sets))
    }
}

impl PlanRequest {
    /// Runs the planner on the request's spectra: the chosen set's name and a sentence saying
    /// what it measured. For a scene with its own lights and sets, the planner also
    /// considers the shared sets ([`crate::plan::shared_sets`]: for radiances, and folded for
    /// the stimuli's light when they share one the scene knows) and the scene's fixed-wavelength
    /// and sensor sets.
    pub(crate) fn resolve(
        &self,
        d: &Derivation,
        lights: &[UserLight],
        own: &[Fitted],
        negatives: Negatives,
    ) -> Result<(String, String, Vec<ZeroedNegatives>), Error> {
        let (stimuli, zeroed) = self.stimuli(d.settings.range_nm, negatives)?;
        let mut extra = plan::shared_sets(d, &stimuli, lights)?;
        extra.extend(
            own.iter()
                .map(|f| (f.name.clone(), f.wavelengths_nm.len(), f.eval.clone())),
        );
        let plan = plan::plan(d, &stimuli, &extra, self.max_delta_e00, self.metric)?;
        let c = &plan.chosen;
        Ok((
            c.name.clone(),
            std::format!(
                "{} ({} wavelengths): ΔE00 mean {:.3}, max {:.3} on {} stimuli; budget: {} ΔE00 <= {}",
                c.name,
                c.wavelengths,
                c.mean_de00,
                c.max_de00,
                stimuli.len(),
                self.metric,
                self.max_delta_e00
            ),
            zeroed,
        ))
    }

    /// The stimuli the request names: surfaces under illuminants, or lights seen directly; and
    /// the negative values read as 0 in their files.
    pub(crate) fn stimuli(
        &self,
        range_nm: [f64; 2],
        negatives: Negatives,
    ) -> Result<(Vec<Stimulus>, Vec<ZeroedNegatives>), Error> {
        plan::stimuli_from_files(
            range_nm,
            self.reflectances.as_deref(),
            self.illuminants.as_deref(),
            self.emission.as_deref(),
            negatives,
        )
    }
}

/// The negative values read as 0 in the files of a scene's lights and sensors
/// ([`Scene::resolve_user`]'s results), one entry per file that has any, lights first.
pub fn user_warnings(lights: &[UserLight], sets: &[Fitted]) -> Vec<ZeroedNegatives> {
    let sensors = sets.iter().filter_map(|f| f.channels.as_ref());
    lights
        .iter()
        .filter_map(|l| l.zeroed.clone())
        .chain(sensors.filter_map(|s| s.zeroed.clone()))
        .collect()
}
