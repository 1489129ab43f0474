//! The Planckian locus table (`tables::PLANCKIAN_LOCUS`) the runtime's CCT interpolates, baked
//! when a scene asks for it (`[extras] cct = true`, and in the default scene).

use std::string::{String, ToString};
use std::vec::Vec;

use super::layout::{self, lit, Expr};
use super::lists::Constant;
use super::model::Locus;

/// The item `PLANCKIAN_LOCUS` of the model's locus (CIE 015's range, 360-830 nm clipped to the
/// observer's table, whatever the scene's range), made by `PlanckianLocus::new`, which checks
/// it; registered in `consts`.
pub(crate) fn planckian_rs(locus: &Locus, consts: &mut Vec<Constant>) -> String {
    let [lo_nm, hi_nm] = locus.range_nm;
    let nodes = &locus.nodes;
    let pairs = |f: &dyn Fn(usize) -> [f32; 2]| -> Expr {
        Expr::Array(
            (0..nodes.len())
                .map(|i| {
                    let [a, b] = f(i);
                    Expr::Array(std::vec![Expr::Atom(lit(a)), Expr::Atom(lit(b))])
                })
                .collect(),
        )
    };
    let mired = nodes.iter().map(|n| Expr::Atom(lit(n.mired))).collect();
    let unit_tangent = nodes
        .iter()
        .map(|n| {
            let [a, b] = n.unit_tangent_q14;
            Expr::Array(std::vec![
                Expr::atom(a.to_string()),
                Expr::atom(b.to_string())
            ])
        })
        .collect();
    let along = nodes
        .iter()
        .map(|n| Expr::atom(n.along_q30.to_string()))
        .collect();
    let value = Expr::Call(
        "checked".into(),
        std::vec![Expr::Call(
            "crate::PlanckianLocus::new".into(),
            std::vec![
                Expr::Array(mired),
                pairs(&|i| nodes[i].uv),
                pairs(&|i| nodes[i].tangent),
                pairs(&|i| nodes[i].chord),
                Expr::Array(unit_tangent),
                Expr::Array(along),
            ],
        )],
    );
    let [first, last] = locus.mired_ends;
    let doc = std::format!(
        "The Planckian locus in CIE 1960 (u, v), Planck's law (c₂ = 1.4388e-2 m·K) against the {} functions ({}) at 1 nm over {lo_nm}-{hi_nm} nm, {}, whatever range the scene integrates colours over; {} to {} mired ({} K to {} K): {} nodes, each a point, its tangent d(u, v)/dμ, the chord to the next and the tangent's direction in fixed point, close enough that their cubic Hermite interpolation stays within 5e-9 of the locus. [`PlanckianLocus::cct`](crate::PlanckianLocus::cct) gives the CCT and Duv of an XYZ.",
        locus.observer[0],
        locus.observer[1],
        if [lo_nm, hi_nm] == [360.0, 830.0] {
            "CIE 015's range"
        } else {
            "CIE 015's 360-830 nm clipped to the observer's table"
        },
        first,
        last,
        (1e6 / last).round(),
        (1e6 / first).round(),
        nodes.len()
    );
    let ty = std::format!("crate::PlanckianLocus<{}>", nodes.len());
    let mut o = layout::comment(0, "///", &doc, 0);
    o.push_str(&layout::item(
        0,
        &std::format!("pub const PLANCKIAN_LOCUS: {ty} ="),
        &value,
    ));
    o.push('\n');
    consts.push(Constant::new("PLANCKIAN_LOCUS", ty));
    o
}
