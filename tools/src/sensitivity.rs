//! How much the rules move when the data or settings change: grid step, spectral range,
//! observer. Each variant is derived in full and compared order by order with the baseline.

use std::string::String;
use std::vec::Vec;

use spectral_quadrature_generator::{derive, Error, ObserverId, Settings, Status};

/// One variant of the settings, compared with the baseline.
#[derive(Debug, Clone, PartialEq)]
pub struct Variant {
    /// What changed, e.g. `1 nm grid`.
    pub name: String,
    /// The settings.
    pub settings: Settings,
}

/// The variants the report shows: 1 nm instead of 5 nm data, 360-830 instead of 380-770 nm,
/// and the CIE 1964 10° observer instead of the 1931 2°.
pub fn standard_variants() -> Vec<Variant> {
    let base = crate::settings();
    std::vec![
        Variant {
            name: "1 nm grid".into(),
            settings: Settings {
                step_nm: 1.0,
                ..base.clone()
            },
        },
        Variant {
            name: "360-830 nm".into(),
            settings: Settings {
                range_nm: [360.0, 830.0],
                ..base.clone()
            },
        },
        Variant {
            name: "CIE 1964 10°".into(),
            settings: Settings {
                observer: ObserverId::Cie1964_10deg,
                ..base
            },
        },
    ]
}

/// A rule of the baseline beside the same channel and order of a variant.
#[derive(Debug, Clone, PartialEq)]
pub struct Shift {
    /// The variant's name.
    pub variant: String,
    /// Channel row: 0 = A, 1 = C1, 2 = C2.
    pub channel: usize,
    /// The order.
    pub order: usize,
    /// The baseline's classification.
    pub baseline: Status,
    /// The variant's classification.
    pub changed: Status,
    /// Where both are defined: the largest distance between corresponding nodes, in nm.
    pub max_node_shift_nm: Option<f64>,
    /// Where both are defined: the largest change of a weight relative to the channel's total
    /// |mass| (so signed channels compare fairly).
    pub max_weight_change: Option<f64>,
}

/// Compares the baseline's rules of orders 1..=`max_order` with each variant's.
pub fn shifts(
    baseline: &Settings,
    variants: &[Variant],
    max_order: usize,
) -> Result<Vec<Shift>, Error> {
    let base = derive(&Settings {
        max_order,
        ..baseline.clone()
    })?;
    let mut out = Vec::new();
    for v in variants {
        let d = derive(&Settings {
            max_order,
            ..v.settings.clone()
        })?;
        for c in 0..3 {
            let mass_b: f64 = base.measures[c].mass.iter().map(|m| m.abs()).sum();
            let mass_v: f64 = d.measures[c].mass.iter().map(|m| m.abs()).sum();
            for n in 1..=max_order {
                let (rb, rv) = (&base.rules[c][n - 1], &d.rules[c][n - 1]);
                let both = rb.is_defined() && rv.is_defined();
                out.push(Shift {
                    variant: v.name.clone(),
                    channel: c,
                    order: n,
                    baseline: rb.status,
                    changed: rv.status,
                    max_node_shift_nm: both.then(|| {
                        rb.nodes_nm
                            .iter()
                            .zip(&rv.nodes_nm)
                            .map(|(a, b)| (a - b).abs())
                            .fold(0.0, f64::max)
                    }),
                    max_weight_change: both.then(|| {
                        rb.weights
                            .iter()
                            .zip(&rv.weights)
                            .map(|(a, b)| (a / mass_b - b / mass_v).abs())
                            .fold(0.0, f64::max)
                    }),
                });
            }
        }
    }
    Ok(out)
}
