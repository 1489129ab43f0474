//! Display matrices from primaries and white point, and the condition number that decides which
//! primaries are too nearly collinear.

use proptest::prelude::*;
use spectral_quadrature_math::{
    condition_number, display_matrices, xyz_from_xy, DisplayError, Point, MAX_PRIMARIES_CONDITION,
    MIN_WHITE_SHARE,
};

const D65: [f64; 2] = [0.3127, 0.3290];

/// The displays the runtime bakes by default, as their standards give them (all with D65 white):
/// sRGB / Rec. 709, Display P3, Rec. 2020 and the paper's 1987 monitor (Eq. 18).
const STANDARD: [(&str, [[f64; 2]; 3]); 4] = [
    ("sRGB", [[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]]),
    (
        "Display P3",
        [[0.680, 0.320], [0.265, 0.690], [0.150, 0.060]],
    ),
    (
        "Rec. 2020",
        [[0.708, 0.292], [0.170, 0.797], [0.131, 0.046]],
    ),
    ("Meyer 1987", [[0.64, 0.33], [0.29, 0.60], [0.15, 0.06]]),
];

fn mul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

fn transpose(a: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| a[j][i]))
}

#[test]
fn srgb_matrix_is_the_one_iec_61966_2_1_prints() {
    let m = display_matrices(STANDARD[0].1, D65).unwrap();
    // The standard prints RGB → XYZ to 4 decimals: within half a unit of the last digit.
    let printed = [
        [0.4124, 0.3576, 0.1805],
        [0.2126, 0.7152, 0.0722],
        [0.0193, 0.1192, 0.9505],
    ];
    for (row, want) in m.rgb_to_xyz.iter().zip(printed) {
        for (v, w) in row.iter().zip(want) {
            assert!((v - w).abs() <= 0.5e-4, "{:?}", m.rgb_to_xyz);
        }
    }
}

#[test]
fn standard_displays_are_well_conditioned_balanced_and_white_at_y_1() {
    for (name, primaries) in STANDARD {
        let m = display_matrices(primaries, D65).unwrap();
        // The range MAX_PRIMARIES_CONDITION's documentation states.
        assert!(
            (19.0..=23.0).contains(&m.condition),
            "{name}: {}",
            m.condition
        );
        assert_eq!(m.condition, condition_number(&primaries_matrix(primaries)));
        // f64 rounding of a few operations on values near 1: 1e-14 is a hundred units in the
        // last place.
        assert!(
            (m.luminance.iter().sum::<f64>() - 1.0).abs() < 1e-14,
            "{name}"
        );
        let white = xyz_from_xy(D65).unwrap();
        for (r, w) in m.rgb_to_xyz.iter().zip(white) {
            assert!((r.iter().sum::<f64>() - w).abs() < 1e-14, "{name}");
        }
        let id = mul(&m.rgb_to_xyz, &m.xyz_to_rgb);
        for (i, row) in id.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                // Rounding magnified by the condition number (about 20): 1e-14.
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((v - want).abs() < 1e-14, "{name}: {id:?}");
            }
        }
    }
}

#[test]
fn the_1987_monitor_has_the_white_balance_the_paper_implies() {
    // Y_r : Y_g : Y_b ≈ 0.222 : 0.707 : 0.071, from its Eq. 18 phosphors and D65 (the ratio its
    // Eq. 19 prints is a transcription error; docs/reproducing-the-paper.md). Three decimals:
    // within 0.0006.
    let l = display_matrices(STANDARD[3].1, D65).unwrap().luminance;
    for (v, want) in l.iter().zip([0.222, 0.707, 0.071]) {
        assert!((v - want).abs() < 0.0006, "{l:?}");
    }
}

/// The primaries' XYZ at Y = 1 as columns.
fn primaries_matrix(p: [[f64; 2]; 3]) -> [[f64; 3]; 3] {
    let cols = p.map(|xy| xyz_from_xy(xy).unwrap());
    [0, 1, 2].map(|r| [cols[0][r], cols[1][r], cols[2][r]])
}

#[test]
fn invalid_chromaticities_are_refused_naming_the_first() {
    let srgb = STANDARD[0].1;
    let nan = f64::NAN;
    let inf = f64::INFINITY;
    for bad in [
        [nan, 0.3],
        [0.3, inf],
        [-0.1, 0.3],
        [0.3, 0.0],
        [0.3, -0.2],
        [0.7, 0.5],
    ] {
        assert_eq!(xyz_from_xy(bad), None, "{bad:?}");
        for (k, point) in [Point::Red, Point::Green, Point::Blue]
            .into_iter()
            .enumerate()
        {
            let mut p = srgb;
            p[k] = bad;
            // A later invalid point is not the one named.
            let e = display_matrices(p, [nan, nan]).unwrap_err();
            assert!(
                matches!(e, DisplayError::Chromaticity { point: q, xy } if q == point
                    && xy.iter().zip(bad).all(|(a, b)| a.to_bits() == (b as f32).to_bits())),
                "{e:?}"
            );
        }
        let e = display_matrices(srgb, bad).unwrap_err();
        assert!(
            matches!(
                e,
                DisplayError::Chromaticity {
                    point: Point::White,
                    ..
                }
            ),
            "{e:?}"
        );
        assert!(e.to_string().starts_with("white point chromaticity"), "{e}");
    }
    // The edges of the valid range are valid.
    assert!(xyz_from_xy([0.0, 1.0]).is_some() && xyz_from_xy([0.5, 0.5]).is_some());
}

#[test]
fn collinear_primaries_are_refused_with_their_condition_number() {
    let srgb = STANDARD[0].1;
    // Exactly collinear: all three on the line x = y (the matrix may invert, by rounding, but
    // its condition number is huge), and two primaries the same (no inverse at all).
    for p in [
        [[0.2, 0.2], [0.4, 0.4], [0.3, 0.3]],
        [srgb[0], srgb[0], srgb[2]],
    ] {
        match display_matrices(p, D65) {
            Err(DisplayError::Collinear { condition }) => {
                assert!(
                    f64::from(condition) > MAX_PRIMARIES_CONDITION,
                    "{condition}"
                )
            }
            other => panic!("{p:?}: {other:?}"),
        }
    }
    // Green moved towards the red-blue edge: refused once the condition number passes the
    // threshold, and the error reports it.
    let mid = [
        0.5 * (srgb[0][0] + srgb[2][0]),
        0.5 * (srgb[0][1] + srgb[2][1]),
    ];
    let mut refused = 0;
    for k in 0..=1000 {
        let t = f64::from(k) / 1000.0;
        let g = [
            mid[0] + t * (srgb[1][0] - mid[0]),
            mid[1] + t * (srgb[1][1] - mid[1]),
        ];
        let p = [srgb[0], g, srgb[2]];
        let c = condition_number(&primaries_matrix(p));
        match display_matrices(p, [0.3, 0.2]) {
            Err(DisplayError::Collinear { condition }) => {
                assert!(
                    condition.to_bits() == (c as f32).to_bits() || c.is_infinite(),
                    "{t}"
                );
                assert!(condition.is_nan() || f64::from(condition) > MAX_PRIMARIES_CONDITION);
                refused += 1;
            }
            _ => assert!(c <= MAX_PRIMARIES_CONDITION, "{t}: {c}"),
        }
    }
    assert!(refused > 0 && refused < 1000, "{refused}");
    let e = DisplayError::Collinear { condition: 2e3 };
    assert!(
        e.to_string().contains("2.000e3") && e.to_string().contains("1e3"),
        "{e}"
    );
}

#[test]
fn a_white_outside_the_triangle_or_on_an_edge_is_refused() {
    let srgb = STANDARD[0].1;
    match display_matrices(srgb, [0.1, 0.8]) {
        Err(DisplayError::WhiteOutside { drives, .. }) => assert!(drives.iter().any(|d| *d < 0.0)),
        other => panic!("{other:?}"),
    }
    // On the red-green edge: blue's share is 0 up to rounding.
    let edge = [
        0.5 * (srgb[0][0] + srgb[1][0]),
        0.5 * (srgb[0][1] + srgb[1][1]),
    ];
    assert!(matches!(
        display_matrices(srgb, edge),
        Err(DisplayError::WhiteOutside { .. })
    ));
    // Just inside the edge: blue's share is small, but far above MIN_WHITE_SHARE.
    let inside = [
        0.999 * edge[0] + 0.001 * srgb[2][0],
        0.999 * edge[1] + 0.001 * srgb[2][1],
    ];
    let m = display_matrices(srgb, inside).unwrap();
    let largest = m.luminance.iter().fold(0.0f64, |a, b| a.max(*b));
    assert!(m.luminance[2] < 0.01 * largest && m.luminance[2] > MIN_WHITE_SHARE * largest);
}

#[test]
fn condition_numbers_of_known_matrices() {
    let id = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    assert_eq!(condition_number(&id), 1.0);
    // Diagonal: the ratio of the largest to the smallest entry, exactly (no rotation needed).
    assert_eq!(
        condition_number(&[[2.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 0.002]]),
        1000.0
    );
    // A rotation: 1, up to rounding of its entries and of the norms (a few units in the last
    // place each: 1e-15).
    let r = rotation(0.3, -1.1, 2.5);
    assert!((condition_number(&r) - 1.0).abs() < 1e-15);
    assert_eq!(condition_number(&[[0.0; 3]; 3]), f64::INFINITY);
    assert_eq!(
        condition_number(&[[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 0.0, 1.0]]),
        f64::INFINITY
    );
    let mut nan = id;
    nan[1][2] = f64::NAN;
    assert!(condition_number(&nan).is_nan());
    let mut inf = id;
    inf[0][0] = f64::INFINITY;
    assert_eq!(condition_number(&inf), f64::INFINITY);
}

/// The rotation by angles a, b, c about the z, y and x axes.
fn rotation(a: f64, b: f64, c: f64) -> [[f64; 3]; 3] {
    let rz = [
        [a.cos(), -a.sin(), 0.0],
        [a.sin(), a.cos(), 0.0],
        [0.0, 0.0, 1.0],
    ];
    let ry = [
        [b.cos(), 0.0, b.sin()],
        [0.0, 1.0, 0.0],
        [-b.sin(), 0.0, b.cos()],
    ];
    let rx = [
        [1.0, 0.0, 0.0],
        [0.0, c.cos(), -c.sin()],
        [0.0, c.sin(), c.cos()],
    ];
    mul(&mul(&rz, &ry), &rx)
}

proptest! {
    // A failure prints the shrunk input; no regression files are written.
    #![proptest_config(ProptestConfig {
        cases: 2000,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// U · diag(σ) · Vᵀ with rotations U and V has singular values σ, so its condition number is
    /// max σ / min σ. The product's entries are rounded (a few ε · max σ each), and so are the
    /// rotations that find the singular values: each moves the smallest singular value by a few
    /// ε · max σ, a relative tolerance of 64 ε · κ in all (at most 3.8 ε · κ measured over a
    /// million such matrices).
    #[test]
    fn condition_number_is_the_ratio_of_the_singular_values(
        u in prop::array::uniform3(-3.2f64..3.2),
        v in prop::array::uniform3(-3.2f64..3.2),
        log_sigma in prop::array::uniform3(-3.0f64..3.0),
        scale in -200i32..200,
    ) {
        let sigma = log_sigma.map(|l| 10f64.powf(l));
        let d = [
            [sigma[0], 0.0, 0.0],
            [0.0, sigma[1], 0.0],
            [0.0, 0.0, sigma[2]],
        ];
        let a = mul(&mul(&rotation(u[0], u[1], u[2]), &d), &transpose(&rotation(v[0], v[1], v[2])));
        let want = sigma.iter().fold(0.0f64, |m, s| m.max(*s))
            / sigma.iter().fold(f64::INFINITY, |m, s| m.min(*s));
        let got = condition_number(&a);
        let tol = 64.0 * f64::EPSILON * want;
        prop_assert!((got - want).abs() <= tol * want, "{got} against {want}");
        // Scaling by a power of two changes no bit; transposing changes the condition number
        // by rounding only, within the same tolerance.
        let s = 2f64.powi(scale);
        prop_assert_eq!(condition_number(&a.map(|r| r.map(|x| x * s))), got);
        let t = condition_number(&transpose(&a));
        prop_assert!((t - got).abs() <= tol * got, "{t} against {got}");
    }

    /// Any input, bit patterns included: never a panic, and a display that is returned has
    /// finite matrices, a condition number within the threshold and every share of the white
    /// above MIN_WHITE_SHARE of the largest.
    #[test]
    fn display_matrices_never_panics_and_returns_only_valid_displays(
        bits in prop::array::uniform8(any::<u64>()),
        jitter in prop::array::uniform8(-0.1f64..0.1),
        raw in any::<bool>(),
    ) {
        let v: [f64; 8] = if raw {
            bits.map(f64::from_bits)
        } else {
            // Near sRGB: mostly valid displays, some with the white outside.
            let s = [0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.3127, 0.3290];
            core::array::from_fn(|i| s[i] + jitter[i])
        };
        let p = [[v[0], v[1]], [v[2], v[3]], [v[4], v[5]]];
        if let Ok(m) = display_matrices(p, [v[6], v[7]]) {
            let all = m.rgb_to_xyz.iter().chain(&m.xyz_to_rgb).flatten();
            prop_assert!(all.clone().all(|x| x.is_finite()));
            prop_assert!(m.condition <= MAX_PRIMARIES_CONDITION);
            let largest = m.luminance.iter().fold(0.0f64, |a, b| a.max(*b));
            prop_assert!(m.luminance.iter().all(|l| *l > MIN_WHITE_SHARE * largest));
        }
    }
}
