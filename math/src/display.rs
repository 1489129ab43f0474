//! Display matrices from three primaries and a white point (CIE 1931 xy chromaticities): linear
//! RGB → XYZ and back, with RGB = (1, 1, 1) the white at Y = 1, so that the white balance (each
//! primary's luminance) follows from the primaries and the white point. And the one test of
//! whether primaries are too nearly collinear to make a display: the 2-norm condition number of
//! their matrix against [`MAX_PRIMARIES_CONDITION`].

use core::fmt;

/// The largest [`condition_number`] of the primaries' matrix (columns: the primaries' XYZ at
/// Y = 1) that [`display_matrices`] accepts. Beyond it the primaries are so nearly collinear that
/// errors in XYZ are magnified more than a thousandfold in RGB, and a matrix rounded to f32 (seven
/// digits) would keep four digits or fewer. sRGB, Display P3, Rec. 2020 and the paper's 1987
/// monitor lie between 19 and 23 (`tests/display.rs` checks it), so 1000 leaves wide room for real
/// displays and none for degenerate ones.
pub const MAX_PRIMARIES_CONDITION: f64 = 1000.0;

/// The smallest share of a primary in the white, relative to the largest share, that
/// [`display_matrices`] accepts. A white outside the primaries' triangle needs a negative share;
/// one on an edge (or within a hair of it) a share near zero, and then XYZ → RGB would be
/// dominated by one enormous column.
pub const MIN_WHITE_SHARE: f64 = 1e-6;

/// Which chromaticity of a display.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Point {
    /// The red primary.
    Red,
    /// The green primary.
    Green,
    /// The blue primary.
    Blue,
    /// The white point.
    White,
}

impl Point {
    /// The point's identifier, `"red"`, `"green"`, `"blue"` or `"white"` (kebab-case, stable
    /// across versions, as every enum's `name()` in the runtime that re-exports it). Its
    /// [`Display`](fmt::Display) is the phrase for messages (`"red primary"`).
    pub const fn name(self) -> &'static str {
        match self {
            Point::Red => "red",
            Point::Green => "green",
            Point::Blue => "blue",
            Point::White => "white",
        }
    }
}

impl fmt::Display for Point {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Point::Red => "red primary",
            Point::Green => "green primary",
            Point::Blue => "blue primary",
            Point::White => "white point",
        })
    }
}

/// Why a display is refused: by [`display_matrices`], and by the runtime's `Display::new` and the
/// generator's display derivation, which report this same type (the runtime inside its
/// `Error::Display`, the generator inside its `Error::Display` with the display's name).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum DisplayError {
    /// A chromaticity is not finite, is negative, or has y ≤ 0 or x + y > 1.
    Chromaticity {
        /// Which one.
        point: Point,
        /// Its (x, y), to f32 (the error's details are for messages: f32 keeps f64 and its
        /// formatting out of a firmware that prints them).
        xy: [f32; 2],
    },
    /// The primaries are collinear or nearly so: the [`condition_number`] of their matrix is
    /// above [`MAX_PRIMARIES_CONDITION`]. It is infinite where the matrix is exactly singular,
    /// an entry overflows, or the matrix (or RGB → XYZ) has no finite inverse.
    Collinear {
        /// The condition number, to f32 (+Inf above f32's range).
        condition: f32,
    },
    /// The white is not a mix of the primaries in which every primary's share exceeds
    /// [`MIN_WHITE_SHARE`] of the largest: it lies outside their triangle or on an edge.
    WhiteOutside {
        /// The white point's chromaticity, to f32.
        white_xy: [f32; 2],
        /// The primaries' shares of the white (at Y = 1 each): what they would have to be
        /// driven at to make it, to f32.
        drives: [f32; 3],
    },
    /// A power-law transfer function's γ is not finite and positive (not a
    /// [`display_matrices`] error: the runtime's `Display::new` checks its transfer function
    /// first).
    Gamma {
        /// The γ given.
        gamma: f32,
    },
}

impl fmt::Display for DisplayError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            DisplayError::Chromaticity { point, xy } => write!(
                f,
                "{point} chromaticity ({}, {}) is not finite, is negative, or has y <= 0 or x + y > 1",
                xy[0],
                xy[1]
            ),
            DisplayError::Collinear { condition } => write!(
                f,
                "primaries are nearly collinear (condition number {condition:.3e} > threshold \
                 {MAX_PRIMARIES_CONDITION:e})"
            ),
            DisplayError::WhiteOutside { white_xy, drives } => write!(
                f,
                "the white ({}, {}) lies outside the primaries' triangle or on an edge (drives \
                 {:.4}, {:.4}, {:.4})",
                white_xy[0], white_xy[1], drives[0], drives[1], drives[2]
            ),
            DisplayError::Gamma { gamma } => {
                write!(f, "gamma {gamma} is not finite and positive")
            }
        }
    }
}

impl core::error::Error for DisplayError {}

/// A display's matrices, in f64.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DisplayMatrices {
    /// Linear RGB → XYZ (RGB = (1, 1, 1) is the white at Y = 1).
    pub rgb_to_xyz: [[f64; 3]; 3],
    /// XYZ → linear RGB, the inverse of `rgb_to_xyz`.
    pub xyz_to_rgb: [[f64; 3]; 3],
    /// The luminance Y of each primary at full drive, the white balance Y_r : Y_g : Y_b (they
    /// sum to the white's Y = 1, up to rounding).
    pub luminance: [f64; 3],
    /// The [`condition_number`] of the primaries' matrix (columns: their XYZ at Y = 1).
    pub condition: f64,
}

/// XYZ at Y = 1 of the chromaticity `xy`: `[x / y, 1, (1 − x − y) / y]`, or `None` unless x and
/// y are finite, x ≥ 0, y > 0 and x + y ≤ 1.
pub fn xyz_from_xy(xy: [f64; 2]) -> Option<[f64; 3]> {
    let [x, y] = xy;
    if x.is_finite() && y.is_finite() && x >= 0.0 && y > 0.0 && x + y <= 1.0 {
        Some([x / y, 1.0, (1.0 - x - y) / y])
    } else {
        None
    }
}

/// The matrices of the display with these primaries (red, green, blue) and white point: the
/// primaries' XYZ at Y = 1 as columns, each scaled by its share of the white, so that
/// RGB = (1, 1, 1) is the white at Y = 1. The white balance is derived, not given.
///
/// Errors, checked in this order, never a panic: [`DisplayError::Chromaticity`] for the first
/// invalid chromaticity (red, green, blue, white); [`DisplayError::Collinear`] when the
/// primaries' matrix has a [`condition_number`] above [`MAX_PRIMARIES_CONDITION`] (infinite
/// and NaN included) or no finite inverse; [`DisplayError::WhiteOutside`] when a primary's
/// share of the white is not above [`MIN_WHITE_SHARE`] of the largest (or not finite);
/// [`DisplayError::Collinear`] with an infinite condition number when RGB → XYZ has no finite
/// inverse (entries that overflow).
///
/// Every matrix entry of a returned display is finite. The arithmetic is plain f64 in a fixed
/// order (the inverses by cofactors, in the order of [`invert3`]), so the results are the same
/// bits on every target.
///
/// ```
/// use spectral_quadrature_math::display_matrices;
/// // sRGB: Rec. 709 primaries, D65 white.
/// let srgb = display_matrices([[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]], [0.3127, 0.3290])
///     .unwrap();
/// // IEC 61966-2-1 prints the first row of RGB → XYZ as 0.4124, 0.3576, 0.1805.
/// assert!((srgb.rgb_to_xyz[0][0] - 0.4124).abs() < 5e-5);
/// assert!((srgb.luminance.iter().sum::<f64>() - 1.0).abs() < 1e-12);
/// ```
pub fn display_matrices(
    primaries_xy: [[f64; 2]; 3],
    white_xy: [f64; 2],
) -> Result<DisplayMatrices, DisplayError> {
    let point_xyz = |point: Point, xy: [f64; 2]| {
        xyz_from_xy(xy).ok_or(DisplayError::Chromaticity {
            point,
            xy: xy.map(|v| v as f32),
        })
    };
    let cols = [
        point_xyz(Point::Red, primaries_xy[0])?,
        point_xyz(Point::Green, primaries_xy[1])?,
        point_xyz(Point::Blue, primaries_xy[2])?,
    ];
    let white = point_xyz(Point::White, white_xy)?;
    // Row r, column c: component r of primary c.
    let p = [0, 1, 2].map(|r| [cols[0][r], cols[1][r], cols[2][r]]);
    let collinear = |condition: f64| DisplayError::Collinear {
        condition: condition as f32,
    };
    let condition = condition_number(&p);
    if condition.is_nan() || condition > MAX_PRIMARIES_CONDITION {
        return Err(collinear(condition));
    }
    let inv = invert3(&p).ok_or(collinear(f64::INFINITY))?;
    // The primaries' shares of the white: inv · white, each row summed left to right.
    let s = inv.map(|row| row[0] * white[0] + row[1] * white[1] + row[2] * white[2]);
    let largest = s.iter().fold(0.0f64, |m, v| m.max(*v));
    if !s
        .iter()
        .all(|&v| v.is_finite() && v > MIN_WHITE_SHARE * largest)
    {
        return Err(DisplayError::WhiteOutside {
            white_xy: white_xy.map(|v| v as f32),
            drives: s.map(|v| v as f32),
        });
    }
    let rgb_to_xyz = p.map(|row| [row[0] * s[0], row[1] * s[1], row[2] * s[2]]);
    let xyz_to_rgb = invert3(&rgb_to_xyz).ok_or(collinear(f64::INFINITY))?;
    Ok(DisplayMatrices {
        rgb_to_xyz,
        xyz_to_rgb,
        luminance: s,
        condition,
    })
}

/// The inverse of a 3×3 matrix (row-major) by cofactors, or `None` when its determinant is 0 or
/// any entry of the result is not finite (NaN in `m` included).
///
/// The operations and their order are those of nalgebra's closed-form 3×3 inverse, with which the
/// baked displays' matrices were computed before this crate held them, so they kept their bits.
pub fn invert3(m: &[[f64; 3]; 3]) -> Option<[[f64; 3]; 3]> {
    let [[m11, m12, m13], [m21, m22, m23], [m31, m32, m33]] = *m;
    let minor_m12_m23 = m22 * m33 - m32 * m23;
    let minor_m11_m23 = m21 * m33 - m31 * m23;
    let minor_m11_m22 = m21 * m32 - m31 * m22;
    let det = m11 * minor_m12_m23 - m12 * minor_m11_m23 + m13 * minor_m11_m22;
    if det == 0.0 {
        return None;
    }
    let inv = [
        [
            minor_m12_m23 / det,
            (m13 * m32 - m33 * m12) / det,
            (m12 * m23 - m22 * m13) / det,
        ],
        [
            -minor_m11_m23 / det,
            (m11 * m33 - m31 * m13) / det,
            (m13 * m21 - m23 * m11) / det,
        ],
        [
            minor_m11_m22 / det,
            (m12 * m31 - m32 * m11) / det,
            (m11 * m22 - m21 * m12) / det,
        ],
    ];
    inv.iter().flatten().all(|v| v.is_finite()).then_some(inv)
}

/// The 2-norm condition number of a 3×3 matrix: the ratio of its largest to its smallest
/// singular value, `‖m‖₂ · ‖m⁻¹‖₂`, the most by which the matrix can magnify a relative error.
/// 1 for a rotation or a multiple of one; unchanged by scaling `m` or transposing it.
///
/// This is the crate's one definition of nearly singular: [`display_matrices`] refuses primaries
/// whose matrix has a condition number above [`MAX_PRIMARIES_CONDITION`].
///
/// NaN when an entry is NaN; infinite when an entry is infinite or the smallest singular value
/// is 0 (an exactly singular matrix; one singular only up to rounding gives a huge finite
/// value). The singular values come from one-sided Jacobi rotations of `m` scaled by its
/// largest entry (no inverse, no `mᵀm`), which find them with an error of a few units in the
/// last place of the largest: the condition number is as accurate as `m`'s own rounding allows.
pub fn condition_number(m: &[[f64; 3]; 3]) -> f64 {
    if m.iter().flatten().any(|v| v.is_nan()) {
        return f64::NAN;
    }
    let scale = m.iter().flatten().fold(0.0f64, |s, v| s.max(v.abs()));
    if scale == 0.0 || scale.is_infinite() {
        return f64::INFINITY;
    }
    let sigma = singular_values(m.map(|row| row.map(|v| v / scale)));
    let largest = sigma[0].max(sigma[1]).max(sigma[2]);
    let smallest = sigma[0].min(sigma[1]).min(sigma[2]);
    if smallest == 0.0 {
        f64::INFINITY
    } else {
        largest / smallest
    }
}

/// Sweeps of [`singular_values`] at most: a 3×3 matrix needs about six, since each sweep
/// squares the columns' cosines once they are small.
const SWEEPS: usize = 32;

/// The singular values of a finite matrix with entries of at most 1 (so that no square
/// overflows), in column order, by one-sided Jacobi (Hestenes): rotations of pairs of columns,
/// each making the pair orthogonal, until every pair is orthogonal to the last bit; the columns'
/// lengths are then the singular values. Rotations are orthogonal, so the singular values do not
/// change along the way, and each rotation's rounding is a few units in the last place of the
/// columns it touches.
fn singular_values(mut a: [[f64; 3]; 3]) -> [f64; 3] {
    let dot = |a: &[[f64; 3]; 3], i: usize, j: usize| {
        a[0][i] * a[0][j] + a[1][i] * a[1][j] + a[2][i] * a[2][j]
    };
    for _ in 0..SWEEPS {
        let mut rotated = false;
        for (i, j) in [(0, 1), (0, 2), (1, 2)] {
            let (alpha, beta, gamma) = (dot(&a, i, i), dot(&a, j, j), dot(&a, i, j));
            // Orthogonal to the last bit (or a zero column): nothing to rotate.
            if gamma.abs() <= f64::EPSILON * libm::sqrt(alpha * beta) {
                continue;
            }
            rotated = true;
            // The rotation's tangent t, the smaller root of t² + 2ζt − 1 = 0.
            let zeta = (beta - alpha) / (2.0 * gamma);
            let t = 1.0 / (zeta.abs() + libm::sqrt(1.0 + zeta * zeta));
            let t = if zeta < 0.0 { -t } else { t };
            let c = 1.0 / libm::sqrt(1.0 + t * t);
            let s = c * t;
            for row in &mut a {
                let (x, y) = (row[i], row[j]);
                row[i] = c * x - s * y;
                row[j] = s * x + c * y;
            }
        }
        if !rotated {
            break;
        }
    }
    [0, 1, 2].map(|k| libm::sqrt(dot(&a, k, k)))
}
