//! What one application uses, so the build bakes only that: the scene file ([`scene`]), every
//! set the crate can build by name ([`catalog`]), the user's own lights, wavelengths and sensors
//! ([`user`]) with a sensor's white reference and calibration ([`calibration`]), the planner
//! that picks a set for a ΔE budget ([`plan`]), and the RGB upsamplings a scene asks for
//! ([`upsampling`]).

pub mod calibration;
pub mod catalog;
pub mod plan;
pub mod scene;
pub(crate) mod upsampling;
pub mod user;
