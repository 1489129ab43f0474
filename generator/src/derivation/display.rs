//! Display matrices from primaries and a white point, and the folding of AC1C2 → XYZ → RGB into a
//! wavelength set's weights.

use std::string::String;
use std::vec::Vec;

use nalgebra::Matrix3;

use std::fmt;

use crate::base::error::{DisplayProblem, Error};

/// How a display encodes linear light.
#[derive(Debug, Clone, PartialEq)]
pub enum Transfer {
    /// No encoding.
    Linear,
    /// The sRGB piecewise curve (IEC 61966-2-1).
    Srgb,
    /// A pure power law: encoded = linear^(1/γ).
    Gamma(f64),
}

/// A display: three primaries and a white point (CIE 1931 xy), and a transfer function.
///
/// [`standard_displays`] is the one description of each display the crate knows: the derivation
/// derives its matrices once ([`crate::Derivation::displays`]), and code generation, shaders,
/// scenes and the tools take name, label, primaries, white and transfer from there.
#[derive(Debug, Clone, PartialEq)]
pub struct DisplaySpec {
    /// The const name in generated code (upper snake case), and the name scenes and tools use.
    pub name: String,
    /// The human name (`"Display P3"`), baked as the runtime `Display`'s `name`.
    pub label: String,
    /// One line for the doc comment.
    pub doc: String,
    /// Chromaticities of red, green and blue.
    pub primaries_xy: [[f64; 2]; 3],
    /// Chromaticity of the white point (the colour of RGB = 1, 1, 1 at Y = 1).
    pub white_xy: [f64; 2],
    /// The transfer function.
    pub transfer: Transfer,
}

/// D65 as the displays' standards give it.
pub(crate) const D65_XY: [f64; 2] = [0.3127, 0.3290];

/// A display is refused when the 2-norm condition number of its primaries' XYZ matrix exceeds
/// this: nearly collinear primaries would turn tiny errors in XYZ into huge RGB values. sRGB,
/// Display P3, Rec. 2020 and the 1987 monitor lie between 19 and 23; 1000 leaves wide room for
/// real displays and none for degenerate ones.
pub const MAX_CONDITION: f64 = 1000.0;

/// The message quotes [`MAX_CONDITION`], so it is written here rather than beside the type.
impl fmt::Display for DisplayProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DisplayProblem::Chromaticity { which, xy } => write!(
                f,
                "{which} chromaticity ({}, {}) is not a valid colour",
                xy[0], xy[1]
            ),
            DisplayProblem::Collinear { condition } => write!(
                f,
                "primaries are nearly collinear (condition number {condition:.3e} > threshold {:e})",
                MAX_CONDITION
            ),
            DisplayProblem::WhiteOutside { white_xy, drives } => write!(
                f,
                "white point ({}, {}) lies outside the primaries' triangle (gun drives for white {drives:?})",
                white_xy[0], white_xy[1]
            ),
            DisplayProblem::Singular(what) => write!(f, "{what} matrix is singular"),
        }
    }
}

/// The displays the crate bakes by default.
pub fn standard_displays() -> Vec<DisplaySpec> {
    std::vec![
        DisplaySpec {
            name: "SRGB".into(),
            label: "sRGB".into(),
            doc: "sRGB / Rec. 709 primaries, D65 white, the sRGB transfer curve.".into(),
            primaries_xy: [[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]],
            white_xy: D65_XY,
            transfer: Transfer::Srgb,
        },
        DisplaySpec {
            name: "DISPLAY_P3".into(),
            label: "Display P3".into(),
            doc: "Display P3: DCI-P3 primaries, D65 white, the sRGB transfer curve.".into(),
            primaries_xy: [[0.680, 0.320], [0.265, 0.690], [0.150, 0.060]],
            white_xy: D65_XY,
            transfer: Transfer::Srgb,
        },
        DisplaySpec {
            name: "REC2020".into(),
            label: "Rec. 2020".into(),
            doc: "Rec. 2020 primaries, D65 white, a pure 2.4 gamma (BT.1886 with zero black level).".into(),
            primaries_xy: [[0.708, 0.292], [0.170, 0.797], [0.131, 0.046]],
            white_xy: D65_XY,
            transfer: Transfer::Gamma(2.4),
        },
        DisplaySpec {
            name: "MEYER_1987".into(),
            label: "Meyer 1987 monitor".into(),
            doc: "The paper's monitor: Eq. 18 phosphors, D65 white; white balance derived from them (Eq. 19 as transcribed is wrong). Its guns' measured curves are not published: a 2.2 gamma stands in; use a per-channel lookup table for a measured display.".into(),
            primaries_xy: [[0.64, 0.33], [0.29, 0.60], [0.15, 0.06]],
            white_xy: D65_XY,
            transfer: Transfer::Gamma(2.2),
        },
    ]
}

/// A display's matrices, derived in f64.
#[derive(Debug, Clone, PartialEq)]
pub struct DisplayMatrices {
    /// Linear RGB → XYZ (white at Y = 1).
    pub rgb_to_xyz: [[f64; 3]; 3],
    /// XYZ → linear RGB.
    pub xyz_to_rgb: [[f64; 3]; 3],
    /// The luminance of each primary at full drive: the white balance (Y_r : Y_g : Y_b).
    pub luminance: [f64; 3],
    /// The 2-norm condition number of `rgb_to_xyz`.
    pub condition: f64,
}

fn xyz_of(name: &str, which: &'static str, xy: [f64; 2]) -> Result<[f64; 3], Error> {
    let [x, y] = xy;
    if !(x.is_finite() && y.is_finite()) || y <= 0.0 || x < 0.0 || x + y > 1.0 {
        return Err(Error::Display {
            name: name.into(),
            problem: DisplayProblem::Chromaticity { which, xy },
        });
    }
    Ok([x / y, 1.0, (1.0 - x - y) / y])
}

/// Derives RGB ↔ XYZ: the primaries' XYZ columns scaled so that RGB = (1, 1, 1) is the white
/// at Y = 1. Errors ([`Error::Display`], naming the display) when a chromaticity is invalid,
/// when the primaries are nearly collinear (condition number above [`MAX_CONDITION`]) or when
/// the white point lies outside the primaries' triangle (a negative gun drive would be needed
/// for white).
pub fn display_matrices(spec: &DisplaySpec) -> Result<DisplayMatrices, Error> {
    let name = &spec.name;
    let fail = |problem: DisplayProblem| Error::Display {
        name: name.clone(),
        problem,
    };
    let mut cols = [[0.0; 3]; 3];
    for (c, which) in ["red primary", "green primary", "blue primary"]
        .into_iter()
        .enumerate()
    {
        cols[c] = xyz_of(name, which, spec.primaries_xy[c])?;
    }
    let white = xyz_of(name, "white", spec.white_xy)?;
    let p = Matrix3::from_fn(|i, j| cols[j][i]);
    let svd = p.svd(false, false);
    let (smax, smin) = (svd.singular_values.max(), svd.singular_values.min());
    let condition = if smin > 0.0 {
        smax / smin
    } else {
        f64::INFINITY
    };
    if condition.is_nan() || condition > MAX_CONDITION {
        return Err(fail(DisplayProblem::Collinear { condition }));
    }
    let inv = p
        .try_inverse()
        .ok_or_else(|| fail(DisplayProblem::Singular("primaries")))?;
    let s = inv * nalgebra::Vector3::new(white[0], white[1], white[2]);
    if s.iter().any(|v| v.is_nan() || *v <= 0.0) {
        return Err(fail(DisplayProblem::WhiteOutside {
            white_xy: spec.white_xy,
            drives: [s[0], s[1], s[2]],
        }));
    }
    let m = Matrix3::from_fn(|i, j| cols[j][i] * s[j]);
    let mi = m
        .try_inverse()
        .ok_or_else(|| fail(DisplayProblem::Singular("RGB to XYZ")))?;
    Ok(DisplayMatrices {
        rgb_to_xyz: to_array(&m),
        xyz_to_rgb: to_array(&mi),
        luminance: [s[0], s[1], s[2]],
        condition,
    })
}

/// The standard display called `name` ([`DisplaySpec::name`]), or [`Error::UnknownDisplay`]
/// listing the valid names.
pub(crate) fn standard_display(name: &str) -> Result<DisplaySpec, Error> {
    let all = standard_displays();
    match all.iter().position(|d| d.name == name) {
        Some(i) => Ok(all[i].clone()),
        None => Err(Error::UnknownDisplay {
            name: name.into(),
            valid: all.into_iter().map(|d| d.name).collect(),
        }),
    }
}

fn to_array(m: &Matrix3<f64>) -> [[f64; 3]; 3] {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| m[(i, j)]))
}

/// `a · b` for 3×3 row-major matrices.
pub(crate) fn mul3(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

/// Folds `matrix` (3×3, from the space of the weights' rows to another) and a `scale` into a
/// set's 3×N weights: `out[r][i] = scale · Σ_k matrix[r][k] · weights[k][i]`.
pub(crate) fn fold(matrix: &[[f64; 3]; 3], weights: &[Vec<f64>; 3], scale: f64) -> [Vec<f64>; 3] {
    let n = weights[0].len();
    [0, 1, 2].map(|r| {
        (0..n)
            .map(|i| scale * (0..3).map(|k| matrix[r][k] * weights[k][i]).sum::<f64>())
            .collect()
    })
}
