//! The runtime's 8-bit encoders of the baked power-law transfer functions: for each distinct γ
//! among the scene's displays, the 255 thresholds where x^(1/γ) · 255 crosses a rounding
//! boundary, so that the runtime encodes to 8 bits with comparisons alone, correctly rounded,
//! without a power function (and without f64) per pixel. The sRGB curve has its own table, built
//! by `const fn` in the runtime (`encode.rs`).

use std::string::String;
use std::vec::Vec;

use super::layout::{self, Expr};
use crate::derivation::display::Transfer;

/// The bits of the smallest f32 at or above `t` (t ≥ 0 and finite): 1 (the smallest subnormal)
/// for a `t` that rounds to 0 as f32.
pub(crate) fn ceil_f32_bits(t: f64) -> u32 {
    let f = t as f32;
    if f64::from(f) < t {
        f.to_bits() + 1
    } else {
        f.to_bits()
    }
}

/// Thresholds of the power law x^(1/γ) with γ the f32 `gamma` (as the runtime holds it):
/// entry k (1..=255) is the bits of the smallest f32 x with x^(1/γ) · 255 ≥ k − ½, i.e.
/// x ≥ ((k − ½)/255)^γ, computed in f64; entry 0 is 0. Non-decreasing (equal where two
/// boundaries fall on one f32).
pub(crate) fn gamma_thresholds(gamma: f32) -> [u32; 256] {
    let g = f64::from(gamma);
    let mut t = [0u32; 256];
    for (k, slot) in t.iter_mut().enumerate().skip(1) {
        *slot = ceil_f32_bits(((k as f64 - 0.5) / 255.0).powf(g));
    }
    t
}

/// The Rust source of `pub(crate) static GAMMA_ENCODERS: [GammaEncoder8; K]`, one per distinct
/// γ (as f32) among `transfers`' `Gamma` variants, in order of first appearance; empty when
/// there is none.
pub(crate) fn gamma_encoders_rs<'a>(transfers: impl IntoIterator<Item = &'a Transfer>) -> String {
    let mut gammas: Vec<f32> = Vec::new();
    for t in transfers {
        if let Transfer::Gamma(g) = *t {
            let g = g as f32;
            if g.is_finite() && g > 0.0 && !gammas.iter().any(|h| h.to_bits() == g.to_bits()) {
                gammas.push(g);
            }
        }
    }
    let mut o = layout::comment(
        0,
        "///",
        "The 8-bit encoders of the baked displays' power laws (`TransferFunction::Gamma`), one per distinct γ: thresholds from generator/src/emit/transfer_tables.rs.",
        0,
    );
    let encoders = gammas
        .iter()
        .map(|g| {
            let t = gamma_thresholds(*g);
            Expr::Struct(
                "crate::encode::GammaEncoder8".into(),
                std::vec![
                    ("gamma".into(), Expr::atom(std::format!("{g:?}"))),
                    (
                        "thresholds".into(),
                        Expr::Array(
                            t.iter()
                                .map(|b| Expr::atom(std::format!("{b:#010x}")))
                                .collect(),
                        ),
                    ),
                ],
            )
        })
        .collect();
    o.push_str(&layout::item(
        0,
        &std::format!(
            "pub(crate) static GAMMA_ENCODERS: [crate::encode::GammaEncoder8; {}] =",
            gammas.len()
        ),
        &Expr::Array(encoders),
    ));
    o.push('\n');
    o
}
