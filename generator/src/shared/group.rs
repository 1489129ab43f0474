//! Light groups: one node set shared by several lights, with a weight matrix folded per light.
//!
//! A renderer's pixel gathers light from several sources of different spectra. With a light
//! folded into the weights, a set is right only for its own light; a radiance set samples each
//! light's spectrum, spikes included. A group keeps one accumulator of N node values per light
//! (the reflectance products a path carries from that light, the light itself left out) and
//! integrates each through its own light's folded weights: the nodes are shared, so the renderer
//! evaluates its materials at N wavelengths whatever the number of lights.
//!
//! The fit is empirical, on training reflectances:
//! - **Weights.** For given nodes, each light's 3×N matrix is the least-squares fit of the
//!   training reflectances' XYZ under that light from their values at the nodes, with the white
//!   pinned: a reflectance of 1 gives the light's white exactly, as every folded set does.
//! - **Nodes.** Coordinate descent on the 1 nm grid ([`Problem::refine_with`], the single-light
//!   search's), from the nodes the kernel model finds for the group and an even spread,
//!   minimising [`GroupObjective`] over each light's mean CIEDE2000 on the training
//!   reflectances against that of the light's own folded set (the crate's `KQ_<light>_<n>`).
//!
//! The report's section 9 judges the fit by five-fold cross-validation. For one light fitted on
//! reflectances as they are the crate keeps its folded set (the kernel model's), so a scene's
//! group has two lights or more, or one fitted on bounce forms ([`GroupTraining::Bounces`]).

use std::string::String;
use std::vec::Vec;

use nalgebra::DMatrix;
use spectral_quadrature_math::{delta_e2000, lab_from_xyz};

use super::model::{Problem, Shared};
use crate::base::error::Error;
use spectral_quadrature_spectra::Curve;

/// The training reflectances of the crate's light groups: every reflectance file of the crate
/// (the CIE test colours, the ColorChecker, the 190 rawtoaces patches). The report judges the
/// fit by cross-validation over the last two instead (section 9).
pub(crate) const GROUP_TRAINING_FILES: [&str; 3] = [
    "data/reflectance_cie_tcs.csv",
    "data/reflectance_colorchecker_ohta.csv",
    "data/reflectance_rawtoaces_190.csv",
];

/// What a light group's weights and nodes are fitted on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum GroupTraining {
    /// The training reflectances as they are: light reflected once (the default; report
    /// section 10d measures the other on reflectances no fit saw, and it does no better on
    /// average).
    Reflectances,
    /// Their bounce forms too ([`bounce_forms`]): `ρ`, `ρ²`, `ρ³` and two enclosures.
    Bounces,
}

impl GroupTraining {
    /// `"reflectances"` or `"bounces"`, as a scene writes it.
    pub(crate) const fn name(self) -> &'static str {
        match self {
            GroupTraining::Reflectances => "reflectances",
            GroupTraining::Bounces => "bounces",
        }
    }
}

/// The enclosures' albedos of [`bounce_forms`].
const BOUNCE_ALBEDOS: [f64; 2] = [0.5, 0.9];

/// The bounce forms a fit for bounced light trains on, each reflectance on the 1 nm grid of
/// `range_nm`: as it is, squared and cubed (one, two and three bounces off one material), then
/// in an enclosure of albedo 0.5 and 0.9, `ρ (1 − a) / (1 − a ρ)` (the integrating-sphere sum
/// over every bounce, a perfect reflector giving 1).
pub fn bounce_forms(training: &[Curve], range_nm: [f64; 2]) -> Vec<Curve> {
    let (lo, hi) = (range_nm[0].ceil() as i64, range_nm[1].floor() as i64);
    let grid: Vec<f64> = (lo..=hi).map(|v| v as f64).collect();
    let form = |r: &Curve, label: &str, f: &dyn Fn(f64) -> f64| Curve {
        name: std::format!("{label} of {}", r.name),
        wavelengths: grid.clone(),
        values: grid.iter().map(|&nm| f(r.at(nm))).collect(),
    };
    let mut out = Vec::new();
    for k in 1..=3 {
        out.extend(
            training
                .iter()
                .map(|r| form(r, &std::format!("ρ^{k}"), &|v| v.powi(k))),
        );
    }
    for a in BOUNCE_ALBEDOS {
        out.extend(training.iter().map(|r| {
            form(r, &std::format!("sphere a={a}"), &|v| {
                v * (1.0 - a) / (1.0 - a * v)
            })
        }));
    }
    out
}

/// The sizes a scene's light group may have.
pub(crate) const GROUP_SIZES: core::ops::RangeInclusive<i64> = 3..=16;

/// What the node search of a light group minimises, from each light's mean CIEDE2000 `e_l` on
/// the training reflectances at the group's nodes and `own_l`, that of the light's own folded
/// set of the same size.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum GroupObjective {
    /// The mean over the lights of `e_l / own_l`: what the group costs each light, on average,
    /// against its own set.
    Mean,
    /// The largest `e_l / own_l`: no light is given up for the others.
    Worst,
}

impl GroupObjective {
    /// `"mean"` or `"worst"`, as a scene writes it.
    pub(crate) const fn name(self) -> &'static str {
        match self {
            GroupObjective::Mean => "mean",
            GroupObjective::Worst => "worst",
        }
    }
}

/// How a group's weights are tied across its lights.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Weights {
    /// One matrix per light (a light group): each light folded into its own weights.
    PerLight,
    /// One matrix for radiances `r · L`, whatever the light (a radiance set fitted on the
    /// group's lights): light l's folded weights are that matrix times L at the nodes. The
    /// comparison a renderer without light groups has.
    Radiance,
}

/// One light of a group: its folded weights on the group's nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct Member {
    /// The light's name.
    pub light: String,
    /// The light at each node, scaled as [`Problem::light`] (the luminance of an equal-energy
    /// spectrum of 1).
    pub light_at_nodes: Vec<f64>,
    /// Folded XYZ weights `w[c][i]` for samples of a reflectance under this light.
    pub xyz_weights: [Vec<f64>; 3],
    /// Mean CIEDE2000 over the training reflectances.
    pub training_de00: f64,
}

impl Member {
    /// The member as the runtime bakes it: AC1C2 rows (Eq. 9 applied to the folded XYZ
    /// weights), named `name`, on the group's nodes (`wavelengths_nm`), its light folded in.
    pub fn wavelength_set(
        &self,
        d: &crate::derivation::derive::Derivation,
        name: &str,
        wavelengths_nm: &[f64],
    ) -> crate::derivation::sets::WavelengthSet {
        crate::derivation::sets::WavelengthSet {
            name: name.into(),
            doc: std::format!("{}'s member of a light group", self.light),
            wavelengths_nm: wavelengths_nm.to_vec(),
            weights: crate::derivation::display::fold(
                &d.opponent.xyz_to_ac1c2,
                &self.xyz_weights,
                1.0,
            ),
            light: Some(self.light.clone()),
            sensor: None,
        }
    }
}

/// A light group's sets: one per light, all on the same nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    /// The shared nodes in nm, ascending.
    pub wavelengths_nm: Vec<f64>,
    /// Per light, in the group's order.
    pub members: Vec<Member>,
    /// The objective the nodes were searched for.
    pub objective: GroupObjective,
    /// How the weights are tied across the lights.
    pub weights: Weights,
    /// What the fit trained on (as the caller built the [`GroupFit`]; set by the scene's
    /// resolution, [`GroupTraining::Reflectances`] otherwise).
    pub training: GroupTraining,
}

/// Everything the fit reads, computed once for a group's lights and training reflectances.
pub struct GroupFit {
    /// Per light: its kernel-model problem (grid, scaled light, folded observer, white).
    problems: Vec<Problem>,
    /// The search's grid: where any light is not negligible.
    search: Problem,
    /// The training reflectances on the grid, one row each.
    samples: Vec<Vec<f64>>,
    /// `Σ_r r(λ_a) r(λ_b)` over the training reflectances, row-major G×G: computed on the first
    /// search ([`GroupFit::optimize`]); a group at given nodes (from the node cache, in a build
    /// script at opt-level 0) sums only the N² entries it needs.
    gram: std::sync::OnceLock<Vec<f64>>,
    /// Per light and grid point: `Σ_r r(λ_a) XYZ_l(r)`.
    cross: Vec<Vec<[f64; 3]>>,
    /// Per light: each training reflectance's reference CIELAB (1 nm grid).
    labs: Vec<Vec<[f64; 3]>>,
}

impl GroupFit {
    /// Sets up the fit of a group of `lights` (at least one, each with its kernel-model
    /// problem, as [`problem_for`](crate::shared::problem_for) gives it) on `training`
    /// reflectances (at least one).
    pub fn new(problems: Vec<Problem>, training: &[Curve]) -> Result<GroupFit, Error> {
        if problems.is_empty() {
            return Err(Error::Numerical(
                "a light group needs at least one light".into(),
            ));
        }
        if training.is_empty() {
            return Err(Error::Numerical(
                "a light group needs training reflectances".into(),
            ));
        }
        let first = &problems[0];
        if problems.iter().any(|p| p.grid_nm != first.grid_nm) {
            return Err(Error::Numerical(
                "a light group's lights must share one grid".into(),
            ));
        }
        let g = first.g;
        let mut search = first.clone();
        search.allowed = (0..g)
            .map(|i| problems.iter().any(|p| p.allowed[i]))
            .collect();
        let samples: Vec<Vec<f64>> = training
            .iter()
            .map(|c| first.grid_nm.iter().map(|&nm| c.at(nm)).collect())
            .collect();
        let mut cross = Vec::with_capacity(problems.len());
        let mut labs = Vec::with_capacity(problems.len());
        for p in &problems {
            let f = p.folded_cmfs();
            let white = p.white();
            let xyzs: Vec<[f64; 3]> = samples
                .iter()
                .map(|s| [0, 1, 2].map(|c| f[c].iter().zip(s).map(|(w, r)| w * r).sum()))
                .collect();
            let mut cr = std::vec![[0.0; 3]; g];
            for (s, xyz) in samples.iter().zip(&xyzs) {
                for (a, out) in cr.iter_mut().enumerate() {
                    for c in 0..3 {
                        out[c] += s[a] * xyz[c];
                    }
                }
            }
            cross.push(cr);
            labs.push(xyzs.iter().map(|&x| lab_from_xyz(x, white)).collect());
        }
        Ok(GroupFit {
            problems,
            search,
            samples,
            gram: std::sync::OnceLock::new(),
            cross,
            labs,
        })
    }

    /// The full Gram matrix (computed once).
    fn full_gram(&self) -> &[f64] {
        self.gram.get_or_init(|| {
            let g = self.search.g;
            let mut gram = std::vec![0.0; g * g];
            for s in &self.samples {
                for a in 0..g {
                    let sa = s[a];
                    for (b, v) in gram[a * g..(a + 1) * g].iter_mut().enumerate() {
                        *v += sa * s[b];
                    }
                }
            }
            gram
        })
    }

    /// `Σ_r r(λ_a) r(λ_b)`: from the Gram matrix once a search computed it, else summed.
    fn gram_at(&self, a: usize, b: usize) -> f64 {
        match self.gram.get() {
            Some(gram) => gram[a * self.search.g + b],
            None => self.samples.iter().map(|s| s[a] * s[b]).sum(),
        }
    }

    /// The least-squares weights of light `l` at grid indices `nodes`, white pinned; `None`
    /// when the system is singular.
    fn weights(&self, l: usize, nodes: &[usize]) -> Option<[Vec<f64>; 3]> {
        let n = nodes.len();
        let mut a = DMatrix::<f64>::zeros(n + 1, n + 1);
        let mut b = DMatrix::<f64>::zeros(n + 1, 3);
        for (i, &ni) in nodes.iter().enumerate() {
            for (j, &nj) in nodes.iter().enumerate() {
                a[(i, j)] = self.gram_at(ni, nj);
            }
            a[(i, n)] = 1.0;
            a[(n, i)] = 1.0;
            for c in 0..3 {
                b[(i, c)] = self.cross[l][ni][c];
            }
        }
        let white = self.problems[l].white();
        for c in 0..3 {
            b[(n, c)] = white[c];
        }
        let x = a.lu().solve(&b)?;
        let w = [0, 1, 2].map(|c| (0..n).map(|i| x[(i, c)]).collect::<Vec<f64>>());
        w.iter().flatten().all(|v| v.is_finite()).then_some(w)
    }

    /// Every light's folded weights at `nodes` for `kind`; `None` when a system is singular.
    fn all_weights(&self, kind: Weights, nodes: &[usize]) -> Option<Vec<[Vec<f64>; 3]>> {
        match kind {
            Weights::PerLight => (0..self.problems.len())
                .map(|l| self.weights(l, nodes))
                .collect(),
            Weights::Radiance => {
                let w = self.radiance_weights(nodes)?;
                Some(
                    self.problems
                        .iter()
                        .map(|p| {
                            w.clone().map(|row| {
                                row.iter()
                                    .zip(nodes)
                                    .map(|(v, &i)| v * p.light[i])
                                    .collect()
                            })
                        })
                        .collect(),
                )
            }
        }
    }

    /// One radiance matrix W at `nodes` for every light: least squares over the lights and
    /// training reflectances of `XYZ_l(r) ≈ W (r · L_l)` at the nodes, each light's white
    /// pinned (`W L_l = white_l`; a least-norm solution where the pins alone fix W).
    fn radiance_weights(&self, nodes: &[usize]) -> Option<[Vec<f64>; 3]> {
        let n = nodes.len();
        let k = self.problems.len();
        let mut a = DMatrix::<f64>::zeros(n + k, n + k);
        let mut b = DMatrix::<f64>::zeros(n + k, 3);
        for (l, p) in self.problems.iter().enumerate() {
            for (i, &ni) in nodes.iter().enumerate() {
                for (j, &nj) in nodes.iter().enumerate() {
                    a[(i, j)] += p.light[ni] * self.gram_at(ni, nj) * p.light[nj];
                }
                a[(i, n + l)] = p.light[ni];
                a[(n + l, i)] = p.light[ni];
                for c in 0..3 {
                    b[(i, c)] += p.light[ni] * self.cross[l][ni][c];
                }
            }
            let white = p.white();
            for c in 0..3 {
                b[(n + l, c)] = white[c];
            }
        }
        let x = a.svd(true, true).solve(&b, 1e-12).ok()?;
        let w = [0, 1, 2].map(|c| (0..n).map(|i| x[(i, c)]).collect::<Vec<f64>>());
        w.iter().flatten().all(|v| v.is_finite()).then_some(w)
    }

    /// The mean CIEDE2000 over the training reflectances of light `l` with `weights` at grid
    /// indices `nodes`.
    fn training_de00(&self, l: usize, nodes: &[usize], weights: &[Vec<f64>; 3]) -> f64 {
        let white = self.problems[l].white();
        let total: f64 = self
            .samples
            .iter()
            .zip(&self.labs[l])
            .map(|(s, lab)| {
                let xyz =
                    [0, 1, 2].map(|c| nodes.iter().zip(&weights[c]).map(|(&i, w)| w * s[i]).sum());
                delta_e2000(*lab, lab_from_xyz(xyz, white))
            })
            .sum();
        total / self.samples.len() as f64
    }

    /// Each light's mean CIEDE2000 on the training reflectances with the group's least-squares
    /// weights at `nodes`; infinite where a system is singular.
    fn errors(&self, kind: Weights, nodes: &[usize]) -> Vec<f64> {
        match self.all_weights(kind, nodes) {
            Some(ws) => ws
                .iter()
                .enumerate()
                .map(|(l, w)| self.training_de00(l, nodes, w))
                .collect(),
            None => std::vec![f64::INFINITY; self.problems.len()],
        }
    }

    /// The lights' kernel-model problems, in the group's order.
    pub(crate) fn problems(&self) -> &[Problem] {
        &self.problems
    }

    /// The mean CIEDE2000 on the training reflectances of each light's own folded set: `own[l]`
    /// its nodes, as grid indices, with their kriging weights.
    pub(crate) fn own_errors(&self, own: &[Vec<usize>]) -> Vec<f64> {
        self.problems
            .iter()
            .zip(own)
            .enumerate()
            .map(|(l, (p, nodes))| {
                p.solve(nodes)
                    .map_or(f64::INFINITY, |(w, _)| self.training_de00(l, nodes, &w))
            })
            .collect()
    }

    /// The group of `n` wavelengths: nodes searched for `objective` against `own` (each light's
    /// own folded set, as grid indices: the objective's scale and a start of the search).
    pub fn optimize(
        &self,
        n: usize,
        own: &[Vec<usize>],
        objective: GroupObjective,
        kind: Weights,
    ) -> Result<Group, Error> {
        self.full_gram();
        let own_de = self.own_errors(own);
        let score = |nodes: &[usize]| {
            let ratios = self
                .errors(kind, nodes)
                .into_iter()
                .zip(&own_de)
                .map(|(e, o)| e / o);
            match objective {
                GroupObjective::Mean => ratios.sum::<f64>() / own_de.len() as f64,
                GroupObjective::Worst => ratios.fold(0.0, f64::max),
            }
        };
        let model_own: Vec<f64> = self
            .problems
            .iter()
            .zip(own)
            .map(|(p, o)| p.objective(o))
            .collect();
        let model_score = |nodes: &[usize]| {
            self.problems
                .iter()
                .zip(&model_own)
                .map(|(p, o)| p.objective(nodes) / o)
                .sum::<f64>()
        };
        // Two starts: the kernel model's nodes for the group (the sum of the lights' expected
        // errors, each against its own set's) and an even spread. More starts (each light's own
        // nodes, two more spreads) cost five times the time and moved no light's held-out error
        // by more than 0.02 ΔE00 at N = 8 (the report's light-group section measures the fit).
        let mut starts = std::vec![self.search.optimize_with(n, &model_score).0];
        let spread = self.search.spread(n, 0.5);
        if spread.len() == n {
            starts.push(spread);
        }
        let (nodes, _) = starts
            .into_iter()
            .map(|s| self.search.refine_with(s, &score))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap_or((Vec::new(), f64::INFINITY));
        if nodes.len() != n {
            return Err(Error::Numerical(std::format!(
                "no light group of {n} wavelengths: only {} grid points are usable",
                nodes.len()
            )));
        }
        self.group_at(&nodes, objective, kind)
    }

    /// The group at grid indices `nodes` (ascending): each light's least-squares weights,
    /// tied across the lights as `kind` says. What [`optimize`](Self::optimize) returns for the
    /// nodes it finds: a node cache keeps the nodes and refits here.
    pub fn group_at(
        &self,
        nodes: &[usize],
        objective: GroupObjective,
        kind: Weights,
    ) -> Result<Group, Error> {
        let all = self.all_weights(kind, nodes).ok_or_else(|| {
            Error::Numerical(std::format!(
                "no light group at {:?} nm: a least-squares system is singular",
                nodes
                    .iter()
                    .map(|&i| self.search.grid_nm[i])
                    .collect::<Vec<_>>(),
            ))
        })?;
        let members = self
            .problems
            .iter()
            .zip(all)
            .enumerate()
            .map(|(l, (p, w))| {
                Ok(Member {
                    light: p.light_name.clone().unwrap_or_default(),
                    light_at_nodes: nodes.iter().map(|&i| p.light[i]).collect(),
                    training_de00: self.training_de00(l, nodes, &w),
                    xyz_weights: w,
                })
            })
            .collect::<Result<Vec<Member>, Error>>()?;
        Ok(Group {
            wavelengths_nm: nodes.iter().map(|&i| self.search.grid_nm[i]).collect(),
            members,
            objective,
            weights: kind,
            training: GroupTraining::Reflectances,
        })
    }
}

/// A shared set's nodes as grid indices of its problem (its wavelengths are grid points).
pub fn nodes_of(problem: &Problem, set: &Shared) -> Vec<usize> {
    set.wavelengths_nm
        .iter()
        .filter_map(|&nm| problem.grid_nm.iter().position(|&g| (g - nm).abs() < 1e-9))
        .collect()
}
