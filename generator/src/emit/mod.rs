//! The emitters: the Rust tables the runtime includes ([`codegen`]), the WGSL and GLSL snippets
//! ([`shader`]), the 8-bit encoders' thresholds (`transfer_tables`), the integer path's
//! fixed-point sets ([`fixed_point`]), and
//! [`generate`](crate::generate), which the runtime's build script calls to run the whole
//! generation for a scene.

pub mod codegen;
pub mod fixed_point;
pub(crate) mod generate;
pub(crate) mod layout;
pub mod shader;
pub(crate) mod transfer_tables;
