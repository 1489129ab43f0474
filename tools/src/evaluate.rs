//! Sets the report builds to measure beside the crate's own, on the generator's measuring
//! (`spectral_quadrature_generator::evaluate`): every combination of per-channel Gauss rules for
//! any three weight functions (Figs. 6 and 7, and the budgets of section 5), a shared set
//! as measured on radiances, and [`Sampled`]: many sets judged on the same stimuli at once.

use std::collections::HashMap;
use std::vec::Vec;

use spectral_quadrature_generator::quadrature::{self, Measure};
use spectral_quadrature_generator::shared::Shared;
use spectral_quadrature_generator::{Derivation, Rule, WavelengthSet};
use spectral_quadrature_math::{delta_e2000, delta_e76, lab_from_xyz};
use spectral_quadrature_spectra::{Curve, Errors, EvalSet, Reference, Stimulus};

/// Per-channel Gauss rules of orders 1..=max_order for three weight functions given on the
/// derivation grid (columns of `w`), as `rules[c][n - 1]`.
pub fn channel_rules(d: &Derivation, w: &[[f64; 3]], max_order: usize) -> [Vec<Rule>; 3] {
    let s = &d.settings;
    [0, 1, 2].map(|c| {
        let col: Vec<f64> = w.iter().map(|v| v[c]).collect();
        let m = Measure::new(&d.grid_nm, &col, s.step_nm, s.range_nm);
        let rec = quadrature::stieltjes(&m, max_order);
        (1..=max_order)
            .map(|n| quadrature::gauss_rule(&m, &rec, n, s.range_nm))
            .collect()
    })
}

/// Every combination of defined per-channel rules (orders 1..=max in each channel) as sets,
/// with weights converted to XYZ by `to_xyz`.
pub fn combinations(rules: &[Vec<Rule>; 3], to_xyz: &[[f64; 3]; 3], family: &str) -> Vec<EvalSet> {
    let mut out = Vec::new();
    for a in rules[0].iter().filter(|r| r.is_defined()) {
        for b in rules[1].iter().filter(|r| r.is_defined()) {
            for c in rules[2].iter().filter(|r| r.is_defined()) {
                let orders = [a.order, b.order, c.order];
                let name = std::format!("{family} {}+{}+{}", a.order, b.order, c.order);
                if let Ok(set) = WavelengthSet::merge(&name, "", [Some(a), Some(b), Some(c)]) {
                    out.push(EvalSet::from_weights(
                        &name,
                        family,
                        Some(orders),
                        &set.wavelengths_nm,
                        &set.weights,
                        to_xyz,
                    ));
                }
            }
        }
    }
    out
}

/// A shared set as the report measures it, on radiances `r · L`: the folded weights divided by
/// the light at each wavelength, so that applied to `r · L` it equals the folded set applied to
/// r.
pub fn shared_on_radiance(set: &Shared, name: &str, family: &str) -> EvalSet {
    EvalSet {
        name: name.into(),
        family: family.into(),
        orders: None,
        wavelengths_nm: set.wavelengths_nm.clone(),
        xyz_weights: set.xyz_weights.clone().map(|row| {
            row.iter()
                .zip(&set.light_at_nodes)
                .map(|(v, l)| v / l)
                .collect()
        }),
    }
}

/// A light group's member as the report measures it, on radiances `r · L`, as
/// [`shared_on_radiance`]: its folded weights at the group's nodes `wavelengths_nm` divided by
/// the light at each.
pub fn member_on_radiance(
    member: &spectral_quadrature_generator::shared::Member,
    wavelengths_nm: &[f64],
    name: &str,
    family: &str,
) -> EvalSet {
    EvalSet {
        name: name.into(),
        family: family.into(),
        orders: None,
        wavelengths_nm: wavelengths_nm.to_vec(),
        xyz_weights: member.xyz_weights.clone().map(|row| {
            row.iter()
                .zip(&member.light_at_nodes)
                .map(|(v, l)| v / l)
                .collect()
        }),
    }
}

/// The stimuli of a [`Reference`] as the lights and reflectances they are made of, so that
/// judging sets samples each distinct light and reflectance once at their nodes instead of
/// interpolating both for every stimulus at every node of every set (a stimulus is a light times a reflectance,
/// `Stimulus::radiance`; a surface's white is its light, one per light): [`Reference::errors`]
/// for many sets at a fraction of the cost, with the same arithmetic in the same order (the
/// same errors, bit for bit; `tools/tests/evaluate.rs` holds it).
pub struct Sampled<'a> {
    reference: &'a Reference,
    stimuli: &'a [Stimulus],
    /// Per stimulus: its light's and its reflectance's index (`None`: a light seen directly).
    rows: Vec<(usize, Option<usize>)>,
    /// The distinct lights.
    lights: Vec<&'a Curve>,
    /// The distinct reflectances.
    reflectances: Vec<&'a Curve>,
}

impl<'a> Sampled<'a> {
    /// `stimuli` (those `reference` was made from), their lights and reflectances told apart.
    pub fn new(reference: &'a Reference, stimuli: &'a [Stimulus]) -> Sampled<'a> {
        // The distinct curves, compared whole (two curves of one name may differ).
        let mut lights: Vec<&Curve> = Vec::new();
        let mut reflectances: Vec<&Curve> = Vec::new();
        let mut by_name: HashMap<&str, Vec<usize>> = HashMap::new();
        let rows = stimuli
            .iter()
            .map(|s| {
                let l = match lights.iter().position(|c| *c == &s.light) {
                    Some(l) => l,
                    None => {
                        lights.push(&s.light);
                        lights.len() - 1
                    }
                };
                let r = s.reflectance.as_ref().map(|r| {
                    let same = by_name.entry(r.name.as_str()).or_default();
                    match same.iter().copied().find(|&k| reflectances[k] == r) {
                        Some(k) => k,
                        None => {
                            reflectances.push(r);
                            same.push(reflectances.len() - 1);
                            reflectances.len() - 1
                        }
                    }
                });
                (l, r)
            })
            .collect();
        Sampled {
            reference,
            stimuli,
            rows,
            lights,
            reflectances,
        }
    }

    /// The errors of `set` against the reference, as [`Reference::errors`] gives them.
    pub fn errors(&self, set: &EvalSet) -> Errors {
        self.judge(&self.nodes(std::slice::from_ref(set)), set, true)
    }

    /// The ΔE*ab of `set` on each stimulus, as [`Reference::errors`] gives them (`de76`),
    /// without the cost of CIEDE2000.
    pub fn de76(&self, set: &EvalSet) -> Vec<f64> {
        self.judge(&self.nodes(std::slice::from_ref(set)), set, false)
            .de76
    }

    /// Every light and reflectance at every node of `sets` (sets judged together share most of
    /// their nodes: the combinations of per-channel rules do).
    fn nodes(&self, sets: &[EvalSet]) -> Nodes {
        let mut wavelengths = Vec::new();
        let mut columns = HashMap::new();
        for &nm in sets.iter().flat_map(|s| &s.wavelengths_nm) {
            columns.entry(nm.to_bits()).or_insert_with(|| {
                wavelengths.push(nm);
                wavelengths.len() - 1
            });
        }
        let table = |curves: &[&Curve]| -> Vec<f64> {
            curves
                .iter()
                .flat_map(|c| wavelengths.iter().map(|&nm| c.at(nm)))
                .collect()
        };
        Nodes {
            width: wavelengths.len(),
            lights: table(&self.lights),
            reflectances: table(&self.reflectances),
            columns,
        }
    }

    /// The errors of `set` (every node of it in `nodes`), CIEDE2000 left out (empty) unless
    /// `de00`.
    fn judge(&self, nodes: &Nodes, set: &EvalSet, de00: bool) -> Errors {
        let w = nodes.width;
        let cols: Vec<usize> = set
            .wavelengths_nm
            .iter()
            .map(|nm| nodes.columns[&nm.to_bits()])
            .collect();
        // `EvalSet::xyz`: each channel's sum over the nodes in their order.
        let xyz = |values: &[f64]| -> [f64; 3] {
            [0, 1, 2].map(|c| {
                set.xyz_weights[c]
                    .iter()
                    .zip(values)
                    .map(|(w, v)| w * v)
                    .sum()
            })
        };
        let light_values: Vec<Vec<f64>> = (0..self.lights.len())
            .map(|l| cols.iter().map(|&c| nodes.lights[l * w + c]).collect())
            .collect();
        // A surface's white is its light (`Stimulus::white`): one XYZ per light.
        let light_whites: Vec<[f64; 3]> = light_values.iter().map(|v| xyz(v)).collect();
        let mut e = Errors {
            de76: Vec::with_capacity(self.stimuli.len()),
            de00: Vec::with_capacity(if de00 { self.stimuli.len() } else { 0 }),
        };
        let mut radiance = std::vec![0.0; cols.len()];
        for ((&(l, r), &level), exact) in self
            .rows
            .iter()
            .zip(&self.reference.levels)
            .zip(&self.reference.labs)
        {
            let light = &light_values[l];
            let white = match r {
                Some(r) => {
                    // `Stimulus::radiance`: the light times the reflectance at each node.
                    let row = &nodes.reflectances[r * w..(r + 1) * w];
                    for ((v, &lv), &c) in radiance.iter_mut().zip(light).zip(&cols) {
                        *v = lv * row[c];
                    }
                    light_whites[l]
                }
                None => {
                    // A light seen directly: its radiance is the light times 1, its white
                    // equal energy at the stimulus' level.
                    for (v, &lv) in radiance.iter_mut().zip(light) {
                        *v = lv * 1.0;
                    }
                    xyz(&std::vec![level; cols.len()])
                }
            };
            let approx = lab_from_xyz(xyz(&radiance), white);
            e.de76.push(delta_e76(*exact, approx));
            if de00 {
                e.de00.push(delta_e2000(*exact, approx));
            }
        }
        e
    }
}

/// Every light and reflectance of a [`Sampled`] at the nodes of some sets.
struct Nodes {
    /// A node's bits → its column.
    columns: HashMap<u64, usize>,
    /// The number of columns.
    width: usize,
    /// Per light, its value at every column (row-major).
    lights: Vec<f64>,
    /// Per reflectance, its value at every column (row-major).
    reflectances: Vec<f64>,
}

/// The errors of each of `sets` against `reference` on `stimuli` ([`Reference::errors`] for
/// each, through one [`Sampled`]), on every core. CIEDE2000 only for the sets `de00`
/// picks by their index (the others' `de00` is empty: a caller that needs ΔE*ab alone saves
/// its cost); `done` is called with the number of sets just judged, for a progress line.
pub fn errors_of_sets(
    reference: &Reference,
    stimuli: &[Stimulus],
    sets: &[EvalSet],
    de00: &(dyn Fn(usize) -> bool + Sync),
    done: &(dyn Fn(usize) + Sync),
) -> Vec<Errors> {
    let sampled = Sampled::new(reference, stimuli);
    // Every light and reflectance at every node once: the report's 9216 combinations of rules
    // have 1024 distinct nodes between them.
    let nodes = sampled.nodes(sets);
    // Chunks of sets, so that progress is told often without a call per set.
    const CHUNK: usize = 64;
    let chunks: Vec<(usize, &[EvalSet])> = sets.chunks(CHUNK).enumerate().collect();
    crate::par_map(&chunks, |&(c, chunk)| {
        let e: Vec<Errors> = chunk
            .iter()
            .enumerate()
            .map(|(k, s)| sampled.judge(&nodes, s, de00(c * CHUNK + k)))
            .collect();
        done(chunk.len());
        e
    })
    .into_iter()
    .flatten()
    .collect()
}
