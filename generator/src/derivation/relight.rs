//! A light's samples at a radiance set's nodes, for relighting: the N values `l` that, multiplied
//! into a reflectance's values at the nodes (`r ⊙ l`), give through the set the reflectance's
//! colour under the light.
//!
//! Point samples of the light's spectrum (its value at each node) are what a renderer would
//! take, and they fail on spiky lights: the set's weights were made for smooth radiances, and
//! a fluorescent lamp's lines between the nodes go unseen. So the samples are fitted instead:
//! `l` minimises, over the training reflectances, the squared XYZ error of `W (r ⊙ l)` against
//! the reflectance's XYZ under the light (1 nm), with a perfect white pinned: `W l` is the
//! light's own XYZ, scaled to Y = 1 with the folded sets' scale (a spectrum of constant 1 has
//! Y = 1). So the white of a relit material is the light's white exactly, and the docs can say
//! so.

use std::vec::Vec;

use nalgebra::DMatrix;

use super::derive::Derivation;
use super::sets::WavelengthSet;
use crate::base::error::Error;
use spectral_quadrature_spectra::Curve;

/// The fitted samples of `light` at `set`'s nodes (see the module), `set` a set for radiances
/// with AC1C2 weights, `training` the reflectances fitted on (at least one). Errors when the
/// light has no luminance or the system is singular.
pub(crate) fn light_at_nodes(
    d: &Derivation,
    set: &WavelengthSet,
    light: &Curve,
    training: &[Curve],
) -> Result<Vec<f64>, Error> {
    let eval = d.eval_set(set, "relight");
    let reference = d.observer.full_integration(d.settings.range_nm, 1.0)?;
    // The folded sets' scale: a spectrum of constant 1 has Y = 1.
    let unit = reference.xyz(|_| 1.0)[1];
    let white_raw = reference.xyz(|nm| light.at(nm));
    if !(white_raw[1] > 0.0 && white_raw[1].is_finite()) {
        return Err(Error::Numerical(std::format!(
            "light {} has no luminance to relight with",
            light.name
        )));
    }
    // The light scaled so that its white has Y = 1 (in the folded sets' scale).
    let scale = unit / white_raw[1];
    let white = white_raw.map(|v| v * scale);
    let n = set.wavelengths_nm.len();
    let w = &eval.xyz_weights;
    // Least squares in l with 3 equality constraints (the white): the normal equations with
    // their Lagrange multipliers, (N + 3) × (N + 3).
    let mut a = DMatrix::<f64>::zeros(n + 3, n + 3);
    let mut b = DMatrix::<f64>::zeros(n + 3, 1);
    for r in training {
        let rv: Vec<f64> = set.wavelengths_nm.iter().map(|&nm| r.at(nm)).collect();
        let target = reference.xyz(|nm| r.at(nm) * light.at(nm) * scale);
        for c in 0..3 {
            // Row c of W diag(r): w[c][i] r_i.
            let row: Vec<f64> = (0..n).map(|i| w[c][i] * rv[i]).collect();
            for i in 0..n {
                for j in 0..n {
                    a[(i, j)] += row[i] * row[j];
                }
                b[(i, 0)] += row[i] * target[c];
            }
        }
    }
    for c in 0..3 {
        for i in 0..n {
            a[(i, n + c)] = w[c][i];
            a[(n + c, i)] = w[c][i];
        }
        b[(n + c, 0)] = white[c];
    }
    let x = a
        .svd(true, true)
        .solve(&b, 1e-14)
        .map_err(|e| Error::Numerical(std::format!("relighting {}: {e}", light.name)))?;
    let l: Vec<f64> = (0..n).map(|i| x[(i, 0)]).collect();
    if l.iter().any(|v| !v.is_finite()) {
        return Err(Error::Numerical(std::format!(
            "relighting {} at {}'s nodes: the system is singular",
            light.name,
            set.name
        )));
    }
    Ok(l)
}
