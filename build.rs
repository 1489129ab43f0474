//! Bakes `OUT_DIR/tables.rs` and the shader snippets with the generator crate
//! (`spectral-quadrature-build`), from this crate's `data/` and the scene named by the
//! environment variable `SPECTRAL_QUADRATURE_SCENE` (or the default scene).

use std::path::PathBuf;

use spectral_quadrature_build::{generate, SCENE_ENV};

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed={SCENE_ENV}");
    // Armv7E-M (Cortex-M4, M4F, M7) has the DSP extension's dual 16-bit multiply-accumulate,
    // which the integer path uses through inline assembly; rustc sets no target feature for
    // it on these targets, so the target's name decides.
    println!("cargo::rustc-check-cfg=cfg(arm_dsp)");
    let target = std::env::var("TARGET").unwrap_or_default();
    if target.starts_with("thumbv7em-") {
        println!("cargo::rustc-cfg=arm_dsp");
    }
    let crate_dir = PathBuf::from(
        std::env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"),
    );
    let scene = std::env::var_os(SCENE_ENV);
    let out = generate(&crate_dir, scene.as_deref()).unwrap_or_else(|e| fail(&e.to_string()));
    for path in &out.rerun_if_changed {
        println!("cargo:rerun-if-changed={}", path.display());
    }
    // Negative values read as 0 in an input file (rounding noise, or clamped where the scene
    // asks): said once per file, so that nothing changes silently.
    for warning in &out.warnings {
        println!("cargo:warning=spectral-quadrature build: {warning}");
    }
    let dir = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    let files = [
        ("tables.rs", &out.tables_rs),
        ("shaders.wgsl", &out.wgsl),
        ("shaders.glsl", &out.glsl),
    ];
    let more = out.files.iter().map(|(f, t)| (f.as_str(), t));
    for (file, text) in files.into_iter().chain(more) {
        if let Err(e) = std::fs::write(dir.join(file), text) {
            fail(&format!("cannot write {file}: {e}"));
        }
    }
}

fn fail(message: &str) -> ! {
    eprintln!("spectral-quadrature build: {message}");
    println!("cargo:warning=spectral-quadrature build: {message}");
    std::process::exit(1);
}
