//! Method (a), for comparison with the shared sets: the A channel's Gauss nodes, with C1 and C2
//! integrated on them by interpolatory rules, so that all three channels share the nodes.

use crate::base::error::{Error, SetNameProblem};
use crate::derivation::derive::Derivation;
use crate::derivation::quadrature::interpolatory_weights;
use crate::derivation::sets::WavelengthSet;

/// Method (a): the A channel's Gauss rule of order `n` (its nodes and A weights), with C1 and C2
/// integrated on the same nodes by interpolatory rules (the integral of the interpolating
/// polynomial), so that all three channels share `n` wavelengths.
pub(crate) fn interpolatory_a(
    d: &Derivation,
    n: usize,
    name: &str,
) -> Result<WavelengthSet, Error> {
    let problem = |problem: SetNameProblem| Error::SetName {
        name: name.into(),
        problem,
    };
    let r = d.rules[0].get(n.wrapping_sub(1)).ok_or_else(|| {
        problem(SetNameProblem::OrderNotDerived {
            channel: 0,
            order: n,
            max: d.settings.max_order,
        })
    })?;
    if !r.is_defined() {
        return Err(problem(SetNameProblem::RuleUndefined {
            channel: 0,
            order: n,
            status: r.status.as_str(),
            reason: r.reason.clone(),
        }));
    }
    Ok(WavelengthSet {
        name: name.into(),
        doc: std::format!(
            "The A channel's Gauss rule of order {n}, with C1 and C2 integrated by interpolatory rules on its nodes."
        ),
        wavelengths_nm: r.nodes_nm.clone(),
        weights: [
            r.weights.clone(),
            interpolatory_weights(&d.measures[1], &r.nodes_nm),
            interpolatory_weights(&d.measures[2], &r.nodes_nm),
        ],
        light: None,
        sensor: None,
    })
}
