//! Runs the derivation of `src/derive/` at compile time and writes `OUT_DIR/tables.rs`, the
//! `const` tables the no_std runtime includes.

#[allow(dead_code, unused_imports)]
#[path = "src/derive/mod.rs"]
mod derive;

use std::path::PathBuf;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=src/derive");
    let settings = derive::Settings::default();
    for id in derive::ObserverId::ALL {
        println!("cargo:rerun-if-changed={}", id.file());
    }
    let d = match derive::derive(&settings) {
        Ok(d) => d,
        Err(e) => fail(&format!("derivation failed: {e}")),
    };
    let inputs = vec![(
        settings.observer.file().to_string(),
        d.observer.sha256.clone(),
    )];
    let source = match derive::codegen::tables_rs(&d, &inputs) {
        Ok(s) => s,
        Err(e) => fail(&format!("code generation failed: {e}")),
    };
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    if let Err(e) = std::fs::write(out.join("tables.rs"), source) {
        fail(&format!("cannot write tables.rs: {e}"));
    }
}

fn fail(message: &str) -> ! {
    eprintln!("spectral-quadrature build: {message}");
    println!("cargo:warning=spectral-quadrature build: {message}");
    std::process::exit(1);
}
