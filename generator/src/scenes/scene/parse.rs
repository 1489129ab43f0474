//! Reading a scene file ([`Scene::parse`]) into the names and settings it holds, every mistake
//! an error naming the file and line; [`Scene::default_scene`] for no file.

use std::collections::BTreeMap;
use std::string::{String, ToString};
use std::vec::Vec;

use serde::Deserialize;
use toml::Spanned;

use crate::base::error::Error;
use crate::derivation::display::{self, DisplaySpec, Transfer};
use crate::derivation::observer::ObserverId;
use crate::derivation::settings::Settings;
use crate::scenes::calibration;
use crate::scenes::catalog;
use crate::scenes::plan::Metric;
use crate::scenes::upsampling::{RawUpsampling, UpsamplingRequest};
use crate::scenes::user;
use crate::shared;
use spectral_quadrature_spectra::{builtin_lights, DataError, Negatives};

/// The environment variable naming the scene file.
pub const SCENE_ENV: &str = "SPECTRAL_QUADRATURE_SCENE";

/// The shared sets the default scene bakes besides Table 2's rows: kernel quadrature with
/// illuminant C folded in at 4, 6 and 8 wavelengths (Table 2's light), and with F11 at 6.
pub(crate) const DEFAULT_SHARED_SETS: [&str; 4] = ["KQ_C_4", "KQ_C_6", "KQ_C_8", "KQ_F11_6"];

/// The light groups the default scene bakes, by name, lights and size: daylight, tungsten, a
/// spiky fluorescent and a phosphor LED sharing 8 wavelengths (nodes in the node cache,
/// `crate::shared::CACHED_GROUPS`).
pub(crate) const DEFAULT_GROUPS: [(&str, &[&str], usize); 1] =
    [("D65_A_F11_LED_B2_8", &["D65", "A", "F11", "LED_B2"], 8)];

/// The colour sets and light groups the default scene upsamples, on every display it bakes: the
/// shared sets, Table 2's rows and its light group (texels under its first light, D65).
const DEFAULT_UPSAMPLED_SETS: [&str; 7] = [
    "KQ_C_4",
    "KQ_C_6",
    "KQ_C_8",
    "KQ_F11_6",
    "TABLE2_ROW1",
    "TABLE2_ROW2",
    DEFAULT_GROUPS[0].0,
];

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    observer: Option<Spanned<String>>,
    range_nm: Option<Spanned<[f64; 2]>>,
    step_nm: Option<Spanned<f64>>,
    sets: Option<Vec<Spanned<String>>>,
    clamp_negatives: Option<bool>,
    displays: Option<Vec<Spanned<String>>>,
    transfer: Option<BTreeMap<Spanned<String>, Spanned<String>>>,
    extras: Option<Extras>,
    plan: Option<Spanned<RawPlan>>,
    lights: Option<BTreeMap<Spanned<String>, Spanned<String>>>,
    fixed: Option<BTreeMap<Spanned<String>, Spanned<RawFixed>>>,
    sensors: Option<BTreeMap<Spanned<String>, Spanned<RawSensor>>>,
    groups: Option<BTreeMap<Spanned<String>, Spanned<RawGroup>>>,
    upsampling: Option<Spanned<RawUpsampling>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawGroup {
    lights: Spanned<Vec<Spanned<String>>>,
    wavelengths: Spanned<i64>,
    objective: Option<Spanned<String>>,
    training: Option<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFixed {
    wavelengths_nm: Spanned<Vec<f64>>,
    light: Option<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSensor {
    file: Spanned<String>,
    light: Option<Spanned<String>>,
    calibration: Option<Spanned<String>>,
    calibration_reflectances: Option<Spanned<String>>,
}

/// A light a scene reads from a file (`[lights] NAME = "file.csv"`).
#[derive(Debug, Clone, PartialEq)]
pub struct SceneLight {
    /// Its name: `KQ_<NAME>_<n>`, and `light = "NAME"` in `[fixed.*]` and `[sensors.*]`.
    pub name: String,
    /// The file, relative to the scene's directory (or absolute).
    pub path: std::path::PathBuf,
    /// The line that names it.
    pub line: usize,
}

/// A set for wavelengths the user fixes (`[fixed.NAME]`).
#[derive(Debug, Clone, PartialEq)]
pub struct SceneFixed {
    /// The set's name.
    pub name: String,
    /// The wavelengths, nm.
    pub wavelengths_nm: Vec<f64>,
    /// The light folded in (a built-in illuminant or a `[lights]` name), or `None`: radiances.
    pub light: Option<String>,
    /// The line of its table.
    pub line: usize,
}

/// A set for a spectral sensor's readings (`[sensors.NAME]`).
#[derive(Debug, Clone, PartialEq)]
pub struct SceneSensor {
    /// The set's (and the sensor's) name.
    pub name: String,
    /// The channel sensitivities' CSV file, relative to the scene's directory (or absolute).
    pub path: std::path::PathBuf,
    /// The light the weights are fitted for (a built-in illuminant or a `[lights]` name), or
    /// `None`: radiances.
    pub light: Option<String>,
    /// The line of its table.
    pub line: usize,
    /// A device's readings of known reflectances under `light`, to fit its calibration to
    /// (`calibration = "readings.csv"`), relative to the scene's directory (or absolute).
    pub calibration: Option<std::path::PathBuf>,
    /// The reflectances the readings name (`calibration_reflectances`); `None`: the
    /// ColorChecker of the crate's data.
    pub calibration_reflectances: Option<std::path::PathBuf>,
}

/// A light group (`[groups.NAME]`): one node set shared by several lights, each light folded
/// into its own weights ([`crate::shared::GroupFit`]).
#[derive(Debug, Clone, PartialEq)]
pub struct SceneGroup {
    /// The group's name: its sets are `tables::groups::<NAME>_<DISPLAY>`.
    pub name: String,
    /// The lights (built-in illuminants or `[lights]` names), two or more, in the order the
    /// renderer's accumulators follow.
    pub lights: Vec<String>,
    /// The number of shared wavelengths.
    pub wavelengths: usize,
    /// What the node search minimises.
    pub objective: shared::GroupObjective,
    /// What the nodes and weights are fitted on.
    pub training: shared::GroupTraining,
    /// The line of its table.
    pub line: usize,
}

/// What a scene brings of the user's own: lights, fixed wavelengths, sensors.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct UserInputs {
    /// Lights read from files.
    pub lights: Vec<SceneLight>,
    /// Sets for fixed wavelengths, baked whenever declared.
    pub fixed: Vec<SceneFixed>,
    /// Sets for sensors, baked whenever declared.
    pub sensors: Vec<SceneSensor>,
    /// Light groups, baked whenever declared.
    pub groups: Vec<SceneGroup>,
}

impl UserInputs {
    /// The crate's data files the fixed and sensor sets are made from: the training
    /// reflectances of the prior, and the built-in lights they name.
    pub(crate) fn data_files(&self) -> Vec<String> {
        if self.fixed.is_empty() && self.sensors.is_empty() && self.groups.is_empty() {
            return Vec::new();
        }
        let mut files = std::vec![shared::TRAINING_FILE.to_string()];
        if !self.groups.is_empty() {
            for f in shared::GROUP_TRAINING_FILES {
                if !files.iter().any(|g| g == f) {
                    files.push(f.to_string());
                }
            }
        }
        let default_chart = self
            .sensors
            .iter()
            .any(|s| s.calibration.is_some() && s.calibration_reflectances.is_none());
        if default_chart {
            files.push(calibration::DEFAULT_REFLECTANCES.to_string());
        }
        let lights = self
            .fixed
            .iter()
            .map(|f| &f.light)
            .chain(self.sensors.iter().map(|s| &s.light))
            .flatten()
            .chain(self.groups.iter().flat_map(|g| &g.lights));
        for l in lights {
            if builtin_lights().contains(&l.as_str()) {
                let file = std::format!("data/illuminant_{l}.csv");
                if !files.contains(&file) {
                    files.push(file);
                }
            }
        }
        files
    }

    /// The files the scene's own inputs read (lights, then sensors and their calibrations).
    pub(crate) fn files_mut(&mut self) -> impl Iterator<Item = &mut std::path::PathBuf> {
        self.lights
            .iter_mut()
            .map(|l| &mut l.path)
            .chain(self.sensors.iter_mut().flat_map(|s| {
                core::iter::once(&mut s.path)
                    .chain(s.calibration.as_mut())
                    .chain(s.calibration_reflectances.as_mut())
            }))
    }
}

/// Prefixes of the catalogue's set names: a scene's own set may not start with one.
const CATALOG_PREFIXES: [&str; 8] = [
    "TABLE2_",
    "A_",
    "C1_",
    "C2_",
    "AC1C2_",
    "UNIFORM_",
    "KQ_",
    "INTERP_A_",
];

/// Optional tables.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(crate) struct Extras {
    /// `GRID_NM` and `SENSITIVITIES`.
    #[serde(default)]
    pub sensitivities: bool,
    /// The rule tables with every order's status (`A_RULES`, `C1_RULES`, `C2_RULES`, `RULES`,
    /// `MAX_ORDER`).
    #[serde(default)]
    pub rules: bool,
    /// The Planckian locus table (`PLANCKIAN_LOCUS`) for correlated colour temperature and Duv.
    #[serde(default)]
    pub cct: bool,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPlan {
    max_delta_e00: Spanned<f64>,
    metric: Option<Spanned<String>>,
    reflectances: Option<Spanned<String>>,
    illuminants: Option<Spanned<String>>,
    emission: Option<Spanned<String>>,
}

/// A ΔE budget for the planner to resolve at build time.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanRequest {
    /// The largest acceptable ΔE00.
    pub max_delta_e00: f64,
    /// Which statistic of ΔE00 must meet it.
    pub metric: Metric,
    /// Reflectance file (absolute, or relative to the scene file), if surfaces.
    pub reflectances: Option<std::path::PathBuf>,
    /// Illuminant file, if surfaces.
    pub illuminants: Option<std::path::PathBuf>,
    /// Emission file, if lights seen directly.
    pub emission: Option<std::path::PathBuf>,
    /// The line of the `[plan]` table, for errors.
    pub line: usize,
}

/// A parsed scene, before its sets are resolved against a derivation.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// The file it came from, or `default`.
    pub file: String,
    /// The derivation's settings (observer, range, step).
    pub settings: Settings,
    /// Set names with their lines.
    pub sets: Vec<(String, usize)>,
    /// Displays with their transfer functions.
    pub displays: Vec<DisplaySpec>,
    /// Optional tables.
    pub(crate) extras: Extras,
    /// A budget to plan for.
    pub plan: Option<PlanRequest>,
    /// The user's lights, fixed wavelengths and sensors.
    pub user: UserInputs,
    /// How the spectra files the scene names treat negative values: [`Negatives::Clamp`] with
    /// `clamp_negatives = true`, otherwise [`Negatives::Refuse`].
    pub negatives: Negatives,
    /// Whether this is the default scene (everything).
    pub is_default: bool,
    /// The `[upsampling]` table, if any.
    pub(crate) upsampling: Option<UpsamplingRequest>,
}

fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].matches('\n').count() + 1
}

impl Scene {
    /// The default scene: the default settings, every colour set and per-channel rule the
    /// default tables have always had, every display, and every extra.
    /// `data_dir`: where the derivation reads its data ([`Settings::data_dir`]).
    pub fn default_scene(data_dir: &std::path::Path) -> Scene {
        // The sets: Table 2's rows and DEFAULT_SHARED_SETS (see `resolve`).
        Scene {
            file: "default".into(),
            settings: Settings::new(data_dir),
            sets: Vec::new(),
            displays: display::standard_displays(),
            extras: Extras {
                sensitivities: true,
                rules: true,
                cct: true,
            },
            plan: None,
            user: UserInputs::default(),
            negatives: Negatives::Refuse,
            is_default: true,
            upsampling: Some(UpsamplingRequest::default_scene(&DEFAULT_UPSAMPLED_SETS)),
        }
    }

    /// Parses a scene file; the derivation will read its data from `data_dir`
    /// ([`Settings::data_dir`]). Errors name `file`, the line and the valid choices: a mistake
    /// in the file's form is [`Error::Data`]; an entry that names something that does not exist
    /// (a display, a transfer function, a metric, an observer's table) is [`Error::At`] around
    /// the typed error.
    pub fn parse(file: &str, text: &str, data_dir: &std::path::Path) -> Result<Scene, Error> {
        let err = |line: usize, message: String| {
            Error::Data(DataError {
                file: file.into(),
                line: line as u64,
                message,
            })
        };
        let within = |line: usize| move |e: Error| e.at(file, line as u64);
        let mut raw: RawScene = toml::from_str(text).map_err(|e| {
            let line = e.span().map_or(0, |s| line_of(text, s.start));
            err(line, e.message().trim().to_string())
        })?;
        let at = |span: core::ops::Range<usize>| line_of(text, span.start);
        let own = (
            raw.lights.take(),
            raw.fixed.take(),
            raw.sensors.take(),
            raw.groups.take(),
        );
        let mut settings = Settings::new(data_dir);
        if let Some(o) = &raw.observer {
            let id = ObserverId::from_name(o.get_ref()).ok_or_else(|| {
                err(
                    at(o.span()),
                    std::format!(
                        "unknown observer {:?}; valid: {}",
                        o.get_ref(),
                        ObserverId::ALL.map(|o| o.name()).join(", ")
                    ),
                )
            })?;
            settings = Settings::for_observer(id, data_dir).map_err(within(at(o.span())))?;
        }
        if let Some(r) = &raw.range_nm {
            settings.range_nm = *r.get_ref();
            let [lo, hi] = settings.range_nm;
            if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                return Err(err(
                    at(r.span()),
                    std::format!("range_nm = [{lo}, {hi}] is not a range"),
                ));
            }
        }
        if let Some(s) = &raw.step_nm {
            settings.step_nm = *s.get_ref();
            if !(settings.step_nm.is_finite() && settings.step_nm > 0.0) {
                return Err(err(
                    at(s.span()),
                    std::format!("step_nm = {} must be positive", settings.step_nm),
                ));
            }
        }
        let sets: Vec<(String, usize)> = raw
            .sets
            .unwrap_or_default()
            .into_iter()
            .map(|s| (s.get_ref().clone(), at(s.span())))
            .collect();
        let mut displays = Vec::new();
        for d in raw.displays.unwrap_or_default() {
            let spec = display::standard_display(d.get_ref()).map_err(within(at(d.span())))?;
            if !displays.iter().any(|s: &DisplaySpec| s.name == spec.name) {
                displays.push(spec);
            }
        }
        let used: Vec<String> = displays
            .iter()
            .map(|s: &DisplaySpec| s.name.clone())
            .collect();
        for (name, value) in raw.transfer.unwrap_or_default() {
            let line = at(name.span());
            let spec = displays.iter_mut().find(|s| &s.name == name.get_ref()).ok_or_else(|| {
                err(
                    line,
                    std::format!(
                        "[transfer] names display {:?}, which the scene does not use; its displays: {}",
                        name.get_ref(),
                        used.join(", ")
                    ),
                )
            })?;
            spec.transfer = parse_transfer(value.get_ref()).map_err(within(at(value.span())))?;
        }
        let plan = match raw.plan {
            None => None,
            Some(p) => {
                let line = at(p.span());
                let p = p.into_inner();
                let budget = *p.max_delta_e00.get_ref();
                if !(budget.is_finite() && budget > 0.0) {
                    return Err(err(
                        at(p.max_delta_e00.span()),
                        std::format!(
                            "bad budget: max_delta_e00 = {budget} must be a positive, finite ΔE00"
                        ),
                    ));
                }
                let metric = match &p.metric {
                    None => Metric::Mean,
                    Some(m) => m.get_ref().parse().map_err(within(at(m.span())))?,
                };
                let dir = std::path::Path::new(file)
                    .parent()
                    .unwrap_or(std::path::Path::new("."));
                let path = |s: &Option<Spanned<String>>| s.as_ref().map(|s| dir.join(s.get_ref()));
                let (reflectances, illuminants, emission) = (
                    path(&p.reflectances),
                    path(&p.illuminants),
                    path(&p.emission),
                );
                if emission.is_some() && (reflectances.is_some() || illuminants.is_some()) {
                    return Err(err(
                        line,
                        "[plan] takes either emission or reflectances/illuminants, not both".into(),
                    ));
                }
                if emission.is_none() && (reflectances.is_none() || illuminants.is_none()) {
                    return Err(err(
                        line,
                        "[plan] needs reflectances and illuminants, or emission".into(),
                    ));
                }
                Some(PlanRequest {
                    max_delta_e00: budget,
                    metric,
                    reflectances,
                    illuminants,
                    emission,
                    line,
                })
            }
        };
        let dir = std::path::Path::new(file)
            .parent()
            .unwrap_or(std::path::Path::new("."));
        let user = parse_user(own, dir, &at, &err)?;
        let upsampling = match raw.upsampling.take() {
            Some(u) => Some(UpsamplingRequest::parse(file, u, &at)?),
            None => None,
        };
        if sets.is_empty()
            && plan.is_none()
            && user.fixed.is_empty()
            && user.sensors.is_empty()
            && user.groups.is_empty()
        {
            return Err(err(
                0,
                std::format!(
                    "the scene names no sets (sets = [...], a [plan], [fixed.*], [sensors.*] or [groups.*]); valid forms: {}",
                    catalog::NAME_FORMS
                ),
            ));
        }
        Ok(Scene {
            file: file.into(),
            settings,
            sets,
            displays,
            extras: raw.extras.unwrap_or_default(),
            plan,
            user,
            negatives: if raw.clamp_negatives == Some(true) {
                Negatives::Clamp
            } else {
                Negatives::Refuse
            },
            is_default: false,
            upsampling,
        })
    }
}

/// The `[lights]`, `[fixed.*]` and `[sensors.*]` tables: names in upper snake case, each used
/// once across the three (and a light not named like a built-in one), scene sets not named like
/// catalogue sets, every light they use declared or built in.
type OwnTables = (
    Option<BTreeMap<Spanned<String>, Spanned<String>>>,
    Option<BTreeMap<Spanned<String>, Spanned<RawFixed>>>,
    Option<BTreeMap<Spanned<String>, Spanned<RawSensor>>>,
    Option<BTreeMap<Spanned<String>, Spanned<RawGroup>>>,
);

fn parse_user(
    (lights, fixed, sensors, groups): OwnTables,
    dir: &std::path::Path,
    at: &dyn Fn(core::ops::Range<usize>) -> usize,
    err: &dyn Fn(usize, String) -> Error,
) -> Result<UserInputs, Error> {
    let mut user = UserInputs::default();
    let mut seen: Vec<String> = Vec::new();
    let mut check_name = |name: &Spanned<String>, what: &str| -> Result<(), Error> {
        let (n, line) = (name.get_ref(), at(name.span()));
        if !user::is_const_name(n) {
            return Err(err(
                line,
                std::format!(
                    "{what} name {n:?} is not upper snake case (A-Z, 0-9, _; a letter first): it names generated consts"
                ),
            ));
        }
        if seen.contains(n) {
            return Err(err(
                line,
                std::format!(
                    "{n} is declared twice among [lights], [fixed.*], [sensors.*] and [groups.*]"
                ),
            ));
        }
        seen.push(n.clone());
        Ok(())
    };
    for (name, path) in lights.iter().flatten() {
        check_name(name, "light")?;
        if builtin_lights().contains(&name.get_ref().as_str()) {
            return Err(err(
                at(name.span()),
                std::format!(
                    "light {} is a built-in illuminant's name; give the file's light another name",
                    name.get_ref()
                ),
            ));
        }
        user.lights.push(SceneLight {
            name: name.get_ref().clone(),
            path: dir.join(path.get_ref()),
            line: at(name.span()),
        });
    }
    let light_names: Vec<String> = user.lights.iter().map(|l| l.name.clone()).collect();
    let check_light = |light: &Option<Spanned<String>>| -> Result<Option<String>, Error> {
        let Some(l) = light else {
            return Ok(None);
        };
        let n = l.get_ref();
        if light_names.contains(n) || builtin_lights().contains(&n.as_str()) {
            Ok(Some(n.clone()))
        } else {
            Err(err(
                at(l.span()),
                std::format!(
                    "unknown light {n:?}; valid: the scene's [lights] ({}) and the built-in illuminants ({})",
                    light_names.join(", "),
                    builtin_lights().join(", ")
                ),
            ))
        }
    };
    let check_set_name = |name: &Spanned<String>| -> Result<(), Error> {
        let n = name.get_ref();
        match CATALOG_PREFIXES.iter().find(|p| n.starts_with(*p)) {
            Some(p) => Err(err(
                at(name.span()),
                std::format!("{n}: a scene's own set may not start with {p}, a catalogue form"),
            )),
            None => Ok(()),
        }
    };
    for (name, table) in fixed.iter().flatten() {
        check_name(name, "set")?;
        check_set_name(name)?;
        let t = table.get_ref();
        user.fixed.push(SceneFixed {
            name: name.get_ref().clone(),
            wavelengths_nm: t.wavelengths_nm.get_ref().clone(),
            light: check_light(&t.light)?,
            line: at(name.span()),
        });
    }
    for (name, table) in sensors.iter().flatten() {
        check_name(name, "sensor")?;
        check_set_name(name)?;
        let t = table.get_ref();
        let light = check_light(&t.light)?;
        if let (Some(c), None) = (&t.calibration, &light) {
            return Err(err(
                at(c.span()),
                std::format!(
                    "calibration: the readings are of reflectances under the sensor's light; give [sensors.{}] a light",
                    name.get_ref()
                ),
            ));
        }
        if let (Some(r), None) = (&t.calibration_reflectances, &t.calibration) {
            return Err(err(
                at(r.span()),
                "calibration_reflectances without calibration: there are no readings to fit".into(),
            ));
        }
        user.sensors.push(SceneSensor {
            name: name.get_ref().clone(),
            path: dir.join(t.file.get_ref()),
            light,
            line: at(name.span()),
            calibration: t.calibration.as_ref().map(|c| dir.join(c.get_ref())),
            calibration_reflectances: t
                .calibration_reflectances
                .as_ref()
                .map(|r| dir.join(r.get_ref())),
        });
    }
    for (name, table) in groups.iter().flatten() {
        check_name(name, "group")?;
        check_set_name(name)?;
        let t = table.get_ref();
        let mut group_lights: Vec<String> = Vec::new();
        for l in t.lights.get_ref() {
            let light = check_light(&Some(l.clone()))?.unwrap_or_default();
            if group_lights.contains(&light) {
                return Err(err(
                    at(l.span()),
                    std::format!("{light} is named twice in [groups.{}]", name.get_ref()),
                ));
            }
            group_lights.push(light);
        }
        let n = *t.wavelengths.get_ref();
        if !shared::GROUP_SIZES.contains(&n) {
            return Err(err(
                at(t.wavelengths.span()),
                std::format!(
                    "wavelengths = {n}; a light group has {} to {}",
                    shared::GROUP_SIZES.start(),
                    shared::GROUP_SIZES.end()
                ),
            ));
        }
        let objective = match &t.objective {
            None => shared::GroupObjective::Mean,
            Some(o) => match o.get_ref().as_str() {
                "mean" => shared::GroupObjective::Mean,
                "worst" => shared::GroupObjective::Worst,
                other => {
                    return Err(err(
                        at(o.span()),
                        std::format!("objective = {other:?}; valid: \"mean\", \"worst\""),
                    ))
                }
            },
        };
        let training = match &t.training {
            None => shared::GroupTraining::Reflectances,
            Some(o) => match o.get_ref().as_str() {
                "reflectances" => shared::GroupTraining::Reflectances,
                "bounces" => shared::GroupTraining::Bounces,
                other => {
                    return Err(err(
                        at(o.span()),
                        std::format!("training = {other:?}; valid: \"reflectances\", \"bounces\""),
                    ))
                }
            },
        };
        // One light fitted on reflectances as they are is its folded set; fitted on their bounce
        // forms it is a set of its own.
        let fewest = match training {
            shared::GroupTraining::Bounces => 1,
            _ => 2,
        };
        if group_lights.len() < fewest {
            return Err(err(
                at(t.lights.span()),
                std::format!(
                    "[groups.{}] has {} light(s): a group has two or more, or one with training = \"bounces\" (one light fitted on reflectances is its folded set, KQ_<light>_<n>)",
                    name.get_ref(),
                    group_lights.len()
                ),
            ));
        }
        user.groups.push(SceneGroup {
            name: name.get_ref().clone(),
            lights: group_lights,
            wavelengths: n as usize,
            objective,
            training,
            line: at(name.span()),
        });
    }
    Ok(user)
}

/// `"srgb"`, `"linear"` or `"gamma <γ>"`.
fn parse_transfer(s: &str) -> Result<Transfer, Error> {
    let t = s.trim();
    match t {
        "srgb" => Ok(Transfer::Srgb),
        "linear" => Ok(Transfer::Linear),
        _ => {
            let g = t
                .strip_prefix("gamma")
                .map(str::trim)
                .and_then(|g| g.parse::<f64>().ok())
                .filter(|g| g.is_finite() && *g > 0.0)
                .ok_or_else(|| Error::Transfer(s.into()))?;
            Ok(Transfer::Gamma(g))
        }
    }
}
