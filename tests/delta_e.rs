//! The derivation's copy of CIELAB and ΔE against the functions the runtime re-exports from
//! `spectral-quadrature-math` (whose own tests check them against published data): they must
//! agree bit for bit until the derivation calls the math crate instead of its copy.

fn sharma_pairs() -> Vec<([f64; 3], [f64; 3], f64)> {
    let text = include_str!("data/sharma2005.csv");
    let mut reader = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_reader(text.as_bytes());
    reader
        .records()
        .map(|r| {
            let r = r.expect("well-formed test data");
            let v: Vec<f64> = r.iter().map(|f| f.parse().expect("number")).collect();
            ([v[0], v[1], v[2]], [v[3], v[4], v[5]], v[6])
        })
        .collect()
}

/// The derivation crate's CIELAB functions (which measure the error of every set the report and
/// the planner judge) are a copy of the runtime's: the derive crate cannot depend on the runtime,
/// whose build script depends on it. The copies must agree bit for bit.
mod derive_copy {
    use proptest::prelude::*;
    use spectral_quadrature::{delta_e2000, delta_e76, lab_from_xyz};
    use spectral_quadrature_derive::lab;

    fn same(a: [f64; 3], b: [f64; 3]) -> bool {
        a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits())
    }

    #[test]
    fn agrees_on_the_sharma_pairs() {
        for (a, b, _) in super::sharma_pairs() {
            assert_eq!(
                delta_e2000(a, b).to_bits(),
                lab::delta_e2000(a, b).to_bits()
            );
            assert_eq!(delta_e76(a, b).to_bits(), lab::delta_e76(a, b).to_bits());
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(10_000))]
        #[test]
        fn agrees_bit_for_bit(
            xyz in prop::array::uniform3(-0.5f64..200.0),
            white in prop::array::uniform3(1e-3f64..200.0),
            other in prop::array::uniform3(-200f64..200.0),
        ) {
            let l1 = lab_from_xyz(xyz, white);
            prop_assert!(same(l1, lab::lab_from_xyz(xyz, white)));
            prop_assert_eq!(delta_e2000(l1, other).to_bits(), lab::delta_e2000(l1, other).to_bits());
            prop_assert_eq!(delta_e76(l1, other).to_bits(), lab::delta_e76(l1, other).to_bits());
        }
    }
}
