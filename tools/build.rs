//! Where the runtime package's files are, for the tools to read at run time: its build script
//! says (`links = "spectral_quadrature"`, DEP_SPECTRAL_QUADRATURE_*), so the path is right for a
//! checkout (`cargo install --path tools`, `cargo run`) and for Cargo's copy of the published
//! package (`cargo install spectral-quadrature-tools`) alike. Nothing here reads the caller's
//! environment beyond what Cargo sets.

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    for (dep, ours) in [
        (
            "DEP_SPECTRAL_QUADRATURE_DATA_DIR",
            "SPECTRAL_QUADRATURE_TOOLS_DATA_DIR",
        ),
        (
            "DEP_SPECTRAL_QUADRATURE_CRATE_DIR",
            "SPECTRAL_QUADRATURE_TOOLS_CRATE_DIR",
        ),
    ] {
        let Some(value) = std::env::var_os(dep) else {
            panic!("{dep} is not set: the runtime's build script (spectral-quadrature) sets it");
        };
        let Some(value) = value.to_str() else {
            panic!("{dep} is not UTF-8: {value:?}");
        };
        println!("cargo:rustc-env={ours}={value}");
    }
}
