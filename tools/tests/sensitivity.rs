//! How far the rules move with the data and settings.

use spectral_quadrature_tools as tools;

/// The data files the derivation reads (the runtime crate's `data/`).
const DATA_DIR: &str = spectral_quadrature_tools::DATA_DIR;

use spectral_quadrature_generator::{Settings, Status};
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
