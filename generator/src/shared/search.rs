//! The node search: which wavelengths a shared set samples. Greedy selection on the 1 nm grid,
//! evenly spaced and random starts, each refined by coordinate descent, the best kept, all
//! minimising the model's expected error ([`Problem::objective`]).

use std::vec::Vec;

use super::model::{problem, Problem, Shared};
use crate::base::error::Error;
use crate::derivation::derive::Derivation;

/// Random starts of coordinate descent, besides greedy selection and three even spreads.
pub(crate) const RANDOM_STARTS: usize = 12;

/// How far (1 nm grid steps) coordinate descent tries to move one node.
pub(crate) const MAX_MOVE: usize = 12;

/// Shared-set sizes the catalog builds: `KQ_3` … `KQ_32`.
pub(crate) const SIZES: core::ops::RangeInclusive<usize> = 3..=32;

impl Problem {
    /// Greedy selection of `n` allowed grid indices, each the one that most lowers `objective`.
    fn greedy_with(&self, n: usize, objective: &dyn Fn(&[usize]) -> f64) -> Vec<usize> {
        let mut nodes: Vec<usize> = Vec::with_capacity(n);
        for _ in 0..n {
            let mut best = (f64::INFINITY, usize::MAX);
            for c in 0..self.g {
                if !self.allowed[c] || nodes.contains(&c) {
                    continue;
                }
                nodes.push(c);
                let o = objective(&nodes);
                nodes.pop();
                if o < best.0 {
                    best = (o, c);
                }
            }
            if best.1 == usize::MAX {
                break;
            }
            nodes.push(best.1);
        }
        nodes.sort_unstable();
        nodes
    }

    /// Coordinate descent: moves one node at a time by up to ±[`MAX_MOVE`] grid steps while that
    /// lowers `objective`. Returns the nodes (ascending) and their error.
    pub(super) fn refine_with(
        &self,
        mut nodes: Vec<usize>,
        objective: &dyn Fn(&[usize]) -> f64,
    ) -> (Vec<usize>, f64) {
        let mut current = objective(&nodes);
        for _ in 0..200 {
            let mut improved = false;
            for i in 0..nodes.len() {
                let start = nodes[i];
                let mut best = (current, start);
                for step in 1..=MAX_MOVE {
                    for c in [start.checked_sub(step), Some(start + step)]
                        .into_iter()
                        .flatten()
                    {
                        if c >= self.g || !self.allowed[c] || nodes.contains(&c) {
                            continue;
                        }
                        nodes[i] = c;
                        let o = objective(&nodes);
                        if o < best.0 * (1.0 - 1e-12) {
                            best = (o, c);
                        }
                    }
                }
                nodes[i] = best.1;
                if best.1 != start {
                    current = best.0;
                    improved = true;
                }
            }
            if !improved {
                break;
            }
        }
        nodes.sort_unstable();
        (nodes, current)
    }

    /// Evenly spaced allowed grid indices (a start for coordinate descent).
    pub(super) fn spread(&self, n: usize, offset: f64) -> Vec<usize> {
        let allowed: Vec<usize> = (0..self.g).filter(|&c| self.allowed[c]).collect();
        let mut nodes: Vec<usize> = (0..n)
            .map(|i| {
                let t = (i as f64 + offset) / n as f64;
                allowed[((t * allowed.len() as f64) as usize).min(allowed.len() - 1)]
            })
            .collect();
        nodes.dedup();
        nodes
    }

    /// The best of greedy selection and evenly spaced starts, each refined by coordinate
    /// descent: `n` grid indices (ascending) and their error.
    pub(crate) fn optimize(&self, n: usize) -> (Vec<usize>, f64) {
        self.optimize_with(n, &|nodes| self.objective(nodes))
    }

    /// [`optimize`](Self::optimize) for any objective.
    pub(super) fn optimize_with(
        &self,
        n: usize,
        objective: &dyn Fn(&[usize]) -> f64,
    ) -> (Vec<usize>, f64) {
        let mut starts = std::vec![self.greedy_with(n, objective)];
        for offset in [0.5, 0.25, 0.75] {
            let s = self.spread(n, offset);
            if s.len() == n {
                starts.push(s);
            }
        }
        // Random starts from a fixed LCG (deterministic output).
        let allowed: Vec<usize> = (0..self.g).filter(|&c| self.allowed[c]).collect();
        let mut state: u64 = 0x853c_49e6_748f_ea9b;
        for _ in 0..RANDOM_STARTS {
            let mut s: Vec<usize> = Vec::with_capacity(n);
            while s.len() < n.min(allowed.len()) {
                state = state
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                let c = allowed[((state >> 33) as usize) % allowed.len()];
                if !s.contains(&c) {
                    s.push(c);
                }
            }
            starts.push(s);
        }
        starts
            .into_iter()
            .map(|s| self.refine_with(s, objective))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap_or((Vec::new(), f64::INFINITY))
    }

    /// The optimised shared set of `n` wavelengths (`optimize`, the node search).
    pub fn shared(&self, n: usize) -> Result<Shared, Error> {
        let (nodes, _) = self.optimize(n);
        if nodes.len() != n {
            return Err(Error::Numerical(std::format!(
                "no shared set of {n} wavelengths: only {} grid points are usable",
                nodes.len()
            )));
        }
        self.set_at(&nodes).ok_or_else(|| {
            Error::Numerical(std::format!(
                "no shared set of {n} wavelengths: the kriging system is singular"
            ))
        })
    }
}

/// The shared set of `n` wavelengths for a built-in light (`None`: radiances). To build
/// several sizes for one light, set up `problem` once and call [`Problem::shared`].
///
/// This runs the node search (`Problem::optimize`), which solves the kriging system for every
/// node it tries: too slow for a build script at Cargo's default opt-level 0 (README, "Build
/// cost", measures it). `cached_or_optimize` takes the nodes
/// from `CACHE_FILE` where it can.
pub(crate) fn optimize(d: &Derivation, light: Option<&str>, n: usize) -> Result<Shared, Error> {
    problem(d, light)?.shared(n)
}
