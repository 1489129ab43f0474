//! The radiosity solve: `B = E + ρ ∘ (F B)` for every wavelength (or node, or RGB channel) at
//! once, each a column of `B`.

use nalgebra::DMatrix;

/// How much light transport to compute.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bounces {
    /// Every interreflection: the linear system solved.
    All,
    /// The light and what it lights directly: `B = E + ρ ∘ (F E)`.
    Direct,
}

/// The largest relative change of any radiosity between two iterations at which
/// [`solve`] stops: far below what CIEDE2000 resolves.
pub const TOLERANCE: f64 = 1e-9;

/// Solves for the radiosities `B` (patches × columns, one column per wavelength) given the
/// form factors (`f`, row-major n × n), the emission `e` and the reflectance `rho` (both
/// patches × columns). [`Bounces::All`] iterates `B ← E + ρ ∘ (F B)` (Jacobi, one matrix
/// product per step for all columns; it converges because every row of `ρ ∘ F` sums to less
/// than 1) until no radiosity moves by more than [`TOLERANCE`] of the largest; returns `B` and
/// the number of iterations.
pub fn solve(
    f: &DMatrix<f64>,
    e: &DMatrix<f64>,
    rho: &DMatrix<f64>,
    bounces: Bounces,
) -> (DMatrix<f64>, usize) {
    let mut b = e.clone();
    let reflected = |b: &DMatrix<f64>| {
        let mut fb = f * b;
        fb.component_mul_assign(rho);
        fb
    };
    if bounces == Bounces::Direct {
        return (e + reflected(e), 1);
    }
    for it in 1..=10_000 {
        let next = e + reflected(&b);
        let scale = next.amax().max(f64::MIN_POSITIVE);
        let change = (&next - &b).amax();
        b = next;
        if change <= TOLERANCE * scale {
            return (b, it);
        }
    }
    (b, 10_000)
}
