//! What the runtime's `build.rs` does, as a library function: read the scene named by
//! [`SCENE_ENV`] (or take the default one), run the derivation on the runtime crate's `data/`,
//! and generate `tables.rs` and the shader snippets.

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::string::{String, ToString};
use std::vec::Vec;

use super::codegen::tables_rs;
use super::model::Model;
use super::shader::{snippet_of, Language};
use crate::base::error::Error;
use crate::base::files::{read_data, sha256_hex};
use crate::derivation::derive::derive;
use crate::scenes::catalog;
use crate::scenes::scene::{Resolved, Scene, SCENE_ENV};
use crate::shared;
use crate::upsampling;
use spectral_quadrature_spectra::{builtin_lights, DataError};

/// The generated sources and what Cargo must watch.
#[derive(Debug, Clone, PartialEq)]
pub struct Output {
    /// `tables.rs`: every constant the runtime needs, with a header naming the inputs.
    pub tables_rs: String,
    /// The WGSL snippet of the scene's sets and displays.
    pub wgsl: String,
    /// The GLSL snippet, the same items.
    pub glsl: String,
    /// More files for `OUT_DIR` that `tables.rs` includes: name and text (each upsampling's
    /// WGSL and GLSL).
    pub files: Vec<(String, String)>,
    /// Files and directories the output depends on (`cargo:rerun-if-changed`).
    pub rerun_if_changed: Vec<PathBuf>,
    /// What the build script should print as warnings (`cargo:warning`), one line each: the
    /// negative values read as 0 in each input file that has any
    /// ([`ZeroedNegatives`](spectral_quadrature_spectra::ZeroedNegatives)), the observer's first.
    pub warnings: Vec<String>,
}

/// Runs the whole generation for the crate at `crate_dir` (its `data/` holds the data files).
/// `scene`: the value of [`SCENE_ENV`], a path relative to `crate_dir` (or absolute); `None`
/// for the default scene. Errors name the file and line where a file is at fault (the scene,
/// a data file); a derivation the scene's settings do not allow is [`Error::At`] the scene.
///
/// ```no_run
/// // build.rs of the runtime crate
/// let crate_dir = std::path::PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").unwrap());
/// let scene = std::env::var_os(spectral_quadrature_generator::SCENE_ENV);
/// let out = spectral_quadrature_generator::generate(&crate_dir, scene.as_deref()).unwrap();
/// // ... print out.rerun_if_changed and out.warnings, write out.tables_rs, out.wgsl and
/// // out.glsl to OUT_DIR
/// ```
pub fn generate(crate_dir: &Path, scene: Option<&OsStr>) -> Result<Output, Error> {
    let data_dir = crate_dir.join("data");
    let mut rerun = std::vec![data_dir.clone()];
    let mut inputs = Vec::new();
    let scene = match scene {
        None => Scene::default_scene(&data_dir),
        Some(path) => {
            let path = crate_dir.join(Path::new(path));
            rerun.push(path.clone());
            // Inside the crate, name files relative to it, so the header does not depend on
            // where the crate lives.
            let label = relative_label(crate_dir, &path);
            let text = std::fs::read_to_string(&path).map_err(|e| DataError {
                file: label.clone(),
                line: 0,
                message: std::format!("cannot read the scene ({SCENE_ENV}): {e}"),
            })?;
            inputs.push((label.clone(), sha256_hex(text.as_bytes())));
            let mut scene = Scene::parse(&label, &text, &data_dir)?;
            // The scene's own relative paths were resolved against its label: make them
            // absolute again.
            let plan_files = scene.plan.as_mut().into_iter().flat_map(|p| {
                [&mut p.reflectances, &mut p.illuminants, &mut p.emission]
                    .into_iter()
                    .flatten()
            });
            let mut user = std::mem::take(&mut scene.user);
            for f in plan_files.chain(user.files_mut()) {
                *f = crate_dir.join(&*f);
                rerun.push(f.clone());
                if let Ok(bytes) = std::fs::read(&*f) {
                    inputs.push((relative_label(crate_dir, f), sha256_hex(&bytes)));
                }
            }
            scene.user = user;
            scene
        }
    };
    let d = derive(&scene.settings).map_err(|e| e.at(&scene.file, 0))?;
    inputs.insert(
        0,
        (
            scene.settings.observer.file().to_string(),
            d.observer.sha256.clone(),
        ),
    );
    let resolved = scene.resolve(&d)?;
    // Every data file a baked set was made from, after the observer and the scene's own files.
    let sets = resolved.colour_sets.iter().chain(&resolved.rule_sets);
    let own = scene.user.data_files();
    let upsampling = upsampling_input_files(&resolved);
    let groups = group_input_files(&resolved);
    let sets = sets.flat_map(|s| catalog::input_files(&s.name));
    for label in sets.chain(own).chain(upsampling).chain(groups) {
        if inputs.iter().any(|(l, _)| *l == label) {
            continue;
        }
        match read_data(&data_dir, &label) {
            Ok(bytes) => inputs.push((label, sha256_hex(&bytes))),
            // The caches are optional: without them the build searched and fitted.
            Err(_) if label == shared::CACHE_FILE || label == upsampling::CACHE_FILE => {}
            Err(e) => return Err(e.into()),
        }
    }
    // The scene's every constant, computed once: each target is a formatter of it.
    let model = Model::bake(&d, &inputs, &resolved)?;
    let tables_rs = tables_rs(&model);
    let wgsl = snippet_of(&model, Language::Wgsl)?;
    let glsl = snippet_of(&model, Language::Glsl)?;
    let warnings = d
        .observer
        .zeroed
        .iter()
        .chain(&resolved.warnings)
        .map(ToString::to_string)
        .collect();
    let files = super::upsampling::shader_files(&model);
    Ok(Output {
        tables_rs,
        wgsl,
        glsl,
        files,
        rerun_if_changed: rerun,
        warnings,
    })
}

/// The data files (labels `data/<file>`) the scene's upsamplings are made from: the training
/// reflectances, each built-in reference light, and the cache (`upsampling::CACHE_FILE`). Empty
/// when there are none.
fn upsampling_input_files(scene: &Resolved) -> Vec<String> {
    if scene.upsamplings.is_empty() {
        return Vec::new();
    }
    let mut files: Vec<String> = upsampling::TRAINING_FILES
        .iter()
        .map(|f| f.to_string())
        .collect();
    files.push(upsampling::CACHE_FILE.to_string());
    for u in &scene.upsamplings {
        let file = std::format!("data/illuminant_{}.csv", u.light);
        if builtin_lights().contains(&u.light.as_str()) && !files.contains(&file) {
            files.push(file);
        }
    }
    files
}

/// The data files the scene's light groups were made from: the kernel model's and the groups'
/// training reflectances, the node cache, and the built-in lights they fold in.
fn group_input_files(scene: &Resolved) -> Vec<String> {
    if scene.groups.is_empty() {
        return Vec::new();
    }
    let mut files = std::vec![shared::TRAINING_FILE.to_string()];
    files.extend(shared::GROUP_TRAINING_FILES.iter().map(|f| f.to_string()));
    files.push(shared::CACHE_FILE.to_string());
    let builtin = builtin_lights();
    for (_, g) in &scene.groups {
        for m in &g.members {
            if builtin.contains(&m.light.as_str()) {
                files.push(std::format!("data/illuminant_{}.csv", m.light));
            }
        }
    }
    files
}

fn relative_label(crate_dir: &Path, path: &Path) -> String {
    path.strip_prefix(crate_dir)
        .unwrap_or(path)
        .display()
        .to_string()
}
