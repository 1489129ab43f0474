//! Bakes `OUT_DIR/tables.rs`, the shader snippets and the C header with the generator crate
//! (`spectral-quadrature-generator`), from this crate's `data/` and the scene named by the
//! environment variable `SPECTRAL_QUADRATURE_SCENE` (or the default scene). With the feature
//! `default-scene` the variable is not read: the default scene, whatever the environment says
//! (for the desk tools; see DESIGN.md, "The desk tools and the scene").

use std::path::PathBuf;

use spectral_quadrature_generator::{generate, SCENE_ENV};

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    // Armv7E-M (Cortex-M4, M4F, M7) has the DSP extension's dual 16-bit multiply-accumulate,
    // which the integer path uses through inline assembly; rustc sets no target feature for
    // it on these targets, so the target's name decides.
    println!("cargo::rustc-check-cfg=cfg(arm_dsp)");
    let target = std::env::var("TARGET").unwrap_or_default();
    if target.starts_with("thumbv7em-") {
        println!("cargo::rustc-cfg=arm_dsp");
    }
    // Armv6-M (Cortex-M0, M0+): a pixel's common path at N = 4 in inline assembly.
    println!("cargo::rustc-check-cfg=cfg(arm_v6m)");
    if target.starts_with("thumbv6m-") {
        println!("cargo::rustc-cfg=arm_v6m");
    }
    let crate_dir = PathBuf::from(
        std::env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"),
    );
    // For dependents' build scripts (`links`): DEP_SPECTRAL_QUADRATURE_CRATE_DIR and
    // DEP_SPECTRAL_QUADRATURE_DATA_DIR, where this package's files are however it was obtained
    // (a checkout, Cargo's copy of the published package). The desk tools read the data there.
    println!("cargo::metadata=crate_dir={}", crate_dir.display());
    println!(
        "cargo::metadata=data_dir={}",
        crate_dir.join("data").display()
    );
    let scene = if std::env::var_os("CARGO_FEATURE_DEFAULT_SCENE").is_some() {
        // The runtime's own code reads `tables` (the observer's matrices, the displays' transfer
        // curves), so a scene applies to the whole crate: an application whose results must not
        // depend on the environment (the desk tools) takes the default scene for all of it. The
        // variable is not tracked, so a change to it rebuilds nothing.
        if std::env::var_os(SCENE_ENV).is_some() {
            println!(
                "cargo:warning=spectral-quadrature build: the feature `default-scene` is on (the \
                 desk tools enable it): {SCENE_ENV} is not read, the tables are the default \
                 scene's"
            );
        }
        None
    } else {
        println!("cargo:rerun-if-env-changed={SCENE_ENV}");
        std::env::var_os(SCENE_ENV)
    };
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
    // Where the C header is (DEP_SPECTRAL_QUADRATURE_INCLUDE_DIR for dependents' build scripts,
    // as a C library's -sys crate says): the C tests compile it from there.
    println!("cargo::metadata=include_dir={}", dir.display());
    let files = [
        ("tables.rs", &out.tables_rs),
        ("shaders.wgsl", &out.wgsl),
        ("shaders.glsl", &out.glsl),
        ("spectral_quadrature.h", &out.c_header),
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
