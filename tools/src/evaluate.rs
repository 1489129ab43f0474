//! Sets the report builds to measure beside the crate's own, on the generator's measuring
//! (`spectral_quadrature_generator::evaluate`): every combination of per-channel Gauss rules for
//! any three weight functions (Figs. 6 and 7, and the budgets of section 5), and a shared set
//! as measured on radiances.

use std::vec::Vec;

use spectral_quadrature_generator::quadrature::{self, Measure};
use spectral_quadrature_generator::shared::Shared;
use spectral_quadrature_generator::{Derivation, Rule, WavelengthSet};
use spectral_quadrature_spectra::EvalSet;

/// Per-channel Gauss rules of orders 1..=max_order for three weight functions given on the
/// derivation grid (columns of `w`), as `rules[c][n - 1]`.
pub fn channel_rules(d: &Derivation, w: &[[f64; 3]], max_order: usize) -> [Vec<Rule>; 3] {
    let s = &d.settings;
    [0, 1, 2].map(|c| {
        let col: Vec<f64> = w.iter().map(|v| v[c]).collect();
        let m = Measure::new(&d.grid_nm, &col, s.step_nm, s.range_nm);
        let rec = quadrature::stieltjes(&m, max_order);
        (1..=max_order)
            .map(|n| quadrature::gauss_rule(&m, &rec, n, s.range_nm))
            .collect()
    })
}

/// Every combination of defined per-channel rules (orders 1..=max in each channel) as sets,
/// with weights converted to XYZ by `to_xyz`.
pub fn combinations(rules: &[Vec<Rule>; 3], to_xyz: &[[f64; 3]; 3], family: &str) -> Vec<EvalSet> {
    let mut out = Vec::new();
    for a in rules[0].iter().filter(|r| r.is_defined()) {
        for b in rules[1].iter().filter(|r| r.is_defined()) {
            for c in rules[2].iter().filter(|r| r.is_defined()) {
                let orders = [a.order, b.order, c.order];
                let name = std::format!("{family} {}+{}+{}", a.order, b.order, c.order);
                if let Ok(set) = WavelengthSet::merge(&name, "", [Some(a), Some(b), Some(c)]) {
                    out.push(EvalSet::from_weights(
                        &name,
                        family,
                        Some(orders),
                        &set.wavelengths_nm,
                        &set.weights,
                        to_xyz,
                    ));
                }
            }
        }
    }
    out
}

/// A shared set as the report measures it, on radiances `r · L`: the folded weights divided by
/// the light at each wavelength, so that applied to `r · L` it equals the folded set applied to
/// r.
pub fn shared_on_radiance(set: &Shared, name: &str, family: &str) -> EvalSet {
    EvalSet {
        name: name.into(),
        family: family.into(),
        orders: None,
        wavelengths_nm: set.wavelengths_nm.clone(),
        xyz_weights: set.xyz_weights.clone().map(|row| {
            row.iter()
                .zip(&set.light_at_nodes)
                .map(|(v, l)| v / l)
                .collect()
        }),
    }
}

/// A light group's member as the report measures it, on radiances `r · L`, as
/// [`shared_on_radiance`]: its folded weights at the group's nodes `wavelengths_nm` divided by
/// the light at each.
pub fn member_on_radiance(
    member: &spectral_quadrature_generator::shared::Member,
    wavelengths_nm: &[f64],
    name: &str,
    family: &str,
) -> EvalSet {
    EvalSet {
        name: name.into(),
        family: family.into(),
        orders: None,
        wavelengths_nm: wavelengths_nm.to_vec(),
        xyz_weights: member.xyz_weights.clone().map(|row| {
            row.iter()
                .zip(&member.light_at_nodes)
                .map(|(v, l)| v / l)
                .collect()
        }),
    }
}
