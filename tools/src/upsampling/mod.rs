//! RGB materials under another light (report section 8): the crate's upsampling
//! ([`spectral_quadrature_generator::upsampling`]) beside the peers a renderer would use instead,
//! each judged by relighting.
//!
//! **The relighting test** ([`relit_de00`]). A real reflectance's linear sRGB under D65
//! (integrated every 1 nm, white-balanced: a perfect white is (1, 1, 1); [`srgb_under_d65`]) is
//! upsampled to a radiance set's N nodes, the node values are multiplied by another light's
//! samples and integrated by the set's radiance weights, and the colour is compared in CIEDE2000
//! with the real reflectance under that light integrated every 1 nm (each white integrated by
//! the same rule as its colour, as in Table 2).
//!
//! The peers, each evaluated at the same nodes:
//! - [`jakob_hanika`]: Jakob and Hanika (2019), pbrt-v4's and Mitsuba 3's `RGBAlbedoSpectrum`:
//!   a sigmoid of a quadratic in wavelength, fitted per colour by Gauss-Newton in CIELAB;
//! - [`smooth`]: Mallett and Yuksel (2019), three basis spectra, and Smits (1999), seven
//!   piecewise-constant spectra, each derived here by its paper's recipe (the smoothest spectra
//!   in [0, 1] with the given colours).
//!
//! [`groups`] judges a light group's map the same way, through each light's member of the
//! group: texels under the group's first light, relit under every light of the group.

pub mod groups;
pub mod jakob_hanika;
pub mod smooth;

use spectral_quadrature_generator::upsampling::Baked;
use spectral_quadrature_generator::Derivation;
use spectral_quadrature_math::{delta_e2000, lab_from_xyz};
use spectral_quadrature_spectra::{builtin_illuminant, Curve, EvalSet};

use crate::Error;

/// White-balanced linear sRGB of reflectances under D65, integrated every 1 nm: the colours an
/// sRGB texture holds for them.
pub fn srgb_under_d65(d: &Derivation, reflectances: &[Curve]) -> Result<Vec<[f64; 3]>, Error> {
    let (_, m) = d.display("SRGB")?;
    let d65 = d65(d)?;
    Ok(spectral_quadrature_generator::upsampling::exact_rgb(
        d,
        m,
        &d65,
        reflectances,
    )?)
}

/// White-balanced sRGB under D65 of a unit spectrum at each 1 nm: the grid and rows R, G, B.
pub(crate) fn srgb_weights(d: &Derivation) -> Result<(Vec<f64>, [Vec<f64>; 3]), Error> {
    let (_, m) = d.display("SRGB")?;
    let d65 = d65(d)?;
    let full = d.observer.full_integration(d.settings.range_nm, 1.0)?;
    let mut w: [Vec<f64>; 3] = Default::default();
    for (c, row) in w.iter_mut().enumerate() {
        *row = (0..full.len())
            .map(|i| {
                (0..3)
                    .map(|k| m.xyz_to_rgb[c][k] * full.xyz_weights[k][i])
                    .sum::<f64>()
                    * d65.at(full.wavelengths_nm[i])
            })
            .collect();
        let white: f64 = row.iter().sum();
        for v in row.iter_mut() {
            *v /= white;
        }
    }
    Ok((full.wavelengths_nm, w))
}

/// CIE D65 from the crate's data.
pub fn d65(d: &Derivation) -> Result<Curve, Error> {
    Ok(builtin_illuminant(
        &d.settings.data_dir,
        "D65",
        d.settings.range_nm,
    )?)
}

/// CIEDE2000 of each reflectance relit: `values[k]`, node values of `reflectances[k]` at the
/// set's wavelengths, times `light` there, through the set's radiance weights (`set`, XYZ rows),
/// against the reflectance under `light` through `reference` (the 1 nm integration).
pub fn relit_de00(
    set: &EvalSet,
    reference: &EvalSet,
    reflectances: &[Curve],
    values: &[Vec<f64>],
    light: &Curve,
) -> Vec<f64> {
    let white_ref = reference.xyz(|l| light.at(l));
    let white_set = set.xyz(|l| light.at(l));
    reflectances
        .iter()
        .zip(values)
        .map(|(r, v)| {
            let exact = lab_from_xyz(reference.xyz(|l| r.at(l) * light.at(l)), white_ref);
            let samples: Vec<f64> = v
                .iter()
                .zip(&set.wavelengths_nm)
                .map(|(x, &l)| x * light.at(l))
                .collect();
            let xyz = [0, 1, 2].map(|c| {
                set.xyz_weights[c]
                    .iter()
                    .zip(&samples)
                    .map(|(w, s)| w * s)
                    .sum::<f64>()
            });
            delta_e2000(exact, lab_from_xyz(xyz, white_set))
        })
        .collect()
}

/// The mean and the 95th percentile (nearest rank) of `v`.
pub fn mean_p95(v: &[f64]) -> (f64, f64) {
    if v.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let rank = ((0.95 * s.len() as f64).ceil() as usize).clamp(1, s.len());
    (s.iter().sum::<f64>() / s.len() as f64, s[rank - 1])
}

/// Whether some linear map U (N × 3) is bounded and exact at once: `encoding · U = I` (every
/// colour round-trips) and `U · rgb` in [0, 1]ᴺ for every RGB in the unit cube (U ≥ 0 and each
/// row sums to at most 1). Decided as a feasibility programme: the rows `[U | s]` with a slack
/// s ≥ 0 lie in the probability simplex, and the box programme finds the nearest such matrix to
/// meeting `encoding · [U | s] = [I | 0]`. Returns the largest entry of that residual: 0 (to
/// about 1e-9) where such a map exists.
#[allow(clippy::needless_range_loop)]
pub fn bounded_exact_linear_residual(encoding: &[Vec<f64>; 3]) -> Result<f64, Error> {
    let n = encoding[0].len();
    // Variables: P[i][k], i < N, k < 4, at index 4i + k.
    let vars = 4 * n;
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let mut rhs: Vec<f64> = Vec::new();
    for c in 0..3 {
        for k in 0..4 {
            let mut row = std::vec![0.0; vars];
            for i in 0..n {
                row[4 * i + k] = encoding[c][i];
            }
            rows.push(row);
            rhs.push(if k == c { 1.0 } else { 0.0 });
        }
    }
    for i in 0..n {
        let mut row = std::vec![0.0; vars];
        for k in 0..4 {
            row[4 * i + k] = 1.0;
        }
        rows.push(row);
        rhs.push(1.0);
    }
    let u = std::vec![0.25; vars];
    let s = spectral_quadrature_generator::upsampling::nearest_in_box(&u, &rows, &rhs)?;
    Ok(s.residual.iter().fold(0.0f64, |m, r| m.max(r.abs())))
}

/// The node values the runtime's f32 `Upsampling` gives at each RGB, on a bake's codes: what
/// firmware or a shader would get from the same table. `None` for a node count the runtime's
/// type is not instantiated for here (4, 6 and 8 are: the sizes the report and the Cornell box
/// compare), or for a bake for another display than sRGB (the one both bake for).
pub fn runtime_values(b: &Baked, rgb: &[[f64; 3]]) -> Result<Option<Vec<Vec<f64>>>, Error> {
    if b.display != "SRGB" {
        return Ok(None);
    }
    fn run<const N: usize>(b: &Baked, rgb: &[[f64; 3]]) -> Result<Vec<Vec<f64>>, Error> {
        let table: Vec<[u16; N]> = b
            .codes
            .iter()
            .map(|c| core::array::from_fn(|i| c[i]))
            .collect();
        // The runtime's tables are 'static (baked into the binary); the tool leaks its few.
        let table: &'static [[u16; N]] = Box::leak(table.into_boxed_slice());
        let runtime = |e: spectral_quadrature::Error| {
            Error::Derive(spectral_quadrature_generator::Error::Numerical(
                e.to_string(),
            ))
        };
        // The set the bake is for, as the runtime holds it: the nodes, the bake's encoding
        // (node values to the display's RGB under the reference light), that light, and the
        // display (sRGB: the one the report and the Cornell box bake for).
        let light: &'static str = Box::leak(b.light.clone().into_boxed_str());
        let set = spectral_quadrature::FoldedSet::new(
            core::array::from_fn(|i| b.wavelengths_nm[i] as f32),
            core::array::from_fn(|c| core::array::from_fn(|i| b.encoding[c][i] as f32)),
            spectral_quadrature::Samples::Reflectance { light },
            spectral_quadrature::tables::displays::SRGB,
        )
        .map_err(runtime)?;
        let u = spectral_quadrature::Upsampling::new(set, b.grid, table, None).map_err(runtime)?;
        Ok(rgb
            .iter()
            .map(|p| {
                u.reflectance(p.map(|x| x as f32))
                    .iter()
                    .map(|&v| f64::from(v))
                    .collect()
            })
            .collect())
    }
    match b.wavelengths_nm.len() {
        4 => run::<4>(b, rgb).map(Some),
        6 => run::<6>(b, rgb).map(Some),
        8 => run::<8>(b, rgb).map(Some),
        _ => Ok(None),
    }
}
