//! Light that bounces: the forms of reflectance a renderer's path carries after several
//! surfaces, and the fixed sets judged on them (the report's section 10,
//! `docs/interreflection.md`).
//!
//! Every other figure of the report is for direct view, a light times one reflectance. A path
//! that meets k surfaces carries the light times `ρ₁ ρ₂ … ρ_k`: for one material `ρᵏ`, peakier
//! than any reflectance; inside an enclosure of one material of albedo a (an integrating
//! sphere), the sum over every number of bounces, `ρ (1 − a) / (1 − a ρ)`. Each form is a
//! [`Curve`] on a 1 nm grid, judged like a reflectance under a light (its white is the light:
//! the bounce form of a perfect reflector is 1 again).
//!
//! The sets measured: each light's own folded set, the light group of D65, A, F11 and LED_B2
//! ([`GroupFit`], trained on the CIE test colours), the same group trained on bounce forms of
//! the CIE test colours ([`training_forms`]), and the radiance set.

use rand::RngExt;
use spectral_quadrature_generator::shared::{
    nodes_of, problem_for, GroupFit, GroupObjective, Shared, Weights,
};
use spectral_quadrature_generator::{Derivation, Error};
use spectral_quadrature_spectra::{surfaces_under_lights, Curve, EvalSet, Reference, Stimulus};

use crate::random_wavelengths::pixel_rng;

/// The powers `ρᵏ` measured: one to eight bounces off one material.
pub const POWERS: std::ops::RangeInclusive<u32> = 1..=8;

/// The albedos of the enclosures measured.
pub const ENCLOSURE_ALBEDOS: [f64; 2] = [0.5, 0.9];

/// One form of reflectance a path carries.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Form {
    /// `ρᵏ`: k bounces off one material.
    Power(u32),
    /// `ρ_i ρ_j`: two bounces, off reflectance i and a seeded other one.
    Pair,
    /// `ρ_i ρ_j ρ_l`: three bounces, off reflectance i and two seeded others.
    Triple,
    /// `ρ (1 − a) / (1 − a ρ)`: an enclosure of one material, every bounce summed.
    Enclosure(f64),
}

impl Form {
    /// The forms the report's tables show: k = 1, 2, 4, 8, a pair, a triple, the enclosures.
    pub fn tabled() -> Vec<Form> {
        let mut v: Vec<Form> = [1, 2, 4, 8].map(Form::Power).to_vec();
        v.extend([Form::Pair, Form::Triple]);
        v.extend(ENCLOSURE_ALBEDOS.map(Form::Enclosure));
        v
    }

    /// Every form measured: k = 1 … 8, a pair, a triple, the enclosures.
    pub fn all() -> Vec<Form> {
        let mut v: Vec<Form> = POWERS.map(Form::Power).collect();
        v.extend([Form::Pair, Form::Triple]);
        v.extend(ENCLOSURE_ALBEDOS.map(Form::Enclosure));
        v
    }

    /// `ρ^2`, `ρi·ρj`, `ρi·ρj·ρl`, `sphere a=0.9`: for tables and the CSV.
    pub fn label(&self) -> String {
        match self {
            Form::Power(k) => format!("ρ^{k}"),
            Form::Pair => "ρi·ρj".into(),
            Form::Triple => "ρi·ρj·ρl".into(),
            Form::Enclosure(a) => format!("sphere a={a}"),
        }
    }

    /// The form's value for reflectance values `r` (one for a power or an enclosure, two for a
    /// pair, three for a triple; the first is the form's own reflectance).
    pub fn value(&self, r: &[f64]) -> f64 {
        match self {
            Form::Power(k) => r[0].powi(*k as i32),
            Form::Pair | Form::Triple => r.iter().product(),
            Form::Enclosure(a) => enclosure_value(r[0], *a),
        }
    }

    /// How many reflectances one instance of the form multiplies.
    pub fn arity(&self) -> usize {
        match self {
            Form::Pair => 2,
            Form::Triple => 3,
            Form::Power(_) | Form::Enclosure(_) => 1,
        }
    }
}

/// The radiance leaving the wall of an integrating sphere of reflectance `r` (albedo `a`: the
/// fraction of the wall that is that material, the rest a perfect absorber's port), per unit of
/// light entering: `r (1 − a) / (1 − a r)`, the geometric sum over every bounce, normalised so
/// that a perfect reflector gives 1.
pub fn enclosure_value(r: f64, a: f64) -> f64 {
    r * (1.0 - a) / (1.0 - a * r)
}

/// The 1 nm grid of `range_nm`: every whole nm from its start to its end.
pub fn grid(range_nm: [f64; 2]) -> Vec<f64> {
    let (lo, hi) = (range_nm[0].ceil() as i64, range_nm[1].floor() as i64);
    (lo..=hi).map(|v| v as f64).collect()
}

/// The form `form` of the reflectances `parts` (as [`Form::value`] takes them), on the 1 nm
/// grid of `range_nm`.
pub fn form_curve(form: Form, parts: &[&Curve], range_nm: [f64; 2]) -> Curve {
    let wavelengths = grid(range_nm);
    let mut r = vec![0.0; parts.len()];
    let values = wavelengths
        .iter()
        .map(|&nm| {
            for (v, c) in r.iter_mut().zip(parts) {
                *v = c.at(nm);
            }
            form.value(&r)
        })
        .collect();
    let names: Vec<&str> = parts.iter().map(|c| c.name.as_str()).collect();
    Curve {
        name: format!("{} of {}", form.label(), names.join(" · ")),
        wavelengths,
        values,
    }
}

/// The form `form` of every reflectance of `reflectances`, in their order: for a pair or a
/// triple, reflectance i times one or two others drawn (without repeats, none of them i) from
/// the seeded stream `[seed, 0xb0, i]`. Needs at least `form.arity()` reflectances.
pub fn forms(form: Form, reflectances: &[Curve], seed: u64, range_nm: [f64; 2]) -> Vec<Curve> {
    let n = reflectances.len();
    (0..n)
        .map(|i| {
            let mut idx = vec![i];
            let mut rng = pixel_rng(seed, &[0xb0, i as u64]);
            while idx.len() < form.arity().min(n) {
                let j = rng.random_range(0..n);
                if !idx.contains(&j) {
                    idx.push(j);
                }
            }
            let parts: Vec<&Curve> = idx.iter().map(|&k| &reflectances[k]).collect();
            form_curve(form, &parts, range_nm)
        })
        .collect()
}

/// The bounce forms a fit for bounced light trains on: the generator's own, which a scene's
/// `[groups.*] training = "bounces"` bakes ([`spectral_quadrature_generator::shared::bounce_forms`]:
/// each reflectance as it is, squared, cubed, and in the enclosures of albedo 0.5 and 0.9).
pub fn training_forms(training: &[Curve], range_nm: [f64; 2]) -> Vec<Curve> {
    spectral_quadrature_generator::shared::bounce_forms(training, range_nm)
}

/// The names of the fixed sets' methods, in [`Sets::methods`]' order.
pub const METHODS: [&str; 4] = [
    "own folded set",
    "light group",
    "group, bounce-trained",
    "radiance set",
];

/// The fixed sets of one size: per light, each method's set (`None` where the method does not
/// apply: a light outside the group).
#[derive(Debug, Clone)]
pub struct Sets {
    /// N.
    pub n: usize,
    /// `methods[m][l]`: method m ([`METHODS`]) for light l, as measured on radiances.
    pub methods: Vec<Vec<Option<EvalSet>>>,
}

/// The fixed sets at each of `sizes` for `lights`: each light's own folded set
/// (`KQ_<light>_N`), the light group of the lights named in `group_lights` (at least two of
/// them among `lights`, else no group) fitted on `training` as it is and on its
/// [`training_forms`] (per-light least-squares weights, searched for the mean ratio), and the
/// radiance set `KQ_N`.
pub fn fixed_sets(
    d: &Derivation,
    lights: &[Curve],
    group_lights: &[&str],
    training: &[Curve],
    sizes: &[usize],
) -> Result<Vec<Sets>, Error> {
    let range = d.settings.range_nm;
    let mut problems = lights
        .iter()
        .map(|l| problem_for(d, Some(l)))
        .collect::<Result<Vec<_>, Error>>()?;
    problems.push(problem_for(d, None)?);
    let in_group: Vec<usize> = (0..lights.len())
        .filter(|&l| group_lights.contains(&lights[l].name.as_str()))
        .collect();
    let group_problems: Vec<_> = in_group.iter().map(|&l| problems[l].clone()).collect();
    let fits = if in_group.len() >= 2 {
        let plain = GroupFit::new(group_problems.clone(), training)?;
        let bounced = GroupFit::new(group_problems, &training_forms(training, range))?;
        Some([plain, bounced])
    } else {
        None
    };
    let mut out = Vec::new();
    for &n in sizes {
        // Every light's search and the radiance set's, on every core.
        let shared: Vec<Shared> = crate::par_map(&problems, |p| p.shared(n))
            .into_iter()
            .collect::<Result<_, Error>>()?;
        let mut methods = vec![vec![None; lights.len()]; METHODS.len()];
        for (l, light) in lights.iter().enumerate() {
            methods[0][l] = Some(crate::evaluate::shared_on_radiance(
                &shared[l],
                &format!("KQ_{}_{n}", light.name),
                "KQ folded",
            ));
            methods[3][l] = Some(crate::evaluate::shared_on_radiance(
                &shared[lights.len()],
                &format!("KQ_{n}"),
                "KQ radiance",
            ));
        }
        if let Some(fits) = &fits {
            let own_nodes: Vec<Vec<usize>> = in_group
                .iter()
                .map(|&l| nodes_of(&problems[l], &shared[l]))
                .collect();
            let groups: Vec<_> = crate::par_map(fits, |f| {
                f.optimize(n, &own_nodes, GroupObjective::Mean, Weights::PerLight)
            })
            .into_iter()
            .collect::<Result<_, Error>>()?;
            for (m, g) in [1, 2].into_iter().zip(&groups) {
                for (member, &l) in g.members.iter().zip(&in_group) {
                    methods[m][l] = Some(crate::evaluate::member_on_radiance(
                        member,
                        &g.wavelengths_nm,
                        &format!("{} {n} for {}", METHODS[m], lights[l].name),
                        "group",
                    ));
                }
            }
        }
        out.push(Sets { n, methods });
    }
    Ok(out)
}

/// The forms under one light and their exact colours, computed once for every set judged.
pub struct Judged {
    stimuli: Vec<Stimulus>,
    reference: Reference,
}

impl Judged {
    /// The forms `forms` under `light`, against the 1 nm integration `full`.
    pub fn new(full: &EvalSet, light: &Curve, forms: &[Curve]) -> Judged {
        let stimuli = surfaces_under_lights(forms, std::slice::from_ref(light));
        let reference = Reference::new(full.clone(), &stimuli);
        Judged { stimuli, reference }
    }

    /// Each form's CIEDE2000 by `set` (its white integrated by the same set).
    pub fn de00(&self, set: &EvalSet) -> Vec<f64> {
        self.reference.errors(set, &self.stimuli).de00
    }

    /// The stimuli (each form under the light).
    pub fn stimuli(&self) -> &[Stimulus] {
        &self.stimuli
    }

    /// Their reference.
    pub fn reference(&self) -> &Reference {
        &self.reference
    }
}

/// Mean and 95th percentile (nearest rank) of `v`; NaN for none.
pub fn mean_p95(v: &[f64]) -> (f64, f64) {
    if v.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let k = ((0.95 * s.len() as f64).ceil() as usize).clamp(1, s.len());
    (s.iter().sum::<f64>() / s.len() as f64, s[k - 1])
}

/// The light group fitted as the crate fits it (on the CIE test colours and measured
/// reflectances) against the same fit on their bounce forms, by five-fold cross-validation as
/// section 9 runs it: each fold trains on `training` and the other folds of `judged` (as they
/// are, or their [`training_forms`]) and judges the fold's reflectances in every form of
/// [`Form::all`]. `cv[form][light]` is (plain, bounce-trained) mean CIEDE2000 over every fold.
/// `done` is called with 1 as each fold is finished, for a progress line.
pub fn cross_validated(
    d: &Derivation,
    lights: &[Curve],
    training: &[Curve],
    judged: &[Curve],
    n: usize,
    seed: u64,
    done: &(dyn Fn(usize) + Sync),
) -> Result<Vec<Vec<(f64, f64)>>, Error> {
    use crate::light_groups::FOLDS;
    let range = d.settings.range_nm;
    let full = d.observer.full_integration(range, 1.0)?;
    let (problems, _, own_nodes) = crate::light_groups::own_sets(d, lights, n)?;
    let all = Form::all();
    let folds: Vec<usize> = (0..FOLDS).collect();
    // Per fold: [form][light] → (plain, bounced) sums of ΔE00, and the count judged.
    type Fold = (Vec<Vec<(f64, f64)>>, usize);
    let per_fold: Vec<Result<Fold, Error>> = crate::par_map(&folds, |&f| {
        let (train, test) = crate::light_groups::fold(training, judged, f);
        let mut groups = Vec::new();
        for t in [train.clone(), training_forms(&train, range)] {
            let fit = GroupFit::new(problems.clone(), &t)?;
            groups.push(fit.optimize(n, &own_nodes, GroupObjective::Mean, Weights::PerLight)?);
        }
        let mut sums = vec![vec![(0.0, 0.0); lights.len()]; all.len()];
        for (fi, &form) in all.iter().enumerate() {
            // Products pair within the fold, so that no fit saw any of their parts.
            let curves = forms(form, &test, seed, range);
            for (l, light) in lights.iter().enumerate() {
                let j = Judged::new(&full, light, &curves);
                let e: Vec<f64> = groups
                    .iter()
                    .map(|g| {
                        let s = crate::evaluate::member_on_radiance(
                            &g.members[l],
                            &g.wavelengths_nm,
                            "group",
                            "group",
                        );
                        j.de00(&s).iter().sum()
                    })
                    .collect();
                sums[fi][l] = (e[0], e[1]);
            }
        }
        done(1);
        Ok((sums, test.len()))
    });
    let per_fold = per_fold.into_iter().collect::<Result<Vec<_>, Error>>()?;
    let count: usize = per_fold.iter().map(|f| f.1).sum();
    Ok((0..all.len())
        .map(|fi| {
            (0..lights.len())
                .map(|l| {
                    let (p, b) = per_fold
                        .iter()
                        .fold((0.0, 0.0), |(p, b), f| (p + f.0[fi][l].0, b + f.0[fi][l].1));
                    (p / count as f64, b / count as f64)
                })
                .collect()
        })
        .collect())
}
