//! Scenes: what one application uses, so the build bakes only that.
//!
//! A scene is a TOML file whose path `build.rs` reads from the environment variable
//! [`SCENE_ENV`] (set it in `.cargo/config.toml`'s `[env]`, with `relative = true` so the path
//! is absolute). Without it the default scene applies: every set, display and table.
//!
//! ```toml
//! observer = "cie1931_2deg"        # optional; also range_nm = [380, 770], step_nm = 5
//! sets = ["TABLE2_ROW2", "A_3"]    # names from the catalog module
//! clamp_negatives = false          # optional: true reads every negative value in the files
//!                                  # below (lights, sensors, plan spectra) as 0
//! displays = ["SRGB"]              # SRGB, DISPLAY_P3, REC2020, MEYER_1987
//!
//! [transfer]                       # optional: another transfer function for a display
//! SRGB = "gamma 2.2"               # "srgb", "linear" or "gamma <γ>"
//!
//! [extras]                         # optional, all false by default
//! sensitivities = true             # GRID_NM and SENSITIVITIES
//! rules = true                     # the rule tables (A_RULES, ..., RULES, MAX_ORDER)
//! cct = true                       # PLANCKIAN_LOCUS: colour temperature and Duv from XYZ
//!
//! [plan]                           # optional: add the set the planner picks for a budget
//! max_delta_e00 = 1.0
//! metric = "mean"                  # or "max"
//! reflectances = "surfaces.csv"    # relative to the scene file
//! illuminants = "lamps.csv"        # or emission = "leds.csv"
//!
//! [lights]                         # optional: lights read from files (one column of power)
//! SHOP_LED = "shop_led.csv"        # KQ_SHOP_LED_<n> folds it in; light = "SHOP_LED" below
//!
//! [fixed.BINS8]                    # optional: the best weights for exactly these wavelengths
//! wavelengths_nm = [450, 550, 650]
//! light = "C"                      # optional: fold a light in (else radiances)
//!
//! [sensors.AS7341]                 # optional: the best matrix from a sensor's readings
//! file = "as7341.csv"              # wavelength, then one column per channel
//! light = "C"                      # optional: fit for reflectances under it (else radiances)
//! calibration = "device.csv"       # optional: a device's readings of known reflectances
//! calibration_reflectances = "chart.csv"  # optional: their spectra (else the ColorChecker)
//!
//! [upsampling]                     # optional: RGB → node reflectances (crate::upsampling)
//! sets = ["KQ_C_8"]                # default: every colour set (sensor sets excepted)
//! displays = ["SRGB"]              # default: every display of the scene
//! grid = 9                         # points per axis, 2..=65
//! ```
//!
//! `[fixed.*]` and `[sensors.*]` sets are baked whenever declared ([`crate::user`]).
//!
//! The spectra files a scene names follow the readers' rule for negative values
//! ([`crate::table::Negatives`]): rounding noise (at or above −1e-6 of the file's largest value)
//! is read as 0 and reported as a warning ([`Resolved::warnings`]); a more negative value is an
//! error naming the file, line and column, unless `clamp_negatives = true` reads it as 0 as well
//! (for measured data whose noise is larger; still reported).
//!
//! Every mistake (unknown key, set, observer or display, an undefined order, a bad budget) is
//! an error naming the file, the line and the valid choices.

use std::collections::BTreeMap;
use std::string::{String, ToString};
use std::vec::Vec;

use serde::Deserialize;
use toml::Spanned;

use super::calibration::{self, SensorTables};
use super::catalog;
use super::plan::{self, Metric};
use super::upsampling::{RawUpsampling, UpsamplingRequest};
use super::user::{self, fixed_set, sensor_set, Fitted, Sensor, UserLight};
use crate::base::error::{DataError, Error};
use crate::base::files::read_error;
use crate::base::table::{Negatives, ZeroedNegatives};
use crate::derivation::derive::Derivation;
use crate::derivation::display::{self, DisplayMatrices, DisplaySpec, Transfer};
use crate::derivation::evaluate::{self, builtin_lights, Curve, Spectra, Stimulus};
use crate::derivation::observer::ObserverId;
use crate::derivation::sets::WavelengthSet;
use crate::derivation::settings::Settings;
use crate::shared;
use crate::upsampling::{Baked, CacheEntry};

/// The environment variable naming the scene file.
pub const SCENE_ENV: &str = "SPECTRAL_QUADRATURE_SCENE";

/// The shared sets the default scene bakes besides Table 2's rows: kernel quadrature with
/// illuminant C folded in at 4, 6 and 8 wavelengths (Table 2's light), and with F11 at 6.
pub const DEFAULT_SHARED_SETS: [&str; 4] = ["KQ_C_4", "KQ_C_6", "KQ_C_8", "KQ_F11_6"];

/// The colour sets the default scene upsamples, on every display it bakes: the shared sets and
/// Table 2's rows.
const DEFAULT_UPSAMPLED_SETS: [&str; 6] = [
    "KQ_C_4",
    "KQ_C_6",
    "KQ_C_8",
    "KQ_F11_6",
    "TABLE2_ROW1",
    "TABLE2_ROW2",
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
    upsampling: Option<Spanned<RawUpsampling>>,
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

/// What a scene brings of the user's own: lights, fixed wavelengths, sensors.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct UserInputs {
    /// Lights read from files.
    pub lights: Vec<SceneLight>,
    /// Sets for fixed wavelengths, baked whenever declared.
    pub fixed: Vec<SceneFixed>,
    /// Sets for sensors, baked whenever declared.
    pub sensors: Vec<SceneSensor>,
}

impl UserInputs {
    /// The crate's data files the fixed and sensor sets are made from: the training
    /// reflectances of the prior, and the built-in lights they name.
    pub(crate) fn data_files(&self) -> Vec<String> {
        if self.fixed.is_empty() && self.sensors.is_empty() {
            return Vec::new();
        }
        let mut files = std::vec![shared::TRAINING_FILE.to_string()];
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
            .flatten();
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
pub struct Extras {
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
    pub extras: Extras,
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
    pub upsampling: Option<UpsamplingRequest>,
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
        let own = (raw.lights.take(), raw.fixed.take(), raw.sensors.take());
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
        if sets.is_empty() && plan.is_none() && user.fixed.is_empty() && user.sensors.is_empty() {
            return Err(err(
                0,
                std::format!(
                    "the scene names no sets (sets = [...], a [plan], [fixed.*] or [sensors.*]); valid forms: {}",
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
);

fn parse_user(
    (lights, fixed, sensors): OwnTables,
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
                std::format!("{n} is declared twice among [lights], [fixed.*] and [sensors.*]"),
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
    Ok(user)
}

/// `"srgb"`, `"linear"` or `"gamma <γ>"`.
pub(crate) fn parse_transfer(s: &str) -> Result<Transfer, Error> {
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
    pub extras: Extras,
    /// What the planner chose, as a sentence for the generated header, if it ran.
    pub planned: Option<String>,
    /// The upsamplings the scene asks for, baked.
    pub upsamplings: Vec<Baked>,
    /// The negative values read as 0 in the files the scene names (its lights, sensors and plan
    /// spectra), one entry per file that has any: the build prints each as a warning.
    pub warnings: Vec<ZeroedNegatives>,
    /// Each sensor's white reference and fitted calibration, baked in `tables::sensors`.
    pub sensors: Vec<SensorTables>,
    /// The samples of white of the scene's own sets, by name, where they are not all 1: a
    /// sensor set's readings of a reflectance of 1 under its light (or of a radiance of 1), at
    /// the luminance of a spectrum of constant 1 (`Fitted::white_samples`, from
    /// [`calibration::white_readings`]: for a sensor, the same numbers as its [`SensorTables`]'s
    /// `white`).
    pub white_samples: Vec<(String, Vec<f64>)>,
}

impl Resolved {
    /// The cache entries ([`crate::upsampling::CACHE_FILE`]) of the scene's upsamplings: each
    /// one's codes and figures, with the fingerprint of its inputs. For the default scene after
    /// [`Scene::resolve_fitting`], the text of the cache is
    /// [`write_cache`](crate::upsampling::write_cache) of these. The lights are looked up among
    /// the built-in ones: for a set that folds in a scene's own light, this is an error.
    pub fn upsampling_cache(&self, d: &Derivation) -> Result<Vec<CacheEntry>, Error> {
        super::upsampling::cache_entries(
            d,
            &self.upsamplings,
            &self.colour_sets,
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
    /// The upsamplings come from the cache ([`crate::upsampling::CACHE_FILE`]) where their
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
            let upsamplings = self.upsamplings(d, &colour_sets, &displays, &[], cached)?;
            return Ok(Resolved {
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
            });
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
                error: std::boxed::Box::new(e),
                hint: Some(catalog::valid_choices_for(d, name)),
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
        let upsamplings = self.upsamplings(d, &colour_sets, &displays, &user.0, cached)?;
        let sensors = self.resolve_sensors(d, &user.0)?;
        Ok(Resolved {
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
        })
    }

    /// Bakes the `[upsampling]` table's maps, if any.
    fn upsamplings(
        &self,
        d: &Derivation,
        sets: &[WavelengthSet],
        displays: &[(DisplaySpec, DisplayMatrices)],
        lights: &[UserLight],
        cached: bool,
    ) -> Result<Vec<Baked>, Error> {
        match &self.upsampling {
            Some(u) => u.resolve(&self.file, d, sets, displays, lights, cached),
            None => Ok(Vec::new()),
        }
    }

    /// Each sensor's white reference and, where the scene gives readings, the calibration
    /// fitted to them ([`calibration`]). Errors name the scene's line that declares the sensor,
    /// around the file's own error (which names its line).
    pub fn resolve_sensors(
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
                        evaluate::builtin_illuminant(&d.settings.data_dir, n, range)
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
                    let fit = calibration::fit(&golden, &readings.values).map_err(|message| {
                        within(Error::Data(DataError {
                            file: label.clone(),
                            line: 0,
                            message,
                        }))
                    })?;
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
            evaluate::builtin_illuminant(&d.settings.data_dir, n, range)
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
        let plan = plan::plan_with(d, &stimuli, self.max_delta_e00, self.metric, &extra)?;
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
