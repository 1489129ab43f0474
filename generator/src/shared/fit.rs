//! Fitting the model's prior: the kernel length and empirical-covariance weight that maximise
//! the leave-one-out likelihood of the training reflectances. The crate's sets use the values
//! it finds ([`LENGTH_NM`](crate::shared::LENGTH_NM),
//! [`EMPIRICAL_WEIGHT`](crate::shared::EMPIRICAL_WEIGHT)); the unit tests re-run it, and only
//! they compile it.

use std::vec::Vec;

use nalgebra::{DMatrix, DVector};

use super::model::Kernel;
use spectral_quadrature_spectra::Curve;

/// The result of [`fit`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Fit {
    /// The Matérn 5/2 length, nm.
    pub length_nm: f64,
    /// The weight of the empirical covariance.
    pub weight: f64,
    /// The leave-one-out log likelihood (up to a constant).
    pub log_likelihood: f64,
}

/// The lengths [`fit`] searches for the crate's sets, nm.
pub(crate) const FIT_LENGTHS_NM: [f64; 9] = [40.0, 45.0, 50.0, 55.0, 60.0, 65.0, 70.0, 75.0, 80.0];

/// The empirical-covariance weights [`fit`] searches for the crate's sets.
pub(crate) const FIT_WEIGHTS: [f64; 11] = [
    0.0, 10.0, 20.0, 30.0, 50.0, 70.0, 100.0, 150.0, 200.0, 300.0, 1000.0,
];

/// White noise added to the kernel in [`fit`] (relative to its variance): reflectance data are
/// given to about 1 % of their spread, so the likelihood should not chase finer detail.
pub(crate) const FIT_NOISE: f64 = 1e-4;

/// The kernel length and empirical-covariance weight that maximise the leave-one-out likelihood
/// of `training`: each reflectance predicted by a Gaussian with the other reflectances' mean and
/// covariance `σ²(k + α S₋ₖ + ηI)` (σ² profiled, η = `FIT_NOISE`), on a 5 nm grid of
/// `range_nm`. `None` with fewer than 3 spectra or when no candidate is positive definite.
pub(crate) fn fit(
    training: &[Curve],
    range_nm: [f64; 2],
    lengths_nm: &[f64],
    weights: &[f64],
) -> Option<Fit> {
    let n = training.len();
    if n < 3 {
        return None;
    }
    let mut grid = Vec::new();
    let mut nm = range_nm[0];
    while nm <= range_nm[1] + 1e-9 {
        grid.push(nm);
        nm += 5.0;
    }
    let dim = grid.len();
    let ys: Vec<DVector<f64>> = training
        .iter()
        .map(|r| DVector::from_iterator(dim, grid.iter().map(|&nm| r.at(nm))))
        .collect();
    // Per held-out spectrum: its residual from the others' mean, and the others' empirical
    // covariance. Neither depends on the kernel or the weight.
    let held_out: Vec<(DVector<f64>, DMatrix<f64>)> = (0..n)
        .map(|h| {
            let others: Vec<&DVector<f64>> = (0..n).filter(|&i| i != h).map(|i| &ys[i]).collect();
            let m = others.len() as f64;
            let mean = others.iter().fold(DVector::zeros(dim), |acc, y| acc + *y) / m;
            let mut scatter = DMatrix::<f64>::zeros(dim, dim);
            for y in &others {
                let dev = *y - &mean;
                scatter += &dev * dev.transpose() / m;
            }
            (&ys[h] - &mean, scatter)
        })
        .collect();
    let mut best: Option<Fit> = None;
    for &length_nm in lengths_nm {
        let kernel = Kernel::Matern52 { length_nm };
        let mut k = DMatrix::<f64>::from_fn(dim, dim, |i, j| kernel.at(grid[i] - grid[j]));
        for i in 0..dim {
            k[(i, i)] += FIT_NOISE;
        }
        for &weight in weights {
            if let Some(ll) = loo_log_likelihood(&k, &held_out, weight) {
                if best.is_none_or(|b| ll > b.log_likelihood) {
                    best = Some(Fit {
                        length_nm,
                        weight,
                        log_likelihood: ll,
                    });
                }
            }
        }
    }
    best
}

/// The leave-one-out log likelihood (σ² profiled) of residuals `e` under covariances
/// `k + α S` (see [`fit`]).
fn loo_log_likelihood(
    k: &DMatrix<f64>,
    held_out: &[(DVector<f64>, DMatrix<f64>)],
    alpha: f64,
) -> Option<f64> {
    let mut quad = 0.0;
    let mut logdet = 0.0;
    for (e, scatter) in held_out {
        let chol = (k + scatter * alpha).cholesky()?;
        logdet += 2.0 * chol.l().diagonal().iter().map(|v| v.ln()).sum::<f64>();
        quad += e.dot(&chol.solve(e));
    }
    let count = (held_out.len() * k.nrows()) as f64;
    Some(-0.5 * count * (quad / count).ln() - 0.5 * logdet)
}
