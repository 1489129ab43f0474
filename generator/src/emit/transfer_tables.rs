//! The runtime's 8-bit encoders of the baked power-law transfer functions: for each distinct γ
//! among the scene's displays, the 255 thresholds where x^(1/γ) · 255 crosses a rounding
//! boundary (the model's [`GammaEncoder`]s), so that the runtime encodes to 8 bits with
//! comparisons alone, correctly rounded, without a power function (and without f64) per pixel.
//! The sRGB curve has its own table, built by `const fn` in the runtime (`encode.rs`).

use std::string::String;
use std::vec::Vec;

use super::layout::{self, Expr};
use super::model::GammaEncoder;

/// The Rust source of `pub(crate) static GAMMA_ENCODERS: [GammaEncoder8; K]`, one per distinct
/// γ (as f32) among the displays' power laws, in order of first appearance; empty when there is
/// none.
pub(crate) fn gamma_encoders_rs(encoders: &[GammaEncoder]) -> String {
    let mut o = layout::comment(
        0,
        "///",
        "The 8-bit encoders of the baked displays' power laws (`TransferFunction::Gamma`), one per distinct γ: thresholds from generator/src/emit/model.rs, checked by `GammaEncoder8::new`.",
        0,
    );
    let encoders: Vec<Expr> = encoders
        .iter()
        .map(|e| {
            Expr::Call(
                "crate::encode::GammaEncoder8::new".into(),
                std::vec![
                    Expr::atom(std::format!("{:?}", e.gamma)),
                    Expr::Array(
                        e.thresholds
                            .iter()
                            .map(|b| Expr::atom(std::format!("{b:#010x}")))
                            .collect(),
                    ),
                ],
            )
        })
        .collect();
    o.push_str(&layout::item(
        0,
        &std::format!(
            "pub(crate) static GAMMA_ENCODERS: [crate::encode::GammaEncoder8; {}] =",
            encoders.len()
        ),
        &Expr::Array(encoders),
    ));
    o.push('\n');
    o
}
