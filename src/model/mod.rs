//! The model: the value types every path of the runtime computes with, and their own
//! arithmetic. From the bottom: `bits` (equality by bits in const fns), `channel` (the channel selectors `Channel` and `Rgb`), `error`
//! (the one error type, which names them), `matrix` (3×3 products, and AC1C2 ↔ XYZ with the
//! observer's baked matrices), `transfer` (transfer functions), `display` (a display: its
//! matrices, gamut mapping, encoding) and `set` (the set and rule types, their constructors and
//! accessors, and the folding of a set for a display).
//!
//! One role, so that the paths above (per pixel, batch, planar, integer) and the rest of the
//! runtime import the model, not each of its layers. This file only declares the modules; the
//! crate's root re-exports their public items.

#![forbid(unsafe_code)]

pub(crate) mod bits;
pub(crate) mod channel;
pub(crate) mod display;
pub(crate) mod error;
pub(crate) mod matrix;
pub(crate) mod set;
pub(crate) mod transfer;

#[cfg(test)]
mod tests;
