//! The integration tests, linked as one test binary (`--test integration`): each file of tests/
//! is a module here, so that a test build compiles and links one binary against the runtime,
//! the derivation, proptest and the rest instead of one per file. Run one file's tests with its
//! module name as the filter, `cargo test --test integration -- cct::`.
//!
//! Each file is loaded by `#[path]`, which makes it resolve its own `mod common;` from this
//! directory (tests/common/), as when it was a crate of its own; a plain `mod cct;` would look for
//! tests/cct/common.rs. Nothing here depends on running alone in its process: `no_alloc`'s
//! counting allocator counts per thread, and each test runs on a thread of its own.

// The files declare `mod common;` themselves, as they did as crates of their own, so each has
// its own copy of those helpers: constants and functions without state, so nothing is shared by
// accident.
#![allow(clippy::duplicate_mod)]

#[path = "calibration.rs"]
mod calibration;
#[path = "cct.rs"]
mod cct;
#[path = "codegen.rs"]
mod codegen;
#[path = "edge_inputs.rs"]
mod edge_inputs;
#[path = "extremes.rs"]
mod extremes;
#[path = "integer.rs"]
mod integer;
#[path = "light_groups.rs"]
mod light_groups;
#[path = "no_alloc.rs"]
mod no_alloc;
#[path = "planar.rs"]
mod planar;
#[path = "properties.rs"]
mod properties;
#[path = "relight.rs"]
mod relight;
#[path = "sensor_lights.rs"]
mod sensor_lights;
#[path = "transfer.rs"]
mod transfer;
#[path = "upsampling.rs"]
mod upsampling;
