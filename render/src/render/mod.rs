//! Error against render time: one path tracer of the Cornell box for every spectral method
//! (`render`, `docs/render-time.md`).
//!
//! The spatial part ([`transport`]: geometry, camera, paths, per-pixel seeds) is written once;
//! what a path carries is a [`transport::Carrier`] ([`carriers`]: three RGB channels, K random
//! wavelengths, N node values of a folded set or a light group, or every nm for the reference),
//! so that two images at the same samples per pixel differ only spectrally and their times
//! compare. The scenes ([`scene`]) are TOML files beside their data; the methods are made from a
//! scene with the generator and the runtime's public constructors ([`methods`]); images are
//! judged in CIEDE2000 against the 1 nm reference, whose own error is measured from two seeds
//! ([`measure`]). The curves of error against time, where they stop and what they say, are
//! [`curves`].

pub mod carriers;
pub mod curves;
pub mod measure;
pub mod methods;
pub mod scene;
pub mod transport;
