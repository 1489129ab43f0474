//! RGB materials at a set's wavelengths: an upsampling from linear display RGB to the set's N
//! node reflectances, baked on a grid for each set and display a scene asks for.
//!
//! A renderer that samples a few fixed wavelengths still has RGB textures and material colours:
//! it needs each colour's reflectance at those wavelengths. The map from RGB to node
//! reflectances is built in three steps:
//!
//! 1. **The set's encoding under its reference light** (`encoding`): the set's folded weights
//!    for the display, times the reference light at the nodes for a set for radiances
//!    (`RADIANCE_REFERENCE_LIGHT`; a set with a light folded in has it in its weights), each
//!    row divided by its sum, so that node values of 1 give RGB (1, 1, 1): white-balanced RGB.
//! 2. **A least-squares map** (`least_squares_map`): `r ≈ M · rgb`, fitted on the training
//!    reflectances (`TRAINING_FILES`: the CIE test colours and the rawtoaces patches; never
//!    the ColorChecker), their exact RGB under the reference light (1 nm) against their values at
//!    the nodes, with each row of M summing to 1 (white and greys exact). At each grid point the
//!    fit is local (`local_map`): the training pairs weighted by how near their colour lies
//!    in CIELAB (`LOCAL_BANDWIDTH`), pulled a little toward the global map (`LOCAL_PRIOR`).
//! 3. **A projection per grid point** ([`project`]): `M · rgb` moved to the nearest node values
//!    in [0, 1] that encode back to `rgb` exactly, or, where no node values in [0, 1] reach
//!    `rgb`, to those that reach the nearest colour in CIELAB (linearised at `rgb`), and among
//!    them the nearest to `M · rgb`. A small quadratic programme ([`nearest_in_box`]).
//!
//! **A light group's map** ([`bake_group`]) takes RGB under the group's first light and is
//! checked for the round trip through that light's member; its least-squares map (step 2) is
//! fitted on the training reflectances' colours under every light of the group, as each light's
//! member encodes them, beside their node values (`GROUP_COLOUR_WEIGHT`), so that a texel's node
//! values are meant for every light that may fall on it.
//!
//! The runtime interpolates the grid tetrahedrally: a convex combination of four grid points
//! (so bounded), exact on the grey diagonal (an edge of every tetrahedron), and reproducing
//! anything linear in RGB, so that the encoding of the interpolated values is the interpolated
//! RGB: exact wherever the four grid points round-trip. [`bake`] returns the table and the
//! figures the runtime states: the largest round-trip error at the grid points, the Lipschitz
//! constant, the share of the grid that is reachable.
//!
//! The fit takes seconds at Cargo's default build-script opt-level, so the build takes the
//! default scene's tables from a cache (`CACHE_FILE`) while their inputs' fingerprint
//! (`FitInputs::fingerprint`) matches, and fits the rest.
//!
//! The files, each importing only those before it: `qp` (the box programme), `training` (the
//! training reflectances), `bake` (encoding, map, projection, grid), `cache` (the cache file).

mod bake;
mod cache;
pub(crate) mod qp;
mod training;

pub use bake::{bake, bake_group, encode, exact_rgb, grid_point, project, Baked, DEFAULT_GRID};
pub(crate) use bake::{bake_with, encoding, GRID_SIZES, RADIANCE_REFERENCE_LIGHT};
pub(crate) use cache::{read_cache, write_cache, CacheEntry, FitInputs, CACHE_FILE};
pub use qp::{nearest_in_box, Solution};
pub use training::training;
pub(crate) use training::TRAINING_FILES;
// The paths the unit tests (src/tests/) name.
#[cfg(test)]
pub(crate) use bake::{lab_of_rgb, GroupColours, CODE_ONE, GROUP_COLOUR_WEIGHT};
#[cfg(test)]
pub(crate) use cache::parse_cache;
#[cfg(test)]
pub(crate) use training::parse_training;
