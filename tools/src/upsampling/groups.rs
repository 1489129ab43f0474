//! A light group's upsampling map judged by relighting (report section 8): texels' linear sRGB
//! under the group's first light upsampled to the group's nodes, then each light's accumulator
//! of those node values integrated through that light's member of the group, against the
//! reflectance under that light at 1 nm ([`relit_de00`]). Under the first light this is the
//! round trip; under the others, the colour of the material under a light its texel was not
//! made under.
//!
//! Beside the crate's group map ([`spectral_quadrature_generator::upsampling::bake_group`],
//! fitted for every light of the group), at the same nodes and through the same members: the
//! true reflectance at the nodes (the floor), the map of the first light's member alone (fitted
//! for that light only, as a folded set's map is), the route a scene had before group maps (a
//! `[fixed]` set for radiances at the group's nodes with its own map under D65) and Jakob-Hanika.

use spectral_quadrature_generator::scene::Scene;
use spectral_quadrature_generator::shared::{Group, GroupObjective, Weights};
use spectral_quadrature_generator::upsampling::{self as up, Baked};
use spectral_quadrature_generator::{Derivation, Error as DeriveError, WavelengthSet};
use spectral_quadrature_spectra::{Curve, Spectra};

use super::jakob_hanika::{self, JakobHanika};
use super::{relit_de00, runtime_values};
use crate::evaluate::member_on_radiance;
use crate::light_groups::OwnSets;
use crate::node_cache::NodeCache;
use crate::Error;

/// The light groups report section 8 judges unless `--illuminants` names other lights (then
/// D65 and those): the default scene's, and daylight with a tungsten lamp
/// (`examples/scenes/room.toml`). The texels' light, D65, first.
pub const DEFAULT_GROUPS: [&[&str]; 2] = [&["D65", "A", "F11", "LED_B2"], &["D65", "A"]];

/// The size of the light groups report section 8 judges.
pub const GROUP_SIZE: usize = 8;

/// Folds of report section 8's cross-validation.
pub const FOLDS: usize = 5;

/// The methods, in the order of [`GroupMaps::errors`].
pub const METHODS: [&str; 5] = [
    "true reflectance at the nodes (floor)",
    "this crate: the group's map (fitted for every light)",
    "the first light's map alone (fitted for it alone)",
    "a [fixed] set at the group's nodes, its own map (radiances, D65)",
    "Jakob-Hanika 2019 at the group's nodes",
];

/// What one light group's maps measure.
#[derive(Debug, Clone, PartialEq)]
pub struct GroupMaps {
    /// The group's lights, the texels' light first.
    pub lights: Vec<String>,
    /// `errors[method][light][k]`: the CIEDE2000 of judged reflectance k relit under the light
    /// through its member, by each of [`METHODS`].
    pub errors: Vec<Vec<Vec<f64>>>,
    /// Per fold: the group's nodes, nm.
    pub nodes_nm: Vec<Vec<f64>>,
}

/// One fold of a cross-validation: the reflectances every fit of the fold trains on, and the
/// indices of the judged reflectances it judges.
pub type Fold = (Vec<Curve>, Vec<usize>);

/// The reflectances report section 8 judges by default: the ColorChecker (Ohta's), then the
/// upsampling maps' training (the CIE test colours and the 190 rawtoaces patches).
pub fn default_judged(d: &Derivation) -> Result<Vec<Curve>, DeriveError> {
    let (dir, range) = (&d.settings.data_dir, d.settings.range_nm);
    let mut all = Spectra::builtin(dir, "data/reflectance_colorchecker_ohta.csv")?.curves(range)?;
    all.extend(up::training(dir, range)?);
    Ok(all)
}

/// Fold `fold` of `count` over `judged`: it judges every `count`-th reflectance from `fold` on,
/// and trains on the others.
pub fn fold(judged: &[Curve], count: usize, fold: usize) -> Fold {
    let idx: Vec<usize> = (0..judged.len()).filter(|k| k % count == fold).collect();
    let training = judged
        .iter()
        .enumerate()
        .filter(|(k, _)| k % count != fold)
        .map(|(_, c)| c.clone())
        .collect();
    (training, idx)
}

/// The group of `lights` at `n` nodes that fold `f` judges (nodes searched for the mean ratio
/// to each light's own folded set, starting from `own`'s nodes; weights fitted per light on
/// `training`), its nodes from `cache` where its entry `maps_<lights>_<n>_fold<f>` has a
/// matching fingerprint.
pub fn fold_group(
    d: &Derivation,
    cache: &NodeCache,
    lights: &[Curve],
    n: usize,
    own: &OwnSets,
    f: usize,
    training: &[Curve],
) -> Result<Group, DeriveError> {
    let names: Vec<&str> = lights.iter().map(|l| l.name.as_str()).collect();
    let (problems, _, own_nodes) = own;
    cache.group(
        d,
        &format!("maps_{}_{n}_fold{f}", names.join("+")),
        problems.clone(),
        training,
        n,
        own_nodes,
        GroupObjective::Mean,
        Weights::PerLight,
    )
}

/// Every node search of report section 8's default run, through `cache`: each fold's group for
/// each of [`DEFAULT_GROUPS`] (each light's own set among them), the maps and their judging left
/// out.
pub fn default_searches(d: &Derivation, cache: &NodeCache) -> Result<(), DeriveError> {
    let judged = default_judged(d)?;
    let folds: Vec<(usize, Fold)> = (0..FOLDS).map(|f| (f, fold(&judged, FOLDS, f))).collect();
    for names in DEFAULT_GROUPS {
        let lights = crate::light_groups::builtin_lights(d, names)?;
        let own = crate::light_groups::own_sets_with(d, cache, &lights, GROUP_SIZE)?;
        for r in crate::par_map(&folds, |(f, (training, _))| {
            fold_group(d, cache, &lights, GROUP_SIZE, &own, *f, training)
        }) {
            r?;
        }
    }
    Ok(())
}

/// Judges the maps of the light group of `lights` (two or more; the texels' light first) at
/// `n` nodes on `judged`, fold by fold: each fold's group ([`fold_group`], through `cache`;
/// `own` as [`crate::light_groups::own_sets`] gives it) and each map are fitted on the fold's
/// training only.
/// `rgb`: the judged reflectances' linear sRGB under the first light, white-balanced (the
/// texels). `done` is called with 1 as each fold is finished.
#[allow(clippy::too_many_arguments)]
pub fn judge(
    d: &Derivation,
    cache: &NodeCache,
    lights: &[Curve],
    n: usize,
    own: &OwnSets,
    judged: &[Curve],
    rgb: &[[f64; 3]],
    folds: &[Fold],
    done: &(dyn Fn(usize) + Sync),
) -> Result<GroupMaps, Error> {
    let (_, srgb) = d.display("SRGB")?;
    let reference = d.observer.full_integration(d.settings.range_nm, 1.0)?;
    let jh = JakobHanika::srgb(d)?;
    let jh_coeffs: Vec<[f64; 3]> = rgb.iter().map(|p| jh.fit(*p)).collect();
    let fold_numbers: Vec<usize> = (0..folds.len()).collect();
    let per_fold = crate::par_map(&fold_numbers, |&f| -> Result<_, Error> {
        let (train, idx) = &folds[f];
        let group = fold_group(d, cache, lights, n, own, f, train)?;
        let nodes = group.wavelengths_nm.clone();
        let members: Vec<WavelengthSet> = group
            .members
            .iter()
            .map(|m| m.wavelength_set(d, "GROUP", &nodes))
            .collect();
        let group_map = up::bake_group(
            d,
            "GROUP",
            &members,
            ("SRGB", srgb),
            lights,
            train,
            up::DEFAULT_GRID,
        )?;
        let alone = up::bake(
            d,
            &members[0],
            ("SRGB", srgb),
            &lights[0],
            true,
            train,
            up::DEFAULT_GRID,
        )?;
        let fixed = fixed_set(d, &nodes)?;
        let d65 = super::d65(d)?;
        let fixed_map = up::bake(
            d,
            &fixed,
            ("SRGB", srgb),
            &d65,
            false,
            train,
            up::DEFAULT_GRID,
        )?;
        let pts: Vec<[f64; 3]> = idx.iter().map(|&k| rgb[k]).collect();
        let floor: Vec<Vec<f64>> = idx
            .iter()
            .map(|&k| nodes.iter().map(|&l| judged[k].at(l)).collect())
            .collect();
        let jh_values: Vec<Vec<f64>> = idx
            .iter()
            .map(|&k| {
                nodes
                    .iter()
                    .map(|&l| jakob_hanika::spectrum(jh_coeffs[k], l))
                    .collect()
            })
            .collect();
        let values = [
            floor,
            values_of(&group_map, &pts)?,
            values_of(&alone, &pts)?,
            values_of(&fixed_map, &pts)?,
            jh_values,
        ];
        let test: Vec<Curve> = idx.iter().map(|&k| judged[k].clone()).collect();
        let errors: Vec<Vec<Vec<f64>>> = values
            .iter()
            .map(|v| {
                group
                    .members
                    .iter()
                    .zip(lights)
                    .map(|(m, l)| {
                        let eval = member_on_radiance(m, &nodes, "member", "group");
                        relit_de00(&eval, &reference, &test, v, l)
                    })
                    .collect()
            })
            .collect();
        done(1);
        Ok((errors, nodes))
    });
    let mut errors = vec![vec![vec![f64::NAN; judged.len()]; lights.len()]; METHODS.len()];
    let mut nodes_nm = Vec::new();
    for (fold, result) in folds.iter().zip(per_fold) {
        let (e, nodes) = result?;
        for (m, per_light) in e.into_iter().enumerate() {
            for (l, de) in per_light.into_iter().enumerate() {
                for (&k, v) in fold.1.iter().zip(de) {
                    errors[m][l][k] = v;
                }
            }
        }
        nodes_nm.push(nodes);
    }
    Ok(GroupMaps {
        lights: lights.iter().map(|l| l.name.clone()).collect(),
        errors,
        nodes_nm,
    })
}

/// The node values of the runtime's f32 path on `b`'s codes, or the f64 interpolation for a
/// node count the runtime's type is not instantiated for here.
fn values_of(b: &Baked, rgb: &[[f64; 3]]) -> Result<Vec<Vec<f64>>, Error> {
    Ok(match runtime_values(b, rgb)? {
        Some(v) => v,
        None => rgb
            .iter()
            .map(|p| b.interpolate(*p).expect("a fresh bake has its fit"))
            .collect(),
    })
}

/// The set for radiances at exactly `nodes` nm that a scene's `[fixed]` table bakes (the best
/// weights for those wavelengths), read through a scene as a user writes it.
fn fixed_set(d: &Derivation, nodes: &[f64]) -> Result<WavelengthSet, Error> {
    let list: Vec<String> = nodes.iter().map(|v| format!("{v}")).collect();
    let text = format!(
        "displays = [\"SRGB\"]\n[fixed.NODES]\nwavelengths_nm = [{}]\n",
        list.join(", ")
    );
    let scene = Scene::parse("fixed.toml", &text, &d.settings.data_dir)?;
    let resolved = scene.resolve(d)?;
    resolved
        .colour_sets
        .into_iter()
        .find(|s| s.name == "NODES")
        .ok_or_else(|| {
            Error::Derive(spectral_quadrature_generator::Error::Settings(
                "a scene's [fixed.NODES] gave no set NODES".into(),
            ))
        })
}
