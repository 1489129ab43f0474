//! The emitters: the Rust tables the runtime includes ([`codegen`]), the WGSL and GLSL snippets
//! ([`shader`]), the 8-bit encoders' thresholds (`transfer_tables`), the integer path's
//! fixed-point sets ([`fixed_point`]), the RGB upsamplings' tables ([`upsampling`]), the
//! Planckian locus table (`planckian`), the sensors' white references and calibrations
//! (`sensors`), and
//! [`generate`](crate::generate), which the runtime's build script calls to run the whole
//! generation for a scene.

pub(crate) mod codegen;
pub mod fixed_point;
pub(crate) mod generate;
pub(crate) mod layout;
pub(crate) mod lists;
pub(crate) mod planckian;
pub(crate) mod sensors;
pub mod shader;
pub(crate) mod transfer_tables;
pub(crate) mod upsampling;
