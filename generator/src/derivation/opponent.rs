//! Cone fundamentals (Eq. 1), the covariance matrix (Eq. 4-5) and the Karhunen-Loeve transform
//! to the opponent space AC1C2 (Eq. 3, 9, 10).

use std::string::String;
use std::vec::Vec;

use nalgebra::{DMatrix, Matrix3, SymmetricEigen};

use crate::base::error::Error;

/// Eq. 1: the fundamental spectral sensitivities s̄, m̄, l̄ as rows, from x̄, ȳ, z̄.
/// (The transcription prints z̄ twice on the right; the columns are x̄, ȳ, z̄.)
pub(crate) const MEYER_EQ1_XYZ_TO_SML: [[f64; 3]; 3] = [
    [0.0000, 0.0000, 0.0127],
    [-0.2606, 0.7227, 0.0562],
    [0.1150, 0.9364, -0.0203],
];

/// The covariance function K(λ, μ) of Eq. 5: the assumed statistics of the spectra.
#[derive(Debug, Clone, PartialEq)]
pub enum Covariance {
    /// K(λ, μ) = δ(λ − μ): spectra as white noise; the paper's choice. The matrix of Eq. 4 is
    /// then the Gram matrix of s̄, m̄, l̄.
    Delta,
    /// K(λ, μ) = exp(−|λ − μ| / ℓ): spectra correlated over a length ℓ in nm (smooth spectra).
    Exponential {
        /// Correlation length ℓ in nm; must be positive and finite.
        length_nm: f64,
    },
    /// The covariance (mean removed) of a set of spectra sampled on the derivation grid: each
    /// inner vector has one value per grid wavelength. Needs at least two spectra.
    Empirical(Vec<Vec<f64>>),
}

impl Covariance {
    /// A short description for generated headers, e.g. `delta` or `exponential(40 nm)`.
    pub(crate) fn describe(&self) -> String {
        match self {
            Covariance::Delta => "delta".into(),
            Covariance::Exponential { length_nm } => std::format!("exponential({length_nm} nm)"),
            Covariance::Empirical(s) => std::format!("empirical({} spectra)", s.len()),
        }
    }
}

/// Eq. 1 applied at every grid wavelength: `[s̄, m̄, l̄]` per row.
pub(crate) fn cone_fundamentals(xyz: &[[f64; 3]], xyz_to_sml: &[[f64; 3]; 3]) -> Vec<[f64; 3]> {
    xyz.iter().map(|v| apply(xyz_to_sml, v)).collect()
}

/// Eq. 4-5 on a grid of spacing `step` nm: C_ij = Σ_λ Σ_μ K(λ, μ) f_i(λ) f_j(μ) dλ dμ, with the
/// δ covariance discretized as δ_λμ / dλ, so that C is the Gram matrix Σ f_i f_j dλ.
pub(crate) fn covariance_matrix(
    cones: &[[f64; 3]],
    wavelengths: &[f64],
    step: f64,
    covariance: &Covariance,
) -> Result<Matrix3<f64>, Error> {
    let n = cones.len();
    let f = DMatrix::from_fn(n, 3, |i, j| cones[i][j]);
    let c = match covariance {
        Covariance::Delta => f.transpose() * &f * step,
        Covariance::Exponential { length_nm } => {
            if !(length_nm.is_finite() && *length_nm > 0.0) {
                return Err(Error::Settings(std::format!(
                    "exponential covariance needs a positive finite length, got {length_nm} nm"
                )));
            }
            let k = DMatrix::from_fn(n, n, |i, j| {
                (-(wavelengths[i] - wavelengths[j]).abs() / length_nm).exp()
            });
            f.transpose() * k * &f * (step * step)
        }
        Covariance::Empirical(spectra) => {
            if spectra.len() < 2 {
                return Err(Error::Settings(
                    "empirical covariance needs at least two spectra".into(),
                ));
            }
            if let Some(bad) = spectra.iter().position(|s| s.len() != n) {
                return Err(Error::Settings(std::format!(
                    "empirical covariance: spectrum {} has {} samples, the grid has {n}",
                    bad + 1,
                    spectra[bad].len()
                )));
            }
            let m = spectra.len();
            let mean: Vec<f64> = (0..n)
                .map(|i| spectra.iter().map(|s| s[i]).sum::<f64>() / m as f64)
                .collect();
            let x = DMatrix::from_fn(m, n, |r, i| spectra[r][i] - mean[i]);
            let k = x.transpose() * x / (m as f64 - 1.0);
            f.transpose() * k * &f * (step * step)
        }
    };
    Ok(Matrix3::from_fn(|i, j| c[(i, j)]))
}

/// The KL transform: eigenvectors of the covariance as the rows of T (Eq. 3), ordered by
/// eigenvalue, scaled and signed by the paper's convention.
#[derive(Debug, Clone, PartialEq)]
pub struct Opponent {
    /// Eigenvalues of the covariance matrix, largest first (Eq. 10), in the units of Eq. 5.
    pub eigenvalues: [f64; 3],
    /// Unit eigenvectors in SML coordinates, one per row, in the order of `eigenvalues`, signed
    /// like the scaled rows.
    pub eigenvectors_sml: [[f64; 3]; 3],
    /// Scale applied to each unit eigenvector so the sensitivity peaks at magnitude 1.
    pub row_scale: [f64; 3],
    /// T in SML coordinates: AC1C2 = T · SML.
    pub sml_to_ac1c2: [[f64; 3]; 3],
    /// Eq. 9: AC1C2 = M · XYZ.
    pub xyz_to_ac1c2: [[f64; 3]; 3],
    /// The inverse of Eq. 9.
    pub ac1c2_to_xyz: [[f64; 3]; 3],
}

/// Solves the eigenproblem and fixes scale and sign of each row (the paper's conventions,
/// `docs/reproducing-the-paper.md`):
///
/// * rows ordered by eigenvalue: A, C1, C2;
/// * signs: A positive; C1 positive where M exceeds L (its m̄ coefficient above its l̄ one),
///   so negative in the red; C2 positive in the blue (positive s̄ coefficient);
/// * scale: max ā = 1, min c̄1 = −1, max c̄2 = 1, the extremes taken over `peak_xyz`, which
///   should be the finest table available (the 1 nm table: a 5 nm grid misses c̄1's trough).
pub(crate) fn karhunen_loeve(
    covariance: &Matrix3<f64>,
    xyz_to_sml: &[[f64; 3]; 3],
    peak_xyz: &[[f64; 3]],
) -> Result<Opponent, Error> {
    let eig = SymmetricEigen::new(*covariance);
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
    let eigenvalues = order.map(|k| eig.eigenvalues[k]);
    if eigenvalues.iter().any(|v| !v.is_finite() || *v <= 0.0) {
        return Err(Error::Numerical(std::format!(
            "covariance matrix is not positive definite: eigenvalues {eigenvalues:?}"
        )));
    }
    let mut vectors = order.map(|k| {
        let c = eig.eigenvectors.column(k);
        [c[0], c[1], c[2]]
    });
    // Signs.
    let sign_a = vectors[0].iter().sum::<f64>().signum();
    let sign_c1 = (vectors[1][1] - vectors[1][2]).signum();
    let sign_c2 = vectors[2][0].signum();
    for (v, s) in vectors.iter_mut().zip([sign_a, sign_c1, sign_c2]) {
        for x in v.iter_mut() {
            *x *= s;
        }
    }
    let m = Matrix3::from_fn(|i, j| xyz_to_sml[i][j]);
    let unit_xyz = Matrix3::from_fn(|i, j| {
        vectors[i][0] * m[(0, j)] + vectors[i][1] * m[(1, j)] + vectors[i][2] * m[(2, j)]
    });
    // Extremes of each unit sensitivity over the fine table.
    let mut max = [f64::NEG_INFINITY; 3];
    let mut min = [f64::INFINITY; 3];
    for v in peak_xyz {
        for r in 0..3 {
            let s = unit_xyz[(r, 0)] * v[0] + unit_xyz[(r, 1)] * v[1] + unit_xyz[(r, 2)] * v[2];
            max[r] = max[r].max(s);
            min[r] = min[r].min(s);
        }
    }
    let row_scale = [1.0 / max[0], -1.0 / min[1], 1.0 / max[2]];
    if row_scale.iter().any(|s| !s.is_finite() || *s <= 0.0) {
        return Err(Error::Numerical(std::format!(
            "opponent sensitivities do not have the expected peaks (max a {}, min c1 {}, max c2 {})",
            max[0], min[1], max[2]
        )));
    }
    let sml_to_ac1c2 = [0, 1, 2].map(|r| vectors[r].map(|x| x * row_scale[r]));
    let t = Matrix3::from_fn(|i, j| sml_to_ac1c2[i][j]);
    let xyz_to_ac1c2 = t * m;
    let inverse = xyz_to_ac1c2
        .try_inverse()
        .ok_or_else(|| Error::Numerical("the XYZ to AC1C2 matrix is singular".into()))?;
    Ok(Opponent {
        eigenvalues,
        eigenvectors_sml: vectors,
        row_scale,
        sml_to_ac1c2,
        xyz_to_ac1c2: to_array(&xyz_to_ac1c2),
        ac1c2_to_xyz: to_array(&inverse),
    })
}

/// The opponent sensitivities ā, c̄1, c̄2 at each row of `xyz`.
pub(crate) fn sensitivities(opponent: &Opponent, xyz: &[[f64; 3]]) -> Vec<[f64; 3]> {
    xyz.iter()
        .map(|v| apply(&opponent.xyz_to_ac1c2, v))
        .collect()
}

/// `m · v` for a 3×3 row-major matrix.
pub(crate) fn apply(m: &[[f64; 3]; 3], v: &[f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|r| m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2])
}

fn to_array(m: &Matrix3<f64>) -> [[f64; 3]; 3] {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| m[(i, j)]))
}
