//! How far the rules move with the data and settings, and displays the derivation refuses.

use spectral_quadrature_tools as tools;

/// The data files the derivation reads (the runtime crate's `data/`).
const DATA_DIR: &str = spectral_quadrature_tools::DATA_DIR;

use spectral_quadrature_build::display::{display_matrices, DisplaySpec, Transfer, MAX_CONDITION};
use spectral_quadrature_build::DisplayError;
use spectral_quadrature_build::{Settings, Status};
use tools::sensitivity::{shifts, standard_variants};

#[test]
fn node_shifts_between_grids_ranges_and_observers() {
    let rows = shifts(&Settings::new(DATA_DIR), &standard_variants(), 8).unwrap();
    for r in &rows {
        eprintln!(
            "{:<13} {:<2} {:>2} {:>14} {:>14} {:>9} {:>9}",
            r.variant,
            ["A", "C1", "C2"][r.channel],
            r.order,
            r.baseline.as_str(),
            r.changed.as_str(),
            r.max_node_shift_nm
                .map_or("-".into(), |v| format!("{v:.3}")),
            r.max_weight_change
                .map_or("-".into(), |v| format!("{v:.2e}"))
        );
    }
    let find = |variant: &str, c: usize, n: usize| {
        rows.iter()
            .find(|r| r.variant == variant && r.channel == c && r.order == n)
            .unwrap()
    };
    // The grid matters little: between 5 nm and 1 nm data no classification of orders 1-8
    // changes, and nodes move by at most 1.39 nm (measured: A order 8 1.31, C1 order 8 1.39;
    // orders ≤ 4 under 0.12 nm). Bounds: 1.5 nm, and 0.2 nm for orders ≤ 4.
    for r in rows.iter().filter(|r| r.variant == "1 nm grid") {
        assert_eq!(r.baseline, r.changed, "{r:?}");
        if let Some(shift) = r.max_node_shift_nm {
            assert!(shift < 1.5, "{r:?}");
            if r.order <= 4 {
                assert!(shift < 0.2, "{r:?}");
            }
        }
    }
    // The range matters for high orders: 360-830 nm adds tails where the sensitivities are
    // tiny. Order 1 does not move (measured 0.000 nm), A order 8 moves 35 nm (measured), and
    // classifications flip (C1 7 becomes defined, C1 8 outside, C2 4 outside instead of
    // complex).
    assert!(find("360-830 nm", 0, 1).max_node_shift_nm.unwrap() < 0.01);
    assert!(find("360-830 nm", 0, 8).max_node_shift_nm.unwrap() > 20.0);
    assert_eq!(find("360-830 nm", 1, 7).changed, Status::Defined);
    assert_eq!(find("360-830 nm", 1, 8).changed, Status::Outside);
    // The observer matters most: the 10° observer is a different colour space. A's single node
    // moves 5.3 nm (measured), C2 order 2's nodes 21 nm, and C2 orders 3, 5, 8 change class.
    let a1 = find("CIE 1964 10°", 0, 1).max_node_shift_nm.unwrap();
    assert!((3.0..10.0).contains(&a1), "{a1}");
    assert_eq!(find("CIE 1964 10°", 2, 3).changed, Status::Outside);
    assert_eq!(find("CIE 1964 10°", 2, 8).changed, Status::Defined);
    assert_eq!(rows.len(), 3 * 3 * 8);
}

fn spec(name: &str, primaries: [[f64; 2]; 3], white: [f64; 2]) -> DisplaySpec {
    DisplaySpec {
        name: name.into(),
        label: name.into(),
        doc: String::new(),
        primaries_xy: primaries,
        white_xy: white,
        transfer: Transfer::Gamma(2.2),
    }
}

#[test]
fn nearly_collinear_primaries_are_refused_with_condition_number_and_threshold() {
    // Green almost on the line from red to blue.
    let red = [0.64, 0.33];
    let blue = [0.15, 0.06];
    let t = 0.5;
    let on_line = [
        red[0] + t * (blue[0] - red[0]),
        red[1] + t * (blue[1] - red[1]) + 1e-5,
    ];
    let e = display_matrices(&spec("FLAT", [red, on_line, blue], [0.3127, 0.329])).unwrap_err();
    let spectral_quadrature_build::Error::Display {
        name,
        problem: DisplayError::Collinear { condition },
    } = &e
    else {
        panic!("expected collinear primaries, got {e:?}");
    };
    assert_eq!(name, "FLAT");
    assert!(f64::from(*condition) > MAX_CONDITION, "{condition}");
    let e = e.to_string();
    assert!(e.contains("FLAT") && e.contains("collinear"), "{e}");
    assert!(
        e.contains("condition number") && e.contains(&format!("{MAX_CONDITION:e}")),
        "{e}"
    );
}

#[test]
fn white_outside_the_primaries_triangle_is_refused() {
    let e = display_matrices(&spec(
        "ODD_WHITE",
        [[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]],
        [0.60, 0.38],
    ))
    .unwrap_err();
    assert!(
        matches!(
            &e,
            spectral_quadrature_build::Error::Display { problem: DisplayError::WhiteOutside { drives, .. }, .. }
                if drives.iter().any(|d| *d <= 0.0)
        ),
        "{e:?}"
    );
    let e = e.to_string();
    assert!(
        e.contains("ODD_WHITE") && e.contains("outside the primaries' triangle"),
        "{e}"
    );
}

#[test]
fn invalid_chromaticities_are_refused() {
    for bad in [[0.5, 0.0], [0.7, 0.5], [f64::NAN, 0.3], [-0.1, 0.3]] {
        let e = display_matrices(&spec(
            "BAD",
            [bad, [0.3, 0.6], [0.15, 0.06]],
            [0.3127, 0.329],
        ))
        .unwrap_err();
        assert!(
            matches!(
                &e,
                spectral_quadrature_build::Error::Display {
                    problem: DisplayError::Chromaticity { point, .. },
                    ..
                } if point.name() == "red primary"
            ),
            "{e:?}"
        );
        let e = e.to_string();
        assert!(
            e.contains("BAD") && e.contains("red primary chromaticity"),
            "{e}"
        );
    }
}

#[test]
fn standard_displays_are_well_conditioned_and_balanced() {
    // Condition numbers of real displays lie far below the threshold (measured 19-23), and each
    // white balance sums to 1 (white at Y = 1; f64 rounding 1e-12).
    for s in spectral_quadrature_build::display::standard_displays() {
        let m = display_matrices(&s).unwrap();
        assert!(m.condition < 50.0, "{}: {}", s.name, m.condition);
        assert!((m.luminance.iter().sum::<f64>() - 1.0).abs() < 1e-12);
    }
    // The paper's monitor: Y_r : Y_g : Y_b ≈ 0.222 : 0.707 : 0.071
    // (docs/reproducing-the-paper.md).
    let meyer = spectral_quadrature_build::display::standard_displays()
        .pop()
        .unwrap();
    let l = display_matrices(&meyer).unwrap().luminance;
    for (v, expect) in l.iter().zip([0.222, 0.707, 0.071]) {
        assert!((v - expect).abs() < 0.0006, "{l:?}");
    }
}
