//! The sets the user brings: shared sets folded for each light of `--illuminants`, and the sets of
//! a scene (`--scene`): catalogue names, its lights' shared sets, fixed wavelengths and sensors.
//! A set with a light folded in (or a sensor fitted under a light) is judged on the report's
//! reflectances under that light only; a set for radiances on every stimulus.

use std::path::Path;

use crate::tools::budget;
use crate::Error;
use spectral_quadrature_generator::scene::Scene;
use spectral_quadrature_generator::{self, shared, user, Derivation};
use spectral_quadrature_spectra::{
    builtin_illuminant, surfaces_under_lights, Curve, DataError, EvalSet, Spectra, Stimulus,
};

/// A light with the shared sets folded for it and the stimuli they are judged on.
pub type Folded = (Curve, Vec<EvalSet>, Vec<Stimulus>);

/// A set beside the report's own, with what it is judged on.
pub struct Extra {
    /// The set as measured (on radiances).
    pub set: EvalSet,
    /// The number of samples per pixel (a sensor's channels; otherwise the set's wavelengths).
    pub samples: usize,
    /// The stimuli it is judged on, and their description; `None`: every stimulus.
    pub judged_on: Option<(Vec<Stimulus>, String)>,
    /// The set timed for run time: the same N as the runtime's product.
    pub timing: EvalSet,
}

/// The shared sets of each size of `sizes` folded for each of `lights` (the user's), with the
/// stimuli they are judged on: `surfaces` under that light.
pub fn folded_for_lights(
    d: &Derivation,
    lights: &[Curve],
    surfaces: &[Curve],
    sizes: &[usize],
) -> Result<Vec<Folded>, Error> {
    lights
        .iter()
        .map(|l| {
            let sets = budget::shared_sets_sized(d, Some(l), sizes.iter().copied())?;
            let stimuli = surfaces_under_lights(surfaces, std::slice::from_ref(l));
            Ok((l.clone(), sets, stimuli))
        })
        .collect()
}

/// Section 4's rows for the folded sets of [`folded_for_lights`].
pub fn light_extras(folded: &[Folded], surfaces_from: &str) -> Vec<Extra> {
    folded
        .iter()
        .flat_map(|(l, sets, stimuli)| {
            sets.iter().map(move |s| Extra {
                set: s.clone(),
                samples: s.len(),
                judged_on: Some((stimuli.clone(), format!("{surfaces_from} under {}", l.name))),
                timing: s.clone(),
            })
        })
        .collect()
}

/// Whether two curves are the same light: equal at every nm of `range` (to 1e-9 of the larger).
fn same_curve(a: &Curve, b: &Curve, range: [f64; 2]) -> bool {
    let (lo, hi) = (range[0].ceil() as i64, range[1].floor() as i64);
    (lo..=hi).all(|nm| {
        let (x, y) = (a.at(nm as f64), b.at(nm as f64));
        (x - y).abs() <= 1e-9 * x.abs().max(y.abs())
    })
}

/// The sets of the scene at `path` (read with the report's derivation, whose settings the
/// scene must keep), each with what it is judged on. Sensor sets come with the plain
/// least-squares fit beside them (trained on the CIE test colour samples under the sensor's
/// light, or C for a sensor fitted for radiances).
///
/// A light of the scene's `[lights]` may also be one of `--illuminants` (`illuminants`, read
/// from `illuminants_from`): the same spectrum under the same name is one light, whose sets
/// section 4 measures once; a different spectrum under the same name is an error.
pub fn scene_extras(
    d: &Derivation,
    path: &Path,
    surfaces: &[Curve],
    surfaces_from: &str,
    illuminants: &[Curve],
    illuminants_from: &str,
) -> Result<Vec<Extra>, Error> {
    let label = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| DataError {
        file: label.clone(),
        line: 0,
        message: format!("cannot read the scene: {e}"),
    })?;
    let scene = Scene::parse(&label, &text, &d.settings.data_dir)?;
    if scene.settings != d.settings {
        return Err(spectral_quadrature_generator::Error::Settings(format!(
            "{label}: the report runs on the default settings ({}); the scene asks for {}",
            d.settings, scene.settings
        ))
        .into());
    }
    let (lights, fitted) = scene.resolve_user(d)?;
    crate::tools::warn_zeroed(
        "report",
        &spectral_quadrature_generator::scene::user_warnings(&lights, &fitted),
    );
    for l in &lights {
        if let Some(other) = illuminants.iter().find(|o| o.name == l.name) {
            if !same_curve(&l.curve, other, d.settings.range_nm) {
                let line = scene
                    .user
                    .lights
                    .iter()
                    .find(|s| s.name == l.name)
                    .map_or(0, |s| s.line as u64);
                return Err(DataError {
                    file: label.clone(),
                    line,
                    message: format!(
                        "the scene's light {} ({}) is not the light of that name in {illuminants_from}: name one of them otherwise",
                        l.name, l.file
                    ),
                }
                .into());
            }
        }
    }
    let light_curve = |name: &str| -> Result<Curve, Error> {
        if let Some(l) = lights.iter().find(|l| l.name == name) {
            return Ok(l.curve.clone());
        }
        Ok(builtin_illuminant(
            &d.settings.data_dir,
            name,
            d.settings.range_nm,
        )?)
    };
    let under = |light: &Curve| {
        Some((
            surfaces_under_lights(surfaces, std::slice::from_ref(light)),
            format!("{surfaces_from} under {}", light.name),
        ))
    };
    let mut out = Vec::new();
    for (name, line) in &scene.sets {
        let set = spectral_quadrature_generator::catalog::resolve_with(d, name, &lights)
            // At the scene's line (a misspelt light's message lists the scene's lights too).
            .map_err(|e| Error::from(e.at(&label, *line as u64)))?;
        let light = set.light.as_deref().map(light_curve).transpose()?;
        let e = shared::eval_on_radiance(d, &set, "scene", light.as_ref())?;
        let eval = Extra {
            samples: e.len(),
            timing: e.clone(),
            set: e,
            judged_on: light.as_ref().and_then(under),
        };
        out.push(eval);
    }
    let tcs = Spectra::builtin(&d.settings.data_dir, shared::TRAINING_FILE)
        .and_then(|s| s.curves(d.settings.range_nm))?;
    for f in fitted {
        let timing = EvalSet {
            name: f.name.clone(),
            family: "scene".into(),
            orders: None,
            wavelengths_nm: f.wavelengths_nm.clone(),
            xyz_weights: f.xyz_weights.clone(),
        };
        let light = f.light.as_deref().map(light_curve).transpose()?;
        let judged_on = light.as_ref().and_then(under);
        let channels = f.channels.clone();
        let samples = f.wavelengths_nm.len();
        out.push(Extra {
            samples,
            judged_on,
            timing: timing.clone(),
            set: EvalSet {
                family: "scene".into(),
                ..f.eval
            },
        });
        if let Some(channels) = channels {
            let fit_light = match &light {
                Some(l) => l.clone(),
                None => light_curve("C")?,
            };
            let name = format!("{} least squares", f.name);
            if let Some(ls) = user::least_squares(d, &name, &channels, &fit_light, &tcs)? {
                out.push(Extra {
                    samples,
                    judged_on: under(&fit_light),
                    timing,
                    set: ls,
                });
            }
        }
    }
    Ok(out)
}

/// A light group of a scene (`[groups.NAME]`), as section 9 judges it.
pub struct SceneGroup {
    /// The group's name.
    pub name: String,
    /// Its lights, in its order: the scene's own by name, else the built-in ones.
    pub lights: Vec<Curve>,
    /// Its number of wavelengths.
    pub n: usize,
    /// Whether the scene fits it on bounce forms (`training = "bounces"`).
    pub bounces: bool,
}

/// The light groups of the scene at `path` (read with the report's derivation): each one's
/// lights as curves, its size and training.
pub fn scene_groups(d: &Derivation, path: &Path) -> Result<Vec<SceneGroup>, Error> {
    let label = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| DataError {
        file: label.clone(),
        line: 0,
        message: format!("cannot read the scene: {e}"),
    })?;
    let scene = Scene::parse(&label, &text, &d.settings.data_dir)?;
    let (lights, _) = scene.resolve_user(d)?;
    scene
        .user
        .groups
        .iter()
        .map(|g| {
            let curves = g
                .lights
                .iter()
                .map(|n| match lights.iter().find(|l| &l.name == n) {
                    Some(l) => Ok(Curve {
                        name: n.clone(),
                        ..l.curve.clone()
                    }),
                    None => builtin_illuminant(&d.settings.data_dir, n, d.settings.range_nm)
                        .map_err(Error::from),
                })
                .collect::<Result<Vec<_>, Error>>()?;
            Ok(SceneGroup {
                name: g.name.clone(),
                lights: curves,
                n: g.wavelengths,
                bounces: g.training == shared::GroupTraining::Bounces,
            })
        })
        .collect()
}
