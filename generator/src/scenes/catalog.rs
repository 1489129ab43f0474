//! Every wavelength set the crate can build, by name: the names scenes use, the planner
//! searches and the generated consts carry.
//!
//! | name | set |
//! |---|---|
//! | `TABLE2_ROW1`, `TABLE2_ROW2` | Table 2's merged sets |
//! | `A_<n>`, `C1_<n>`, `C2_<n>` | one channel's Gauss rule of order n (the other rows zero) |
//! | `AC1C2_<a>_<c1>_<c2>` | the union of A order a, C1 order c1 and C2 order c2 |
//! | `UNIFORM_<n>` | n wavelengths at the centres of equal bins, box-filter weights |
//! | `KQ_<n>` | a shared set by kernel quadrature for radiances ([`crate::shared`]), n = 3..=32 |
//! | `KQ_<light>_<n>` | the same with a built-in illuminant (`KQ_C_6`, `KQ_F11_6`, `KQ_LED_B1_4`) or a scene's `[lights]` light folded in ([`resolve_with`]): samples are reflectances |
//! | `INTERP_A_<n>` | A's Gauss nodes of order n, C1 and C2 by interpolatory rules on them |

use std::string::{String, ToString};
use std::vec::Vec;

use std::fmt;

use super::user::UserLight;
use crate::base::error::{Error, SetNameProblem};
use crate::derivation::derive::Derivation;
use crate::derivation::display;
use crate::derivation::quadrature::Rule;
use crate::derivation::sets::{WavelengthSet, CHANNELS};
use crate::shared;
use spectral_quadrature_spectra::{builtin_illuminant, builtin_lights};

/// Uniform sets the crate builds: `UNIFORM_3` to `UNIFORM_64`.
pub(crate) const UNIFORM_SIZES: core::ops::RangeInclusive<usize> = 3..=64;

/// What a name may look like, for error messages.
pub(crate) const NAME_FORMS: &str =
    "TABLE2_ROW1, TABLE2_ROW2, A_<n>, C1_<n>, C2_<n>, AC1C2_<a>_<c1>_<c2>, UNIFORM_<n> (n = 3..=64), KQ_<n> and KQ_<light>_<n> (n = 3..=32, light a built-in illuminant), INTERP_A_<n>";

// The message names the forms (NAME_FORMS) and the channels, so it is written here rather than
// beside the type.
impl fmt::Display for SetNameProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SetNameProblem::UnknownForm => {
                write!(f, "not a set name (forms: {})", NAME_FORMS)
            }
            SetNameProblem::Malformed { expected } => write!(f, "expected {expected}"),
            SetNameProblem::NotAnOrder(s) => write!(f, "{s:?} is not an order"),
            SetNameProblem::OrderNotDerived {
                channel,
                order,
                max,
            } => write!(
                f,
                "{} order {order} is not among the derived orders 1..={max}",
                CHANNELS[*channel]
            ),
            SetNameProblem::RuleUndefined {
                channel,
                order,
                status,
                reason,
            } => write!(
                f,
                "{} order {order} is undefined ({status}: {reason})",
                CHANNELS[*channel]
            ),
            SetNameProblem::Size {
                family,
                size,
                sizes,
            } => write!(
                f,
                "{family} sets have {} to {} wavelengths, not {size}",
                sizes.start(),
                sizes.end()
            ),
            SetNameProblem::UnknownLight {
                light,
                valid,
                scene,
            } if scene.is_empty() => write!(
                f,
                "{light} is not a built-in illuminant (data/illuminant_<light>.csv: {})",
                valid.join(", ")
            ),
            SetNameProblem::UnknownLight {
                light,
                valid,
                scene,
            } => write!(
                f,
                "{light} is neither a built-in illuminant (data/illuminant_<light>.csv: {}) nor a light of the scene's [lights] ({})",
                valid.join(", "),
                scene.join(", ")
            ),
        }
    }
}

/// Whether a set covers only one channel (a per-channel rule): it cannot give a colour alone.
pub(crate) fn is_single_channel(name: &str) -> bool {
    ["A_", "C1_", "C2_"].iter().any(|p| name.starts_with(p))
}

/// The set called `name`, or an error saying why there is none (unknown form, order beyond
/// the derivation's maximum, undefined rule and its reason, a size the family lacks, an unknown
/// light), or why building it failed ([`Error::InSet`]).
pub fn resolve(d: &Derivation, name: &str) -> Result<WavelengthSet, Error> {
    resolve_with(d, name, &[])
}

/// [`resolve`], where `KQ_<light>_<n>` may also name one of `lights` (lights a scene reads from
/// files): their sets are searched afresh (the node cache holds built-in lights only).
pub fn resolve_with(
    d: &Derivation,
    name: &str,
    lights: &[UserLight],
) -> Result<WavelengthSet, Error> {
    let problem = |problem: SetNameProblem| Error::SetName {
        name: name.into(),
        problem,
    };
    let order = |s: &str| -> Result<usize, Error> {
        s.parse::<usize>()
            .map_err(|_| problem(SetNameProblem::NotAnOrder(s.into())))
    };
    let rule = |c: usize, n: usize| -> Result<&Rule, Error> {
        let max = d.settings.max_order;
        let r = d.rules[c].get(n.wrapping_sub(1)).ok_or_else(|| {
            problem(SetNameProblem::OrderNotDerived {
                channel: c,
                order: n,
                max,
            })
        })?;
        if r.is_defined() {
            Ok(r)
        } else {
            Err(problem(SetNameProblem::RuleUndefined {
                channel: c,
                order: n,
                status: r.status.as_str(),
                reason: r.reason.clone(),
            }))
        }
    };
    if let Some(set) = d.table2.iter().find(|s| s.name == name) {
        return Ok(set.clone());
    }
    if let Some(rest) = name.strip_prefix("AC1C2_") {
        let parts: Vec<&str> = rest.split('_').collect();
        if parts.len() != 3 {
            return Err(problem(SetNameProblem::Malformed {
                expected: "AC1C2_<a>_<c1>_<c2>",
            }));
        }
        let rules = [
            rule(0, order(parts[0])?)?,
            rule(1, order(parts[1])?)?,
            rule(2, order(parts[2])?)?,
        ];
        let doc = std::format!(
            "Gauss rules A order {}, C1 order {}, C2 order {}, merged.",
            rules[0].order,
            rules[1].order,
            rules[2].order
        );
        return WavelengthSet::merge(name, &doc, [Some(rules[0]), Some(rules[1]), Some(rules[2])]);
    }
    if let Some(n) = name.strip_prefix("UNIFORM_") {
        let n = order(n)?;
        if !UNIFORM_SIZES.contains(&n) {
            return Err(problem(SetNameProblem::Size {
                family: "uniform",
                size: n,
                sizes: UNIFORM_SIZES,
            }));
        }
        let u = d.observer.uniform_set(d.settings.range_nm, n);
        let weights = display::fold(&d.opponent.xyz_to_ac1c2, &u.xyz_weights, 1.0);
        return Ok(WavelengthSet {
            name: name.into(),
            doc: std::format!(
                "{n} wavelengths at the centres of equal bins of the range, weighted by the integral of the matching functions over each bin."
            ),
            wavelengths_nm: u.wavelengths_nm,
            weights,
            light: None,
            sensor: None,
        });
    }
    if let Some(n) = name.strip_prefix("INTERP_A_") {
        return shared::interpolatory_a(d, order(n)?, name);
    }
    if let Some(rest) = name.strip_prefix("KQ_") {
        let (light, n) = match rest.rsplit_once('_') {
            Some((light, n)) => (Some(light), n),
            None => (None, rest),
        };
        let n = order(n)?;
        if !shared::SIZES.contains(&n) {
            return Err(problem(SetNameProblem::Size {
                family: "shared",
                size: n,
                sizes: shared::SIZES,
            }));
        }
        if let Some(user) = light.and_then(|l| lights.iter().find(|u| u.name == l)) {
            let s = shared::problem_for(d, Some(&user.curve))
                .and_then(|p| p.shared(n))
                .map_err(|e| Error::InSet {
                    name: name.into(),
                    error: std::boxed::Box::new(e),
                })?;
            return Ok(s.wavelength_set(d, name));
        }
        if let Some(l) = light {
            if builtin_illuminant(&d.settings.data_dir, l, d.settings.range_nm).is_err() {
                return Err(problem(SetNameProblem::UnknownLight {
                    light: l.into(),
                    valid: builtin_lights().into_iter().map(String::from).collect(),
                    scene: lights.iter().map(|u| u.name.clone()).collect(),
                }));
            }
        }
        let s = shared::cached_or_optimize(d, light, n).map_err(|e| Error::InSet {
            name: name.into(),
            error: std::boxed::Box::new(e),
        })?;
        return Ok(s.wavelength_set(d, name));
    }
    for (c, prefix) in ["A_", "C1_", "C2_"].iter().enumerate() {
        if let Some(n) = name.strip_prefix(prefix) {
            let r = rule(c, order(n)?)?;
            let mut weights: [Vec<f64>; 3] = Default::default();
            for (k, row) in weights.iter_mut().enumerate() {
                *row = if k == c {
                    r.weights.clone()
                } else {
                    std::vec![0.0; r.order]
                };
            }
            return Ok(WavelengthSet {
                name: name.into(),
                doc: std::format!(
                    "Channel {}, order {}: {} wavelengths.",
                    CHANNELS[c],
                    r.order,
                    r.order
                ),
                wavelengths_nm: r.nodes_nm.clone(),
                weights,
                light: None,
                sensor: None,
            });
        }
    }
    Err(problem(SetNameProblem::UnknownForm))
}

/// The names of every set that serves all three channels: Table 2's rows, every defined
/// AC1C2 combination of orders up to the derivation's maximum, and the uniform sets.
pub(crate) fn colour_set_names(d: &Derivation) -> Vec<String> {
    let mut names: Vec<String> = d.table2.iter().map(|s| s.name.clone()).collect();
    let defined = |c: usize| -> Vec<usize> {
        d.rules[c]
            .iter()
            .filter(|r| r.is_defined())
            .map(|r| r.order)
            .collect()
    };
    for a in defined(0) {
        for c1 in defined(1) {
            for c2 in defined(2) {
                names.push(std::format!("AC1C2_{a}_{c1}_{c2}"));
            }
        }
    }
    names.extend(UNIFORM_SIZES.map(|n| std::format!("UNIFORM_{n}")));
    names
}

/// The data files (labels `data/<file>`) the set called `name` is made from besides the
/// observer: a shared set's training reflectances, its light if built in, and the node cache
/// ([`shared::CACHE_FILE`]). Empty for the sets the observer alone determines.
pub(crate) fn input_files(name: &str) -> Vec<String> {
    let Some(rest) = name.strip_prefix("KQ_") else {
        return Vec::new();
    };
    let mut files = std::vec![shared::TRAINING_FILE.to_string()];
    if let Some((light, _)) = rest.rsplit_once('_') {
        // A light a scene reads from a file is among the scene's own inputs, and its sets are
        // searched afresh, without the node cache.
        if !builtin_lights().contains(&light) {
            return files;
        }
        files.push(std::format!("data/illuminant_{light}.csv"));
    }
    files.push(shared::CACHE_FILE.to_string());
    files
}

/// The names of every defined per-channel rule (`A_1`, ..., `C2_15`).
pub(crate) fn rule_names(d: &Derivation) -> Vec<String> {
    (0..3)
        .flat_map(|c| {
            d.rules[c]
                .iter()
                .filter(|r| r.is_defined())
                .map(move |r| std::format!("{}_{}", CHANNELS[c], r.order))
        })
        .collect()
}

/// The valid choices to follow an error about the set `name`, for its form: the shared-set forms
/// for a `KQ_` name, with the built-in lights and the scene's `lights` (the error about an
/// unknown light lists them itself: then only the forms), the uniform sizes for a `UNIFORM_`
/// name, the orders for an `INTERP_A_` name, and otherwise the defined per-channel rules (the
/// orders a rule or an `AC1C2_<a>_<c1>_<c2>` may use).
pub(crate) fn valid_choices_for(
    d: &Derivation,
    name: &str,
    lights: &[UserLight],
    error: &Error,
) -> String {
    if name.starts_with("KQ_") {
        let forms = std::format!(
            "shared sets: KQ_<n> (radiance) and KQ_<light>_<n> (light folded in), n = {}..={}",
            shared::SIZES.start(),
            shared::SIZES.end(),
        );
        let listed = matches!(
            error,
            Error::SetName {
                problem: SetNameProblem::UnknownLight { .. },
                ..
            }
        );
        if listed {
            return forms;
        }
        let mut s = std::format!("{forms}; lights: {}", builtin_lights().join(", "));
        if !lights.is_empty() {
            let scene: Vec<&str> = lights.iter().map(|u| u.name.as_str()).collect();
            s += &std::format!("; the scene's [lights]: {}", scene.join(", "));
        }
        return s;
    }
    if name.starts_with("UNIFORM_") {
        return std::format!(
            "uniform sets: UNIFORM_<n>, n = {}..={}",
            UNIFORM_SIZES.start(),
            UNIFORM_SIZES.end()
        );
    }
    if name.starts_with("INTERP_A_") {
        let orders: Vec<String> = d.rules[0]
            .iter()
            .filter(|r| r.is_defined())
            .map(|r| r.order.to_string())
            .collect();
        return std::format!("INTERP_A_<n> with a defined A order: {}", orders.join(", "));
    }
    valid_choices(d)
}

/// The valid choices for error messages: the defined per-channel rules (the orders an
/// `AC1C2_<a>_<c1>_<c2>` may combine).
pub(crate) fn valid_choices(d: &Derivation) -> String {
    let rules = rule_names(d);
    std::format!(
        "defined rules: {}",
        rules
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join(", ")
    )
}
