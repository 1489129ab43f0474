//! The derivation's display matrices (its own code, with nalgebra) against
//! `spectral-quadrature-math`'s, which the runtime's `Display::new` uses: the same bits for every
//! matrix, and the same decisions, so that the derivation can call the math crate instead
//! without changing a baked table. This file goes away with the derivation's copy.

use proptest::prelude::*;
use spectral_quadrature_derive::display::{self as derive, DisplaySpec, Transfer};
use spectral_quadrature_math::{display_matrices, DisplayError, MIN_WHITE_SHARE};

fn same(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> bool {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .all(|(x, y)| x.to_bits() == y.to_bits())
}

fn spec(primaries_xy: [[f64; 2]; 3], white_xy: [f64; 2]) -> DisplaySpec {
    DisplaySpec {
        name: "TEST".into(),
        label: "test".into(),
        doc: String::new(),
        primaries_xy,
        white_xy,
        transfer: Transfer::Linear,
    }
}

/// The matrices are the same bits; the condition numbers, from two algorithms (nalgebra's SVD
/// and the math crate's one-sided Jacobi), agree to rounding: each is within a few units in the
/// last place of σ_max / σ_min for these well-conditioned matrices (κ below 1000), so 1e-12
/// relative is generous.
fn agree(primaries_xy: [[f64; 2]; 3], white_xy: [f64; 2]) -> Result<(), TestCaseError> {
    let theirs = derive::display_matrices(&spec(primaries_xy, white_xy)).unwrap();
    let ours = display_matrices(primaries_xy, white_xy).unwrap();
    prop_assert!(same(&ours.rgb_to_xyz, &theirs.rgb_to_xyz));
    prop_assert!(same(&ours.xyz_to_rgb, &theirs.xyz_to_rgb));
    let bits = |v: [f64; 3]| v.map(f64::to_bits);
    prop_assert_eq!(bits(ours.luminance), bits(theirs.luminance));
    prop_assert!(
        (ours.condition - theirs.condition).abs() <= 1e-12 * theirs.condition,
        "{} against {}",
        ours.condition,
        theirs.condition
    );
    Ok(())
}

#[test]
fn the_standard_displays_have_the_same_bits_and_print_the_same_condition_numbers() {
    for s in derive::standard_displays() {
        agree(s.primaries_xy, s.white_xy).unwrap();
        // The generated tables print each display's condition number to 2 decimals.
        let theirs = derive::display_matrices(&s).unwrap().condition;
        let ours = display_matrices(s.primaries_xy, s.white_xy)
            .unwrap()
            .condition;
        assert_eq!(format!("{ours:.2}"), format!("{theirs:.2}"), "{}", s.name);
    }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 5000,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// sRGB's chromaticities moved by up to ±0.15 each: valid displays, nearly collinear ones
    /// and whites outside the triangle. Both refuse the same ones, except in the margin where
    /// the math crate refuses a white on an edge of the triangle (a share of at most
    /// MIN_WHITE_SHARE of the largest) that the derivation accepts.
    #[test]
    fn jittered_displays_get_the_same_bits_and_the_same_decisions(
        jitter in prop::array::uniform8(-0.15f64..0.15),
    ) {
        let s = [0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.3127, 0.3290];
        let v: [f64; 8] = core::array::from_fn(|i| s[i] + jitter[i]);
        let p = [[v[0], v[1]], [v[2], v[3]], [v[4], v[5]]];
        let w = [v[6], v[7]];
        let theirs = derive::display_matrices(&spec(p, w));
        match display_matrices(p, w) {
            Ok(_) => agree(p, w)?,
            Err(DisplayError::WhiteOutside { drives }) if theirs.is_ok() => {
                let largest = drives.iter().fold(0.0f64, |m, d| m.max(*d));
                prop_assert!(drives.iter().any(|d| *d <= MIN_WHITE_SHARE * largest));
            }
            Err(e) => prop_assert!(theirs.is_err(), "{e}"),
        }
    }
}
