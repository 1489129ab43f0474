//! The emitters. A scene is first baked into one [`model`](model::Model): every constant it
//! bakes, computed once from the derivation and rounded to f32 as the runtime holds it. Every
//! target is then a formatter of that model, calling nothing in the derivation: the Rust tables
//! the runtime includes ([`codegen`]), the WGSL and GLSL snippets ([`shader`]), the 8-bit
//! encoders' thresholds (`transfer_tables`), the integer path's fixed-point sets
//! ([`fixed_point`]), the RGB upsamplings' tables and shader files ([`upsampling`]), the
//! Planckian locus table (`planckian`), the sensors' white references and calibrations
//! (`sensors`). [`generate`](crate::generate), which the runtime's build script calls, bakes the
//! model and runs each formatter.

pub(crate) mod codegen;
pub mod fixed_point;
pub(crate) mod generate;
pub(crate) mod layout;
pub(crate) mod lists;
pub(crate) mod model;
pub(crate) mod planckian;
pub(crate) mod sensors;
pub mod shader;
pub(crate) mod transfer_tables;
pub(crate) mod upsampling;
