//! The upsampling of one set for one display: the encoding weights under the reference light,
//! the least-squares map fitted on the training reflectances, and the grid of node values, each
//! projected onto the node values in [0, 1] that the set encodes back to the grid point's colour
//! (or, where none does, to the nearest colour one does).

use std::string::String;
use std::vec::Vec;

use nalgebra::{DMatrix, DVector, Matrix3, Matrix4, Vector3, Vector4};

use super::qp::nearest_in_box;
use crate::base::error::Error;
use crate::derivation::derive::Derivation;
use crate::derivation::display::DisplayMatrices;
use crate::derivation::sets::WavelengthSet;
use spectral_quadrature_math::{delta_e2000, lab_from_xyz};
use spectral_quadrature_spectra::Curve;

/// The light a set for radiances is upsampled under: the RGB is a surface's colour under it,
/// and the renderer multiplies the node reflectances by its own light's samples.
pub(crate) const RADIANCE_REFERENCE_LIGHT: &str = "D65";

/// Grid points per axis the crate bakes unless a scene says otherwise.
pub const DEFAULT_GRID: usize = 9;

/// The grid sizes a scene may ask for: 2 (the cube's corners alone) to 65 points per axis.
pub(crate) const GRID_SIZES: core::ops::RangeInclusive<usize> = 2..=65;

/// The table's code for a node value of 1: node value = code / 65535.
pub(crate) const CODE_ONE: f64 = 65535.0;

/// A grid point counts as reachable when its projection's colour is within this ΔE00 of it. The
/// projection meets a reachable colour to about 1e-8 ΔE00 (the programme's ε); an unreachable
/// one stays at least its distance from the set's gamut, far more than this.
pub(crate) const REACHABLE_DELTA_E00: f64 = 1e-4;

/// Encoding weights: `rgb = weights · r` for node reflectances r under the reference light,
/// white-balanced so that r = 1 gives RGB (1, 1, 1).
///
/// `light_at_nodes`: `None` for a set with its light folded in (its folded weights take
/// reflectances already); for a set for radiances, the reference light at the nodes (any
/// scale). Errors if a channel of the white is not positive.
pub(crate) fn encoding(
    d: &Derivation,
    set: &WavelengthSet,
    display: &DisplayMatrices,
    light_at_nodes: Option<&[f64]>,
) -> Result<[Vec<f64>; 3], Error> {
    let mut w = d.folded(set, display);
    if let Some(l) = light_at_nodes {
        for row in w.iter_mut() {
            for (v, l) in row.iter_mut().zip(l) {
                *v *= l;
            }
        }
    }
    for (c, row) in w.iter_mut().enumerate() {
        let white: f64 = row.iter().sum();
        if !(white > 0.0 && white.is_finite()) {
            return Err(Error::Numerical(std::format!(
                "{}: channel {c} of the white under the reference light is {white}, not positive",
                set.name
            )));
        }
        for v in row.iter_mut() {
            *v /= white;
        }
    }
    Ok(w)
}

/// The white-balanced linear RGB of reflectances under `light`, integrated every 1 nm over the
/// derivation's range: `rgb / rgb(white)` per channel, so that a perfect white is (1, 1, 1).
pub fn exact_rgb(
    d: &Derivation,
    display: &DisplayMatrices,
    light: &Curve,
    reflectances: &[Curve],
) -> Result<Vec<[f64; 3]>, Error> {
    let full = d.observer.full_integration(d.settings.range_nm, 1.0)?;
    // The observer's weights times the light, per channel and wavelength, once; each curve is
    // then read once per wavelength, in plain loops (the build runs this at opt-level 0).
    let nms = &full.wavelengths_nm;
    let wl: Vec<[f64; 3]> = (0..nms.len())
        .map(|k| {
            let l = light.at(nms[k]);
            [0, 1, 2].map(|c| full.xyz_weights[c][k] * l)
        })
        .collect();
    let rgb_of = |r: &dyn Fn(f64) -> f64| -> [f64; 3] {
        let mut xyz = [0.0f64; 3];
        for (k, &nm) in nms.iter().enumerate() {
            let v = r(nm);
            let w = &wl[k];
            xyz[0] += w[0] * v;
            xyz[1] += w[1] * v;
            xyz[2] += w[2] * v;
        }
        [0, 1, 2].map(|c| (0..3).map(|k| display.xyz_to_rgb[c][k] * xyz[k]).sum())
    };
    let white = rgb_of(&|_| 1.0);
    if white
        .iter()
        .any(|w| w.partial_cmp(&0.0) != Some(core::cmp::Ordering::Greater))
    {
        return Err(Error::Numerical(std::format!(
            "the white under {} has RGB {white:?}: a channel is not positive",
            light.name
        )));
    }
    Ok(reflectances
        .iter()
        .map(|r| {
            let rgb = rgb_of(&|nm| r.at(nm));
            [0, 1, 2].map(|c| rgb[c] / white[c])
        })
        .collect())
}

/// The least-squares map from white-balanced RGB to node reflectances, `r ≈ map · rgb` (one
/// row of three per node), fitted on `(rgb, node values)` pairs with every row summing to 1,
/// so that white gives 1 at every node and a grey g gives g (a flat spectrum). Errors if the
/// pairs do not determine the map (fewer than three independent colours).
pub(crate) fn least_squares_map(
    rgb: &[[f64; 3]],
    nodes: &[Vec<f64>],
) -> Result<Vec<[f64; 3]>, Error> {
    let n = nodes.first().map_or(0, Vec::len);
    let mut g = [[0.0; 3]; 3];
    for x in rgb {
        for p in 0..3 {
            for q in 0..3 {
                g[p][q] += x[p] * x[q];
            }
        }
    }
    // minimise Σ_k (y_k − m·x_k)² subject to m·(1, 1, 1) = 1: [G 1; 1ᵀ 0] [m; μ] = [h; 1].
    let mut kkt = Matrix4::<f64>::zeros();
    for p in 0..3 {
        for q in 0..3 {
            kkt[(p, q)] = g[p][q];
        }
        kkt[(p, 3)] = 1.0;
        kkt[(3, p)] = 1.0;
    }
    let lu = kkt.lu();
    (0..n)
        .map(|i| {
            let mut h = Vector4::new(0.0, 0.0, 0.0, 1.0);
            for (x, y) in rgb.iter().zip(nodes) {
                for p in 0..3 {
                    h[p] += x[p] * y[i];
                }
            }
            let m = lu.solve(&h).filter(|m| m.iter().all(|v| v.is_finite()));
            m.map(|m| [m[0], m[1], m[2]]).ok_or_else(|| {
                Error::Numerical("the training colours do not determine a linear map".into())
            })
        })
        .collect()
}

/// The training colours' CIELAB distance over which the local fit's weights fall by e^(−½):
/// the local map at a grid point is fitted mostly on the reflectances whose colour lies within
/// about this ΔE*ab. Chosen by the cross-validation of report section 8 (`docs/upsampling.md`).
pub(crate) const LOCAL_BANDWIDTH: f64 = 10.0;

/// How strongly the local fit is pulled toward the global map, as a share of the local weights'
/// sum: it keeps a local fit determined where the nearby training colours alone would not be.
pub(crate) const LOCAL_PRIOR: f64 = 0.01;

/// The map for colours near `rgb`: least squares on the training pairs weighted by
/// `exp(−½ (ΔE*ab / bandwidth)²)` of their colour's distance from `rgb`, pulled toward the
/// global map `global` with weight `prior` times the weights' sum, every row summing to 1.
/// `bandwidth` infinite gives the global map.
#[allow(clippy::too_many_arguments, clippy::needless_range_loop)]
pub(crate) fn local_map(
    display: &DisplayMatrices,
    rgb: [f64; 3],
    training_rgb: &[[f64; 3]],
    training_labs: &[[f64; 3]],
    nodes: &[Vec<f64>],
    global: &[[f64; 3]],
    bandwidth: f64,
    prior: f64,
) -> Result<Vec<[f64; 3]>, Error> {
    if !bandwidth.is_finite() {
        return Ok(global.to_vec());
    }
    let here = lab_of_rgb(display, rgb);
    let n = global.len();
    // One pass over the training pairs, in plain loops (the build runs this at opt-level 0):
    // the weighted sums of x xᵀ and of x y for every node. A pair farther than eight
    // bandwidths weighs less than e⁻³² and is left out.
    let far = (8.0 * bandwidth).powi(2);
    let mut xx = [[0.0f64; 3]; 3];
    let mut xy = std::vec![[0.0f64; 3]; n];
    let mut total = 0.0;
    for k in 0..training_rgb.len() {
        let l = training_labs[k];
        let d2 = (l[0] - here[0]).powi(2) + (l[1] - here[1]).powi(2) + (l[2] - here[2]).powi(2);
        if d2 > far {
            continue;
        }
        let wk = (-0.5 * d2 / (bandwidth * bandwidth)).exp();
        total += wk;
        let x = training_rgb[k];
        for p in 0..3 {
            let wx = wk * x[p];
            for q in 0..3 {
                xx[p][q] += wx * x[q];
            }
            let y = &nodes[k];
            for i in 0..n {
                xy[i][p] += wx * y[i];
            }
        }
    }
    let alpha = prior * f64::max(total, 1e-12);
    let mut kkt = Matrix4::<f64>::zeros();
    for p in 0..3 {
        for q in 0..3 {
            kkt[(p, q)] = xx[p][q];
        }
        kkt[(p, p)] += alpha;
        kkt[(p, 3)] = 1.0;
        kkt[(3, p)] = 1.0;
    }
    let lu = kkt.lu();
    (0..n)
        .map(|i| {
            let h = Vector4::new(
                alpha * global[i][0] + xy[i][0],
                alpha * global[i][1] + xy[i][1],
                alpha * global[i][2] + xy[i][2],
                1.0,
            );
            let m = lu.solve(&h).filter(|m| m.iter().all(|v| v.is_finite()));
            m.map(|m| [m[0], m[1], m[2]])
                .ok_or_else(|| Error::Numerical("a local map is singular".into()))
        })
        .collect()
}

/// The weight of a light group's colours against the node values in its map's least squares
/// ([`GroupColours`]): how much a texel's colour under each light of the group (white-balanced
/// RGB, each channel about a node value's size) counts beside the reflectance's values at the
/// nodes. At 1000 the colours decide and the node values only settle what the colours leave
/// free (N − 3L directions, none for four lights at N = 8). With 0 the map is the first light's
/// alone. Report section 8 measures it by five-fold cross-validation on the crate's 228
/// reflectances (`docs/upsampling.md`): against 0, 0.2 % (D65 + A) to 0.5 % (D65, A, F11,
/// LED_B2) lower relit errors under the lights other than the first, at N = 8; from 100 to
/// 100 000 the same within 0.001 ΔE00.
pub(crate) const GROUP_COLOUR_WEIGHT: f64 = 1000.0;

/// What a light group's map is fitted for besides the training reflectances' values at the
/// nodes: their colour under every light of the group, as that light's member encodes it.
pub(crate) struct GroupColours<'a> {
    /// Per light, in the group's order: its member's white-balanced encoding ([`encoding`]).
    pub encodings: &'a [[Vec<f64>; 3]],
    /// Per light: the training reflectances' [`exact_rgb`] under it.
    pub colours: &'a [Vec<[f64; 3]>],
    /// `Q = I + β Σ_l W_lᵀ W_l` (β = [`GROUP_COLOUR_WEIGHT`], W_l the encodings) and its
    /// inverse, N × N: the node values' metric in the fit ([`GroupColours::new`]).
    q: DMatrix<f64>,
    q_inv: DMatrix<f64>,
}

impl<'a> GroupColours<'a> {
    /// The group's encodings and the training colours under its lights. Errors if their
    /// numbers differ, or if they hold no light.
    pub(crate) fn new(
        encodings: &'a [[Vec<f64>; 3]],
        colours: &'a [Vec<[f64; 3]>],
    ) -> Result<GroupColours<'a>, Error> {
        if encodings.is_empty() || encodings.len() != colours.len() {
            return Err(Error::Numerical(std::format!(
                "a light group's map needs one encoding per light's colours: {} encodings, {} lights' colours",
                encodings.len(),
                colours.len()
            )));
        }
        let n = encodings[0][0].len();
        let beta = GROUP_COLOUR_WEIGHT;
        let mut q = DMatrix::<f64>::identity(n, n);
        for w in encodings {
            for i in 0..n {
                for j in 0..n {
                    q[(i, j)] += beta * (0..3).map(|c| w[c][i] * w[c][j]).sum::<f64>();
                }
            }
        }
        // Q is the identity plus a sum of Gram matrices: symmetric positive definite.
        let q_inv = q
            .clone()
            .cholesky()
            .map(|c| c.inverse())
            .ok_or_else(|| Error::Numerical("a light group's metric is singular".into()))?;
        Ok(GroupColours {
            encodings,
            colours,
            q,
            q_inv,
        })
    }

    /// The map `M` (N rows of three) minimising, over the training pairs k with weights `w_k`
    ///
    /// `Σ_k w_k (|M x_k − y_k|² + β Σ_l |W_l M x_k − c_lk|²) + α tr((M − M_g)ᵀ Q (M − M_g))`
    ///
    /// subject to `M · (1, 1, 1) = 1` (white gives 1 at every node, greys are flat): x_k the
    /// pair's colour under the reference light, y_k its values at the nodes, c_lk its colour
    /// under light l, W_l light l's encoding, M_g `global` (with weight α = `prior` times the
    /// weights' sum; none for the global map). The Hessian is `Q ⊗ (G + α I)`, G = Σ w_k x_k x_kᵀ,
    /// so the solution is closed: `M = Q⁻¹ (R + λ 1ᵀ) P + α M_g P`, P = (G + α I)⁻¹,
    /// R = Σ w_k (y_k + β Σ_l W_lᵀ c_lk) x_kᵀ, λ the constraint's multipliers.
    #[allow(clippy::needless_range_loop)]
    pub(crate) fn map(
        &self,
        weights: &dyn Fn(usize) -> f64,
        training_rgb: &[[f64; 3]],
        nodes: &[Vec<f64>],
        global: Option<(&[[f64; 3]], f64)>,
    ) -> Result<Vec<[f64; 3]>, Error> {
        let n = self.q.nrows();
        let mut g = Matrix3::<f64>::zeros();
        let mut r = DMatrix::<f64>::zeros(n, 3);
        let mut total = 0.0;
        // Per light: W_lᵀ c_lk, gathered into R with the pair's weight.
        let mut wc = std::vec![0.0f64; n];
        for k in 0..training_rgb.len() {
            let wk = weights(k);
            if wk == 0.0 {
                continue;
            }
            total += wk;
            let x = training_rgb[k];
            wc.copy_from_slice(&nodes[k][..n]);
            for (enc, colours) in self.encodings.iter().zip(self.colours) {
                let c = colours[k];
                for i in 0..n {
                    wc[i] += GROUP_COLOUR_WEIGHT
                        * (enc[0][i] * c[0] + enc[1][i] * c[1] + enc[2][i] * c[2]);
                }
            }
            for p in 0..3 {
                let wx = wk * x[p];
                for q in 0..3 {
                    g[(p, q)] += wx * x[q];
                }
                for i in 0..n {
                    r[(i, p)] += wx * wc[i];
                }
            }
        }
        let alpha = match global {
            Some((_, prior)) => prior * f64::max(total, 1e-12),
            None => 0.0,
        };
        for p in 0..3 {
            g[(p, p)] += alpha;
        }
        let singular = || Error::Numerical("a light group's map is singular".into());
        let p_inv = g.try_inverse().ok_or_else(singular)?;
        let v = p_inv * Vector3::new(1.0, 1.0, 1.0);
        let s = v.sum();
        // The prior's pull, α M_g P, and its part of the constraint, α M_g v.
        let mut pulled = DMatrix::<f64>::zeros(n, 3);
        let mut pulled_v = DVector::<f64>::zeros(n);
        if let Some((mg, _)) = global {
            for i in 0..n {
                let row = Vector3::new(mg[i][0], mg[i][1], mg[i][2]).transpose() * p_inv;
                for c in 0..3 {
                    pulled[(i, c)] = alpha * row[c];
                }
                pulled_v[i] = alpha * (mg[i][0] * v[0] + mg[i][1] * v[1] + mg[i][2] * v[2]);
            }
        }
        let rv = &r * DVector::from_column_slice(v.as_slice());
        let ones_minus = DVector::<f64>::from_element(n, 1.0) - &pulled_v;
        let lambda = (&self.q * ones_minus - rv) / s;
        let mut rl = r;
        for i in 0..n {
            for c in 0..3 {
                rl[(i, c)] += lambda[i];
            }
        }
        let p_dyn = DMatrix::<f64>::from_fn(3, 3, |a, b| p_inv[(a, b)]);
        let m = &self.q_inv * rl * p_dyn + pulled;
        let out: Vec<[f64; 3]> = (0..n).map(|i| [m[(i, 0)], m[(i, 1)], m[(i, 2)]]).collect();
        if out.iter().flatten().all(|v| v.is_finite()) {
            Ok(out)
        } else {
            Err(singular())
        }
    }
}

/// An upsampling baked on a grid: what the runtime's `Upsampling` holds, with the f64 values
/// behind it and the figures its docs state.
#[derive(Debug, Clone, PartialEq)]
pub struct Baked {
    /// The set's name.
    pub set: String,
    /// The display's name (`SRGB`).
    pub display: String,
    /// The reference light: the set's folded light, or `RADIANCE_REFERENCE_LIGHT`.
    pub light: String,
    /// The set's wavelengths, nm.
    pub wavelengths_nm: Vec<f64>,
    /// Grid points per axis.
    pub grid: usize,
    /// The encoding weights (`encoding`).
    pub encoding: [Vec<f64>; 3],
    /// The fit behind the codes; `None` when they came from the cache
    /// (`CACHE_FILE`), which holds the codes and not the fit.
    pub fit: Option<Fit>,
    /// Whether each grid point's colour is reachable by node values in [0, 1].
    pub reachable: Vec<bool>,
    /// The values as the runtime's 16-bit codes (`CODE_ONE` is 1).
    pub codes: Vec<Vec<u16>>,
    /// The largest ΔE00 between a reachable grid point and the colour its codes encode to.
    pub max_round_trip_de00: f64,
    /// The smallest Lipschitz constant of the interpolated codes: no node value changes by more
    /// than `lipschitz · max(|Δr|, |Δg|, |Δb|)`.
    pub lipschitz: f64,
    /// For a light group's map ([`bake_group`]): the group's lights, in its order, the first
    /// being [`light`](Self::light), the light the texel colours are under; the map is fitted
    /// for the colour under every one of them. `None` for a colour set's map.
    pub group_lights: Option<Vec<String>>,
}

/// What a fit computes besides the codes: the global map and the f64 node values the codes round.
#[derive(Debug, Clone, PartialEq)]
pub struct Fit {
    /// The least-squares map ([`least_squares_map`]), one row per node.
    pub map: Vec<[f64; 3]>,
    /// Node values at each grid point, index `(r · grid + g) · grid + b`, in [0, 1].
    pub values: Vec<Vec<f64>>,
}

/// CIELAB of display RGB with the display's white as the reference white.
pub(crate) fn lab_of_rgb(display: &DisplayMatrices, rgb: [f64; 3]) -> [f64; 3] {
    let xyz = mat3_vec(&display.rgb_to_xyz, rgb);
    let white = mat3_vec(&display.rgb_to_xyz, [1.0; 3]);
    lab_from_xyz(xyz, white)
}

fn mat3_vec(m: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|r| (0..3).map(|k| m[r][k] * v[k]).sum())
}

/// The rows of CIELAB's differential at `rgb` (∂Lab/∂RGB): the metric in which an unreachable
/// colour's nearest reachable colour is found.
fn lab_jacobian(display: &DisplayMatrices, rgb: [f64; 3]) -> [[f64; 3]; 3] {
    let xyz = mat3_vec(&display.rgb_to_xyz, rgb);
    let white = mat3_vec(&display.rgb_to_xyz, [1.0; 3]);
    let fprime = |t: f64| {
        const D: f64 = 6.0 / 29.0;
        if t > D * D * D {
            1.0 / (3.0 * t.cbrt().powi(2))
        } else {
            1.0 / (3.0 * D * D)
        }
    };
    let g = [0, 1, 2].map(|c| fprime(xyz[c] / white[c]) / white[c]);
    let j = [
        [0.0, 116.0 * g[1], 0.0],
        [500.0 * g[0], -500.0 * g[1], 0.0],
        [0.0, 200.0 * g[1], -200.0 * g[2]],
    ];
    [0, 1, 2].map(|r| [0, 1, 2].map(|c| (0..3).map(|k| j[r][k] * display.rgb_to_xyz[k][c]).sum()))
}

/// The node values for one colour: `map · rgb` projected onto the node values in [0, 1] that
/// `encoding` takes to `rgb`, or, where there are none, to the colour nearest `rgb` in CIELAB
/// (the difference linearised at `rgb`) that node values in [0, 1] reach. Returns the values
/// and whether `rgb` was reachable.
pub fn project(
    display: &DisplayMatrices,
    encoding: &[Vec<f64>; 3],
    map: &[[f64; 3]],
    rgb: [f64; 3],
) -> Result<(Vec<f64>, bool), Error> {
    let u: Vec<f64> = map
        .iter()
        .map(|m| m[0] * rgb[0] + m[1] * rgb[1] + m[2] * rgb[2])
        .collect();
    let a = lab_jacobian(display, rgb);
    let n = u.len();
    let b: Vec<Vec<f64>> = (0..3)
        .map(|r| {
            (0..n)
                .map(|i| (0..3).map(|k| a[r][k] * encoding[k][i]).sum())
                .collect()
        })
        .collect();
    let d: Vec<f64> = (0..3)
        .map(|r| (0..3).map(|k| a[r][k] * rgb[k]).sum())
        .collect();
    let s = nearest_in_box(&u, &b, &d)?;
    let back = encode(encoding, &s.x);
    let de = delta_e2000(lab_of_rgb(display, rgb), lab_of_rgb(display, back));
    Ok((s.x, de <= REACHABLE_DELTA_E00))
}

/// `encoding · values`.
pub fn encode(encoding: &[Vec<f64>; 3], values: &[f64]) -> [f64; 3] {
    [0, 1, 2].map(|c| encoding[c].iter().zip(values).map(|(w, v)| w * v).sum())
}

/// Bakes the upsampling of `set` for `display` with `grid` points per axis.
///
/// `light`: the reference light (the set's folded light, or `RADIANCE_REFERENCE_LIGHT` for a
/// set for radiances); `folded`: whether the set's weights already hold it. `training`: the
/// reflectances the least-squares map is fitted on.
pub fn bake(
    d: &Derivation,
    set: &WavelengthSet,
    display: (&str, &DisplayMatrices),
    light: &Curve,
    folded: bool,
    training: &[Curve],
    grid: usize,
) -> Result<Baked, Error> {
    let rgb = exact_rgb(d, display.1, light, training)?;
    bake_with(d, set, display, light, folded, training, &rgb, grid)
}

/// [`bake`] with the training reflectances' [`exact_rgb`] under `light` for the display
/// already computed (`training_rgb`, in the order of `training`): a scene that bakes several
/// sets under one light computes it once.
#[allow(clippy::too_many_arguments)]
pub(crate) fn bake_with(
    d: &Derivation,
    set: &WavelengthSet,
    display: (&str, &DisplayMatrices),
    light: &Curve,
    folded: bool,
    training: &[Curve],
    training_rgb: &[[f64; 3]],
    grid: usize,
) -> Result<Baked, Error> {
    let (display_name, m) = display;
    if training_rgb.len() != training.len() {
        return Err(Error::Numerical(std::format!(
            "{} training colours for {} training reflectances",
            training_rgb.len(),
            training.len()
        )));
    }
    if !GRID_SIZES.contains(&grid) {
        return Err(Error::Settings(std::format!(
            "an upsampling grid has {} to {} points per axis, not {grid}",
            GRID_SIZES.start(),
            GRID_SIZES.end()
        )));
    }
    let at_nodes: Vec<f64> = set.wavelengths_nm.iter().map(|&l| light.at(l)).collect();
    let w = encoding(d, set, m, (!folded).then_some(at_nodes.as_slice()))?;
    let rgb = training_rgb;
    let nodes: Vec<Vec<f64>> = training
        .iter()
        .map(|r| set.wavelengths_nm.iter().map(|&l| r.at(l)).collect())
        .collect();
    let map = least_squares_map(rgb, &nodes)?;
    let labs: Vec<[f64; 3]> = rgb.iter().map(|x| lab_of_rgb(m, *x)).collect();
    let local =
        |p: [f64; 3]| local_map(m, p, rgb, &labs, &nodes, &map, LOCAL_BANDWIDTH, LOCAL_PRIOR);
    let grid_values = bake_grid(m, &w, grid, set.len(), &local)?;
    Ok(finish(
        &set.name,
        display_name,
        &light.name,
        &set.wavelengths_nm,
        grid,
        w,
        map,
        grid_values,
        m,
        None,
    ))
}

/// Bakes the map of the light group called `name` for `display`: linear RGB white-balanced
/// under the group's first light, `lights[0]`, to node values fitted for the colour under every
/// light of the group. `members`: the group's members as sets, one per light in the group's
/// order (`spectral_quadrature_generator::shared::Member::wavelength_set`), on the same nodes;
/// `lights`: the curves of their lights. The texel colours are under the first light, and the
/// round trip holds through its member's weights; the least-squares map, global and local as [`bake`]'s, is fitted on the
/// training reflectances' values at the nodes and on their colours under each light as that
/// light's member encodes them (`GROUP_COLOUR_WEIGHT`), so that a texel's node values give
/// its colour under the other lights too, not only under the first.
pub fn bake_group(
    d: &Derivation,
    name: &str,
    members: &[WavelengthSet],
    display: (&str, &DisplayMatrices),
    lights: &[Curve],
    training: &[Curve],
    grid: usize,
) -> Result<Baked, Error> {
    let (display_name, m) = display;
    let names: Vec<&str> = members
        .iter()
        .map(|g| g.light.as_deref().unwrap_or(""))
        .collect();
    if lights.is_empty()
        || lights
            .iter()
            .map(|l| l.name.as_str())
            .ne(names.iter().copied())
    {
        return Err(Error::Numerical(std::format!(
            "the light group {name} has the lights {names:?}; its map was given {:?}",
            lights.iter().map(|l| &l.name).collect::<Vec<_>>()
        )));
    }
    if !GRID_SIZES.contains(&grid) {
        return Err(Error::Settings(std::format!(
            "an upsampling grid has {} to {} points per axis, not {grid}",
            GRID_SIZES.start(),
            GRID_SIZES.end()
        )));
    }
    let encodings = group_encodings(d, members, m)?;
    let nodes_nm = &members[0].wavelengths_nm;
    let colours = lights
        .iter()
        .map(|l| exact_rgb(d, m, l, training))
        .collect::<Result<Vec<_>, Error>>()?;
    let fit = GroupColours::new(&encodings, &colours)?;
    let rgb = &colours[0];
    let nodes: Vec<Vec<f64>> = training
        .iter()
        .map(|r| nodes_nm.iter().map(|&l| r.at(l)).collect())
        .collect();
    let map = fit.map(&|_| 1.0, rgb, &nodes, None)?;
    let labs: Vec<[f64; 3]> = rgb.iter().map(|x| lab_of_rgb(m, *x)).collect();
    let local = |p: [f64; 3]| {
        let here = lab_of_rgb(m, p);
        // As `local_map`: weights exp(−½ (ΔE*ab / bandwidth)²), none beyond eight bandwidths.
        let far = (8.0 * LOCAL_BANDWIDTH).powi(2);
        let weight = |k: usize| {
            let l = labs[k];
            let d2 = (l[0] - here[0]).powi(2) + (l[1] - here[1]).powi(2) + (l[2] - here[2]).powi(2);
            if d2 > far {
                0.0
            } else {
                (-0.5 * d2 / (LOCAL_BANDWIDTH * LOCAL_BANDWIDTH)).exp()
            }
        };
        fit.map(&weight, rgb, &nodes, Some((&map, LOCAL_PRIOR)))
    };
    let w = encodings[0].clone();
    let grid_values = bake_grid(m, &w, grid, nodes_nm.len(), &local)?;
    Ok(finish(
        name,
        display_name,
        &lights[0].name,
        nodes_nm,
        grid,
        w,
        map,
        grid_values,
        m,
        Some(names.iter().map(|s| s.to_string()).collect()),
    ))
}

/// Each member's white-balanced encoding ([`encoding`]) of a light group for the display `m`,
/// in the group's order. Errors unless every member has a light folded in and the first's
/// wavelengths.
pub(crate) fn group_encodings(
    d: &Derivation,
    members: &[WavelengthSet],
    m: &DisplayMatrices,
) -> Result<Vec<[Vec<f64>; 3]>, Error> {
    let Some(first) = members.first() else {
        return Err(Error::Numerical("a light group has no light".into()));
    };
    members
        .iter()
        .map(|set| {
            if set.light.is_none() || set.wavelengths_nm != first.wavelengths_nm {
                return Err(Error::Numerical(std::format!(
                    "{}: a light group's members fold a light in and share their nodes",
                    set.name
                )));
            }
            encoding(d, set, m, None)
        })
        .collect()
}

/// The node values at every point of a `grid`³ lattice (index `(r · grid + g) · grid + b`) and
/// whether each point's colour is reachable: greys exactly, every other point `local(p) · p`
/// projected ([`project`]) onto the node values in [0, 1] that `w` encodes back to `p`.
fn bake_grid(
    m: &DisplayMatrices,
    w: &[Vec<f64>; 3],
    grid: usize,
    n: usize,
    local: &dyn Fn([f64; 3]) -> Result<Vec<[f64; 3]>, Error>,
) -> Result<(Vec<Vec<f64>>, Vec<bool>), Error> {
    let step = 1.0 / (grid - 1) as f64;
    let mut values = Vec::with_capacity(grid * grid * grid);
    let mut reachable = Vec::with_capacity(grid * grid * grid);
    for i in 0..grid {
        for j in 0..grid {
            for k in 0..grid {
                let p = [i as f64 * step, j as f64 * step, k as f64 * step];
                if i == j && j == k {
                    // Greys: the map gives g at every node (its rows sum to 1), which encodes
                    // to the grey itself; written exactly, so that greys interpolate flat.
                    values.push(std::vec![p[0]; n]);
                    reachable.push(true);
                    continue;
                }
                let (v, ok) = project(m, w, &local(p)?, p)?;
                values.push(v);
                reachable.push(ok);
            }
        }
    }
    Ok((values, reachable))
}

/// The [`Baked`] of grid values: their codes, the round trip at the reachable points and the
/// Lipschitz constant.
#[allow(clippy::too_many_arguments)]
fn finish(
    set: &str,
    display: &str,
    light: &str,
    wavelengths_nm: &[f64],
    grid: usize,
    w: [Vec<f64>; 3],
    map: Vec<[f64; 3]>,
    (values, reachable): (Vec<Vec<f64>>, Vec<bool>),
    m: &DisplayMatrices,
    group_lights: Option<Vec<String>>,
) -> Baked {
    let codes: Vec<Vec<u16>> = values
        .iter()
        .map(|v| v.iter().map(|x| (x * CODE_ONE).round() as u16).collect())
        .collect();
    let mut max_round_trip_de00: f64 = 0.0;
    for (idx, c) in codes.iter().enumerate() {
        if !reachable[idx] {
            continue;
        }
        let p = grid_point(grid, idx);
        let decoded: Vec<f64> = c.iter().map(|&q| f64::from(q) / CODE_ONE).collect();
        let de = delta_e2000(lab_of_rgb(m, p), lab_of_rgb(m, encode(&w, &decoded)));
        max_round_trip_de00 = max_round_trip_de00.max(de);
    }
    let lipschitz = lipschitz(grid, wavelengths_nm.len(), &codes);
    Baked {
        set: set.into(),
        display: display.into(),
        light: light.into(),
        wavelengths_nm: wavelengths_nm.to_vec(),
        grid,
        encoding: w,
        fit: Some(Fit { map, values }),
        reachable,
        codes,
        max_round_trip_de00,
        lipschitz,
        group_lights,
    }
}

/// The RGB of grid point `idx` (index `(r · grid + g) · grid + b`).
pub fn grid_point(grid: usize, idx: usize) -> [f64; 3] {
    let s = 1.0 / (grid - 1) as f64;
    [
        (idx / (grid * grid)) as f64 * s,
        ((idx / grid) % grid) as f64 * s,
        (idx % grid) as f64 * s,
    ]
}

/// The Lipschitz constant (max-norm to max-norm) of the tetrahedral interpolation of `codes`
/// decoded to node values: on each tetrahedron of a cell the interpolant is linear, its partial
/// derivatives the differences along the tetrahedron's three edges from the cell's low corner
/// to its high corner, times `grid − 1`; the tetrahedra meet without seams, so the largest sum
/// of their absolute values over all tetrahedra and nodes bounds the whole cube.
// The loops index several tables at once.
#[allow(clippy::needless_range_loop)]
pub(crate) fn lipschitz(grid: usize, n: usize, codes: &[Vec<u16>]) -> f64 {
    let strides = [grid * grid, grid, 1];
    let orders = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    let mut worst: f64 = 0.0;
    for i in 0..grid - 1 {
        for j in 0..grid - 1 {
            for k in 0..grid - 1 {
                let base = (i * grid + j) * grid + k;
                for order in orders {
                    let v1 = base + strides[order[0]];
                    let v2 = v1 + strides[order[1]];
                    let v3 = v2 + strides[order[2]];
                    for node in 0..n {
                        let q = |v: usize| f64::from(codes[v][node]);
                        let sum =
                            (q(v1) - q(base)).abs() + (q(v2) - q(v1)).abs() + (q(v3) - q(v2)).abs();
                        worst = worst.max(sum);
                    }
                }
            }
        }
    }
    worst * (grid - 1) as f64 / CODE_ONE
}

impl Baked {
    /// The tetrahedral interpolation of the f64 node values at `rgb` (each channel clamped to
    /// [0, 1]): the runtime's function without its rounding to 16 bits and f32. `None` for a
    /// table from the cache, which holds only the codes.
    pub fn interpolate(&self, rgb: [f64; 3]) -> Option<Vec<f64>> {
        let fit = self.fit.as_ref()?;
        Some(interpolate(self.grid, &fit.values, rgb))
    }

    /// One bit per cell, index `(r · (grid − 1) + g) · (grid − 1) + b`, bit `i % 32` of word
    /// `i / 32`: set where a corner of the cell is not reachable. The runtime checks the round
    /// trip only in those cells.
    pub(crate) fn edge_cells(&self) -> Vec<u32> {
        let g = self.grid;
        let c = g - 1;
        let mut words = std::vec![0u32; (c * c * c).div_ceil(32)];
        for i in 0..c {
            for j in 0..c {
                for k in 0..c {
                    let corner = |di: usize, dj: usize, dk: usize| {
                        self.reachable[((i + di) * g + j + dj) * g + k + dk]
                    };
                    let all = (0..8).all(|m| corner(m >> 2, (m >> 1) & 1, m & 1));
                    if !all {
                        let idx = (i * c + j) * c + k;
                        words[idx / 32] |= 1 << (idx % 32);
                    }
                }
            }
        }
        words
    }

    /// The share of grid points whose colour node values in [0, 1] reach.
    pub fn reachable_share(&self) -> f64 {
        self.reachable.iter().filter(|&&r| r).count() as f64 / self.reachable.len() as f64
    }
}

/// Tetrahedral interpolation on a `grid`³ table of node values (index `(r · grid + g) · grid +
/// b`), each channel of `rgb` clamped to [0, 1]: the cell's Kuhn tetrahedron that holds the
/// point (the axes taken in decreasing order of the point's position in the cell), its four
/// corners weighted by the point's barycentric coordinates.
pub(crate) fn interpolate(grid: usize, values: &[Vec<f64>], rgb: [f64; 3]) -> Vec<f64> {
    let cells = (grid - 1) as f64;
    let mut cell = [0usize; 3];
    let mut frac = [0.0f64; 3];
    for c in 0..3 {
        let x = rgb[c].clamp(0.0, 1.0) * cells;
        let i = (x.floor() as usize).min(grid - 2);
        cell[c] = i;
        frac[c] = x - i as f64;
    }
    let strides = [grid * grid, grid, 1];
    let mut axes = [0usize, 1, 2];
    axes.sort_by(|&a, &b| frac[b].total_cmp(&frac[a]));
    let base = (cell[0] * grid + cell[1]) * grid + cell[2];
    let v1 = base + strides[axes[0]];
    let v2 = v1 + strides[axes[1]];
    let v3 = v2 + strides[axes[2]];
    let (fa, fb, fc) = (frac[axes[0]], frac[axes[1]], frac[axes[2]]);
    let w = [1.0 - fa, fa - fb, fb - fc, fc];
    (0..values[base].len())
        .map(|node| {
            w[0] * values[base][node]
                + w[1] * values[v1][node]
                + w[2] * values[v2][node]
                + w[3] * values[v3][node]
        })
        .collect()
}
