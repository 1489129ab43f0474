//! On a microcontroller target: puts the memory map of the board it runs on where cortex-m-rt's
//! link.x finds it (QEMU's microbit for the Cortex-M0 build, mps2-an386 for the M4F), and links
//! with link.x.

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=microbit.x");
    println!("cargo:rerun-if-changed=mps2.x");
    if std::env::var("CARGO_CFG_TARGET_OS").as_deref() != Ok("none") {
        return;
    }
    let target = std::env::var("TARGET").expect("cargo sets TARGET");
    let map = if target.starts_with("thumbv6m") {
        "microbit.x"
    } else {
        "mps2.x"
    };
    let out = std::path::PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    std::fs::copy(map, out.join("memory.x")).expect("copy the memory map");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rustc-link-arg-bins=-Tlink.x");
}
