//! Compiles the runtime's C header for the tests: a harness that includes it and lists every
//! `static inline` function it defines by name (`sqt_find`), so that the tests can call each one
//! through a pointer and compare it with the runtime. Warnings are errors (`-Wall -Wextra
//! -pedantic`, C99). Where the CPU has FMA the harness is built with `-mfma` in GNU mode, where
//! GCC contracts `a * b + c` by default: the header's own guard against contraction is what keeps
//! the bits.

use std::fmt::Write as _;
use std::path::PathBuf;

fn main() {
    let include = PathBuf::from(
        std::env::var_os("DEP_SPECTRAL_QUADRATURE_INCLUDE_DIR")
            .expect("the runtime's build script says where the header is"),
    );
    let header_path = include.join("spectral_quadrature.h");
    println!("cargo:rerun-if-changed={}", header_path.display());
    println!("cargo:rerun-if-changed=build.rs");
    let header = std::fs::read_to_string(&header_path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", header_path.display()));
    // Every function the header defines: `static inline <type> sq_<name>(`.
    let mut names = Vec::new();
    for line in header.lines() {
        let Some(rest) = line.strip_prefix("static inline ") else {
            continue;
        };
        let Some(at) = rest.find("sq_") else { continue };
        let Some(end) = rest[at..].find('(') else {
            continue;
        };
        names.push(rest[at..at + end].to_string());
    }
    assert!(names.len() > 20, "{} functions in the header", names.len());
    // Every 8-bit curve on the integer scale (`static const uint64_t sq_<name>_q63[256]`), which
    // the functions for sets made at run time take as an argument.
    let tables: Vec<&str> = header
        .lines()
        .filter_map(|l| l.strip_prefix("static const uint64_t "))
        .filter_map(|l| l.strip_suffix("[256] = {"))
        .filter(|n| n.ends_with("_q63"))
        .collect();
    let mut c = String::from(
        "#include \"spectral_quadrature.h\"\n\ntypedef void (*sqt_fn)(void);\n\nstruct sqt_entry {\n    const char *name;\n    sqt_fn f;\n};\n\nstatic const struct sqt_entry sqt_entries[] = {\n",
    );
    for n in &names {
        writeln!(c, "    {{ \"{n}\", (sqt_fn){n} }},").unwrap();
    }
    c.push_str(
        "};\n\n/* The function of the header named `name`, or NULL. */\nsqt_fn sqt_find(const char *name);\nsqt_fn sqt_find(const char *name) {\n    size_t i;\n    for (i = 0; i < sizeof sqt_entries / sizeof sqt_entries[0]; i++) {\n        if (strcmp(sqt_entries[i].name, name) == 0) {\n            return sqt_entries[i].f;\n        }\n    }\n    return NULL;\n}\n\n/* How many functions the header defines, and the name of the i-th, in the header's order. */\nsize_t sqt_function_count(void);\nsize_t sqt_function_count(void) {\n    return sizeof sqt_entries / sizeof sqt_entries[0];\n}\n\nconst char *sqt_function_name(size_t i);\nconst char *sqt_function_name(size_t i) {\n    return i < sqt_function_count() ? sqt_entries[i].name : NULL;\n}\n",
    );
    c.push_str("\n/* The header's 8-bit curve `name` on the 2^63 scale (sq_..._q63), or NULL. */\nconst uint64_t *sqt_q63(const char *name);\nconst uint64_t *sqt_q63(const char *name) {\n");
    for t in &tables {
        writeln!(
            c,
            "    if (strcmp(name, \"{t}\") == 0) {{\n        return {t};\n    }}"
        )
        .unwrap();
    }
    c.push_str("    (void)name;\n    return NULL;\n}\n");
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    let harness = out.join("harness.c");
    std::fs::write(&harness, c).expect("write harness.c");
    let mut build = cc::Build::new();
    build
        .file(&harness)
        .include(&include)
        .warnings_into_errors(true)
        .flag("-Wall")
        .flag("-Wextra")
        .flag("-pedantic");
    let fma = std::env::var("CARGO_CFG_TARGET_ARCH").as_deref() == Ok("x86_64")
        && std::env::var("TARGET") == std::env::var("HOST")
        && host_has_fma();
    if fma {
        build.flag("-std=gnu99").flag("-mfma");
    } else {
        build.flag("-std=c99");
    }
    build.compile("sqharness");
    // The header uses the C library's powf and sqrtf.
    if std::env::var("CARGO_CFG_TARGET_OS").as_deref() == Ok("linux") {
        println!("cargo:rustc-link-lib=m");
    }
}

#[cfg(target_arch = "x86_64")]
fn host_has_fma() -> bool {
    std::arch::is_x86_feature_detected!("fma")
}

#[cfg(not(target_arch = "x86_64"))]
fn host_has_fma() -> bool {
    false
}
