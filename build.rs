//! Runs the derivation of `src/derive/` at compile time and writes `OUT_DIR/tables.rs`, the
//! `const` tables the no_std runtime includes: those the scene named by the environment
//! variable `SPECTRAL_QUADRATURE_SCENE` asks for, or the default scene's.

#[allow(dead_code, unused_imports)]
#[path = "src/derive/mod.rs"]
mod derive;

use std::path::{Path, PathBuf};

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=src/derive");
    println!("cargo:rerun-if-changed=src/lab.rs");
    println!("cargo:rerun-if-env-changed={}", derive::scene::SCENE_ENV);
    for id in derive::ObserverId::ALL {
        println!("cargo:rerun-if-changed={}", id.file());
    }
    let manifest = PathBuf::from(
        std::env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"),
    );
    let mut inputs = Vec::new();
    let scene = match std::env::var_os(derive::scene::SCENE_ENV) {
        None => derive::scene::Scene::default_scene(),
        Some(path) => {
            // Relative paths are taken from this crate's directory; set the variable with
            // `relative = true` in .cargo/config.toml to give an absolute one.
            let path = manifest.join(Path::new(&path));
            println!("cargo:rerun-if-changed={}", path.display());
            // Inside the crate, name files relative to it, so the header does not depend on
            // where the crate lives.
            let label = path
                .strip_prefix(&manifest)
                .unwrap_or(&path)
                .display()
                .to_string();
            let text = std::fs::read_to_string(&path).unwrap_or_else(|e| {
                fail(&format!(
                    "{label}: cannot read the scene ({}): {e}",
                    derive::scene::SCENE_ENV
                ))
            });
            inputs.push((label.clone(), derive::sha256_hex(text.as_bytes())));
            let mut scene =
                derive::scene::Scene::parse(&label, &text).unwrap_or_else(|e| fail(&e.to_string()));
            // The scene's own relative paths were resolved against its label: make them
            // absolute again.
            if let Some(p) = scene.plan.as_mut() {
                for f in [&mut p.reflectances, &mut p.illuminants, &mut p.emission]
                    .into_iter()
                    .flatten()
                {
                    *f = manifest.join(&*f);
                }
            }
            if let Some(p) = &scene.plan {
                for f in [&p.reflectances, &p.illuminants, &p.emission]
                    .into_iter()
                    .flatten()
                {
                    println!("cargo:rerun-if-changed={}", f.display());
                    let f = manifest.join(f);
                    if let Ok(bytes) = std::fs::read(&f) {
                        let label = f
                            .strip_prefix(&manifest)
                            .unwrap_or(&f)
                            .display()
                            .to_string();
                        inputs.push((label, derive::sha256_hex(&bytes)));
                    }
                }
            }
            scene
        }
    };
    let d = derive::derive(&scene.settings)
        .unwrap_or_else(|e| fail(&format!("{}: derivation failed: {e}", scene.file)));
    inputs.insert(
        0,
        (
            scene.settings.observer.file().to_string(),
            d.observer.sha256.clone(),
        ),
    );
    let resolved = scene.resolve(&d).unwrap_or_else(|e| fail(&e.to_string()));
    let source = derive::codegen::tables_rs(&d, &inputs, &resolved)
        .unwrap_or_else(|e| fail(&format!("code generation failed: {e}")));
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    if let Err(e) = std::fs::write(out.join("tables.rs"), source) {
        fail(&format!("cannot write tables.rs: {e}"));
    }
    write_shaders(&out, &d, &resolved);
}

/// Writes the scene's shader snippets, `OUT_DIR/shaders.wgsl` and `OUT_DIR/shaders.glsl`,
/// which `tables::shaders` includes as strings.
fn write_shaders(out: &Path, d: &derive::Derivation, scene: &derive::scene::Resolved) {
    use derive::shader::{snippet, Language};
    for (lang, file) in [
        (Language::Wgsl, "shaders.wgsl"),
        (Language::Glsl, "shaders.glsl"),
    ] {
        let text = snippet(d, scene, lang)
            .unwrap_or_else(|e| fail(&format!("shader generation failed: {e}")));
        if let Err(e) = std::fs::write(out.join(file), text) {
            fail(&format!("cannot write {file}: {e}"));
        }
    }
}

fn fail(message: &str) -> ! {
    eprintln!("spectral-quadrature build: {message}");
    println!("cargo:warning=spectral-quadrature build: {message}");
    std::process::exit(1);
}
