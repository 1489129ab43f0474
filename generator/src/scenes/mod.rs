//! What one application uses, so the build bakes only that: the scene file ([`scene`]), every
//! set the crate can build by name ([`catalog`]), the user's own lights, wavelengths and sensors
//! ([`user`]), the planner that picks a set for a ΔE budget ([`plan`]), and the RGB upsamplings
//! a scene asks for ([`upsampling`]).

pub mod catalog;
pub mod plan;
pub mod scene;
pub mod upsampling;
pub mod user;
