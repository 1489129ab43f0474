//! The Planckian locus table (`tables::PLANCKIAN_LOCUS`) the runtime's CCT interpolates, baked
//! when a scene asks for it (`[extras] cct = true`, and in the default scene).

use std::string::{String, ToString};
use std::vec::Vec;

use super::layout::{self, Expr};
use crate::base::error::Error;
use crate::derivation::derive::Derivation;
use crate::derivation::planckian::{standard_range_nm, PlanckianLocus};

/// The item `PLANCKIAN_LOCUS` for `d`'s observer over CIE 015's range (360-830 nm, clipped to
/// the observer's table), whatever `d`'s range, and how many f32 values it holds.
/// `f32_literal` writes each value (the code generator's, which calls this one).
pub(crate) fn planckian_rs(
    d: &Derivation,
    f32_literal: impl Fn(f64) -> Result<String, Error>,
) -> Result<(String, usize), Error> {
    let locus = PlanckianLocus::standard(&d.observer)?;
    let [lo_nm, hi_nm] = standard_range_nm(&d.observer);
    let nodes = locus.table();
    let pairs = |f: &dyn Fn(usize) -> [f64; 2]| -> Result<Expr, Error> {
        (0..nodes.len())
            .map(|i| {
                let [a, b] = f(i);
                Ok(Expr::Array(std::vec![
                    Expr::Atom(f32_literal(a)?),
                    Expr::Atom(f32_literal(b)?)
                ]))
            })
            .collect::<Result<Vec<_>, Error>>()
            .map(Expr::Array)
    };
    let mired = nodes
        .iter()
        .map(|n| f32_literal(n.mired).map(Expr::Atom))
        .collect::<Result<Vec<_>, Error>>()?;
    let fixed: Vec<([i16; 2], i32)> = nodes.iter().map(|n| n.fixed_point()).collect();
    let unit_tangent = fixed
        .iter()
        .map(|([a, b], _)| {
            Expr::Array(std::vec![
                Expr::atom(a.to_string()),
                Expr::atom(b.to_string())
            ])
        })
        .collect();
    let along = fixed
        .iter()
        .map(|(_, c)| Expr::atom(c.to_string()))
        .collect();
    let value = Expr::Struct(
        "crate::PlanckianLocus".into(),
        std::vec![
            ("mired".into(), Expr::Array(mired)),
            ("uv".into(), pairs(&|i| nodes[i].uv)?),
            ("tangent".into(), pairs(&|i| nodes[i].tangent)?),
            (
                "chord".into(),
                pairs(&|i| match nodes.get(i + 1) {
                    Some(next) => [0, 1].map(|c| next.uv[c] - nodes[i].uv[c]),
                    None => [0.0; 2],
                })?
            ),
            ("unit_tangent_q14".into(), Expr::Array(unit_tangent)),
            ("along_q30".into(), Expr::Array(along)),
        ],
    );
    let doc = std::format!(
        "The Planckian locus in CIE 1960 (u, v), Planck's law (c₂ = 1.4388e-2 m·K) against the {} functions ({}) at 1 nm over {lo_nm}-{hi_nm} nm, {}, whatever range the scene integrates colours over; {} to {} mired ({} K to {} K): {} nodes, each a point, its tangent d(u, v)/dμ, the chord to the next and the tangent's direction in fixed point, close enough that their cubic Hermite interpolation stays within 5e-9 of the locus. [`PlanckianLocus::cct`](crate::PlanckianLocus::cct) gives the CCT and Duv of an XYZ.",
        d.observer.name,
        d.observer.file,
        if [lo_nm, hi_nm] == [360.0, 830.0] {
            "CIE 015's range"
        } else {
            "CIE 015's 360-830 nm clipped to the observer's table"
        },
        nodes[0].mired,
        nodes[nodes.len() - 1].mired,
        (1e6 / nodes[nodes.len() - 1].mired).round(),
        (1e6 / nodes[0].mired).round(),
        nodes.len()
    );
    let mut o = layout::comment(0, "///", &doc, 0);
    o.push_str(&layout::item(
        0,
        &std::format!(
            "pub const PLANCKIAN_LOCUS: crate::PlanckianLocus<{}> =",
            nodes.len()
        ),
        &value,
    ));
    o.push('\n');
    // Seven f32 a node, and two i16 and an i32: the bytes of nine f32.
    Ok((o, 9 * nodes.len()))
}
