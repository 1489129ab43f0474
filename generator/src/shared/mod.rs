//! Shared wavelength sets by kernel quadrature, with the light folded into the weights.
//!
//! A renderer pays per distinct wavelength, and every channel can use every sample. So a shared
//! set has N distinct wavelengths λᵢ and a full 3×N matrix W with `XYZ ≈ W · [r(λ₁) … r(λ_N)]`,
//! where r is what the renderer samples: a reflectance under a known light L (the light is
//! folded into W, `F = x̄ȳz̄ · L · dλ`), or a radiance (L = 1).
//!
//! The model ([`Problem`]): r is a constant of unknown level plus a zero-mean Gaussian process
//! whose covariance is a Matérn 5/2 smoothness kernel plus a multiple of the training
//! reflectances' empirical covariance. For given nodes, W is the best linear unbiased estimate of
//! `F r` (universal kriging with a constant trend): it minimises the expected squared error of
//! every linear functional of XYZ, and it integrates a constant spectrum exactly, so the white of
//! a surface under L is exact. The node search (`Problem::optimize`) minimises the expected
//! linearised CIELAB error `tr(M Σ)`, Σ the 3×3 covariance of XYZ's error and `M = mean JᵀJ` over
//! the training colours (J = ∂Lab/∂XYZ at each, its white exact): greedy selection on the 1 nm
//! grid, evenly spaced and random starts, each refined by coordinate descent, the best kept.
//!
//! The kernel's length and the empirical covariance's weight ([`LENGTH_NM`],
//! [`EMPIRICAL_WEIGHT`]) maximise the leave-one-out likelihood of the training reflectances
//! (`fit`, which the unit tests re-run). The crate trains on the CIE test colour samples only and judges on the
//! ColorChecker, which no set ever sees. A build takes the nodes of the sets it bakes from the
//! node cache (`CACHE_FILE`) and computes only their weights.
//!
//! Method (a) for comparison, the catalogue's `INTERP_A_<n>` (`interpolatory_a`): the A
//! channel's Gauss nodes of order N, with C1 and C2 integrated by interpolatory rules on those
//! nodes.
//!
//! The files, each importing only those before it: `model` (the prior, the light, the metric and
//! the solve), `fit` (the prior's parameters), `search` (the nodes), `cache` (the node cache),
//! `interpolatory` (method (a)).

mod cache;
#[cfg(test)]
mod fit;
mod group;
mod interpolatory;
mod model;
mod search;

pub use cache::{cache_file, search_fingerprint};
pub(crate) use cache::{cached_or_optimize, cached_or_optimize_group, CACHE_FILE};
pub use group::{
    bounce_forms, nodes_of, Group, GroupFit, GroupObjective, GroupTraining, Member, Weights,
};
pub(crate) use group::{GROUP_SIZES, GROUP_TRAINING_FILES};
pub(crate) use interpolatory::interpolatory_a;
pub use model::{
    eval_on_radiance, problem_for, Problem, Shared, EMPIRICAL_WEIGHT, LENGTH_NM, TRAINING_FILE,
};
// The paths the unit tests (src/tests/) name.
#[cfg(test)]
pub(crate) use cache::{
    fingerprint, group_cache_name, group_fingerprint, group_fit, optimize_group, parse_cache,
    read_cache, set_name, write_cache, CacheEntry, CACHED, CACHED_GROUPS,
};
#[cfg(test)]
pub(crate) use fit::{fit, FIT_LENGTHS_NM, FIT_WEIGHTS};
#[cfg(test)]
pub(crate) use model::{problem, Kernel};
pub(crate) use search::SIZES;
