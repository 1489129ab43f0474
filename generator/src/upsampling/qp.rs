//! A small quadratic programme: the point of the box `[0, 1]ⁿ` nearest to a target `u` among
//! those whose image under a few linear rows `B` is as near `d` as the box allows.
//!
//! ```text
//! minimise ½‖x − u‖² + ½ρ‖B x − d‖²   subject to 0 ≤ x ≤ 1
//! ```
//!
//! with ρ = 1 / `EPSILON` (after `B` and `d` are scaled to unit norm). Where `B x = d` has
//! solutions in the box, the minimiser is, to within `EPSILON` times its multipliers, the
//! Euclidean projection of `u` onto them; where it has none, the rows are matched as closely as
//! the box allows first (in the least-squares sense of `B`'s rows), and `u` only breaks the tie.
//!
//! The method is the primal active-set method for a strictly convex quadratic with bounds:
//! start from `u` clipped to the box, fix the variables at their bounds, solve for the free ones,
//! step as far toward that solution as the box allows (fixing the variable that blocks), and free
//! the fixed variable whose multiplier has the wrong sign when no step is left. Each solve on the
//! free set F is the m × m system `(B_F B_Fᵀ + ε I) λ = B_F u_F − (d − B_A x_A)`, then
//! `x_F = u_F − B_Fᵀ λ`: no quantity of size ρ is ever formed, so ρ may be as large as f64
//! allows, and `λ` is the rows' multipliers. The objective is strictly convex, so the method ends
//! in finitely many steps; `MAX_STEPS` bounds them.

use std::vec::Vec;

use crate::base::error::Error;

/// The weight of the rows' residual against the distance to the target, inverted: ρ = 1/ε,
/// relative to rows scaled to unit Frobenius norm. 1e-9 leaves a residual of about 1e-9 times
/// the multipliers (far below a 16-bit table's step of 1.5e-5), and amplifies the rounding of
/// the right-hand side (about 1e-16) to about 1e-7 in the multipliers, which [`TOLERANCE`]
/// stays above.
pub(crate) const EPSILON: f64 = 1e-9;

/// A fixed variable is freed only when its multiplier has the wrong sign by more than this: well
/// above the multipliers' rounding (about 1e-16 / [`EPSILON`]), and a multiplier this small moves
/// the solution by about as little.
pub(crate) const TOLERANCE: f64 = 1e-6;

/// Active-set steps allowed per variable (plus a constant): each step fixes or frees one
/// variable, and the method seldom revisits one.
pub(crate) const MAX_STEPS: usize = 20;

/// The solution of one programme.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    /// The minimiser, in the box.
    pub x: Vec<f64>,
    /// The rows' residual `B x − d` in the rows' original scale.
    pub residual: Vec<f64>,
    /// Active-set steps taken.
    pub steps: usize,
}

/// Solves the programme for target `u` (n values), rows `b` (m rows of n) and right-hand side
/// `d` (m values). Errors if the sizes disagree, a value is not finite, or the active set has
/// not settled after `MAX_STEPS · n + 50` steps.
pub fn nearest_in_box(u: &[f64], b: &[Vec<f64>], d: &[f64]) -> Result<Solution, Error> {
    let n = u.len();
    let m = b.len();
    if d.len() != m || b.iter().any(|r| r.len() != n) {
        return Err(Error::Numerical(std::format!(
            "box programme: {m} rows of lengths {:?} and {} right-hand sides for {n} variables",
            b.iter().map(Vec::len).collect::<Vec<_>>(),
            d.len()
        )));
    }
    let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
    if !finite(u) || !finite(d) || b.iter().any(|r| !finite(r)) {
        return Err(Error::Numerical(
            "box programme: a value is not finite".into(),
        ));
    }
    // Scale the rows (and d with them) to unit Frobenius norm, so that EPSILON is relative.
    let norm = b.iter().flatten().map(|v| v * v).sum::<f64>().sqrt();
    let scale = if norm > 0.0 { 1.0 / norm } else { 1.0 };
    let bs: Vec<Vec<f64>> = b
        .iter()
        .map(|r| r.iter().map(|v| v * scale).collect())
        .collect();
    let ds: Vec<f64> = d.iter().map(|v| v * scale).collect();

    #[derive(Clone, Copy, PartialEq)]
    enum State {
        Free,
        Lower,
        Upper,
    }
    let mut x: Vec<f64> = u.iter().map(|v| v.clamp(0.0, 1.0)).collect();
    let mut state: Vec<State> = x
        .iter()
        .map(|&v| {
            if v <= 0.0 {
                State::Lower
            } else if v >= 1.0 {
                State::Upper
            } else {
                State::Free
            }
        })
        .collect();
    let limit = MAX_STEPS * n + 50;
    for steps in 0..limit {
        let free: Vec<usize> = (0..n).filter(|&i| state[i] == State::Free).collect();
        // e = d − B_A x_A; rhs = B_F u_F − e.
        let mut rhs = std::vec![0.0; m];
        for r in 0..m {
            let mut e = ds[r];
            let mut bu = 0.0;
            for i in 0..n {
                if state[i] == State::Free {
                    bu += bs[r][i] * u[i];
                } else {
                    e -= bs[r][i] * x[i];
                }
            }
            rhs[r] = bu - e;
        }
        let mut s = std::vec![0.0; m * m];
        for p in 0..m {
            for q in 0..=p {
                let v: f64 = free.iter().map(|&i| bs[p][i] * bs[q][i]).sum();
                s[p * m + q] = v;
                s[q * m + p] = v;
            }
            s[p * m + p] += EPSILON;
        }
        let lambda = cholesky_solve(&mut s, m, &rhs).ok_or_else(|| {
            Error::Numerical("box programme: the rows' system is not positive definite".into())
        })?;
        let target = |i: usize| u[i] - (0..m).map(|r| bs[r][i] * lambda[r]).sum::<f64>();
        // Step toward the free variables' solution, as far as the box allows.
        let mut alpha = 1.0f64;
        let mut block: Option<(usize, State)> = None;
        for &i in &free {
            let t = target(i);
            let p = t - x[i];
            if p < 0.0 && t < 0.0 {
                let a = x[i] / -p;
                if a < alpha {
                    alpha = a;
                    block = Some((i, State::Lower));
                }
            } else if p > 0.0 && t > 1.0 {
                let a = (1.0 - x[i]) / p;
                if a < alpha {
                    alpha = a;
                    block = Some((i, State::Upper));
                }
            }
        }
        for &i in &free {
            let t = target(i);
            x[i] = (x[i] + alpha * (t - x[i])).clamp(0.0, 1.0);
        }
        if let Some((i, bound)) = block {
            x[i] = if bound == State::Lower { 0.0 } else { 1.0 };
            state[i] = bound;
            continue;
        }
        // At the free set's minimiser: the fixed variables' multipliers are the gradient
        // (x − u) + Bᵀλ; a variable at 0 with a negative one, or at 1 with a positive one,
        // would lower the objective by leaving its bound.
        let mut worst: Option<(usize, f64)> = None;
        for i in 0..n {
            let g = x[i] - u[i] + (0..m).map(|r| bs[r][i] * lambda[r]).sum::<f64>();
            let violation = match state[i] {
                State::Free => 0.0,
                State::Lower => -g,
                State::Upper => g,
            };
            if violation > TOLERANCE && worst.is_none_or(|(_, v)| violation > v) {
                worst = Some((i, violation));
            }
        }
        match worst {
            Some((i, _)) => state[i] = State::Free,
            None => {
                let residual = (0..m)
                    .map(|r| (0..n).map(|i| b[r][i] * x[i]).sum::<f64>() - d[r])
                    .collect();
                return Ok(Solution {
                    x,
                    residual,
                    steps: steps + 1,
                });
            }
        }
    }
    Err(Error::Numerical(std::format!(
        "box programme: the active set did not settle in {limit} steps"
    )))
}

/// Solves `S y = rhs` for a symmetric positive definite m × m `S` (row-major, overwritten by its
/// Cholesky factor). `None` if `S` is not positive definite.
fn cholesky_solve(s: &mut [f64], m: usize, rhs: &[f64]) -> Option<Vec<f64>> {
    for j in 0..m {
        let mut diag = s[j * m + j];
        for k in 0..j {
            diag -= s[j * m + k] * s[j * m + k];
        }
        if diag.partial_cmp(&0.0) != Some(core::cmp::Ordering::Greater) {
            return None;
        }
        let l = diag.sqrt();
        s[j * m + j] = l;
        for i in j + 1..m {
            let mut v = s[i * m + j];
            for k in 0..j {
                v -= s[i * m + k] * s[j * m + k];
            }
            s[i * m + j] = v / l;
        }
    }
    let mut y = rhs.to_vec();
    for i in 0..m {
        for k in 0..i {
            y[i] -= s[i * m + k] * y[k];
        }
        y[i] /= s[i * m + i];
    }
    for i in (0..m).rev() {
        for k in i + 1..m {
            y[i] -= s[k * m + i] * y[k];
        }
        y[i] /= s[i * m + i];
    }
    Some(y)
}
