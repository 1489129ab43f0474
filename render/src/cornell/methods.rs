//! The spectral methods, each reduced to what radiosity needs: a list of columns (wavelengths,
//! nodes or RGB channels), the light's emission and each paint's reflectance in every column,
//! and the weights that take the columns' radiosities to XYZ ([`Spectral`]). The spatial part
//! ([`Scene`]: mesh, form factors, view) is shared, so methods differ only here.
//!
//! - [`reference()`]: every nm from 400 to 700, weights x̄ȳz̄ · 1 nm, the light's emission.
//! - [`folded`]: a shared set `KQ_<light>_<n>` with the light folded into its weights; the
//!   light's emission is 1 at every node (the light is in the weights), so each column is an
//!   "effective reflectance" and the folded weights, divided by the generator's scale of the
//!   light ([`FoldedSet::scale`]), give XYZ in the reference's units.
//! - [`radiance`]: a radiance set `KQ_<n>`: the light's emission at the nodes.
//! - [`rgb`]: three channels, the paints and the light as linear sRGB, multiplied and solved.
//! - [`upsampled`]: the paints given as RGB and upsampled to a folded set's nodes.
//! - [`random_image`]: random wavelengths per pixel from the reference's per-nm solution.

use std::time::Instant;

use nalgebra::DMatrix;
use spectral_quadrature_generator::shared::{problem_for, Shared};
use spectral_quadrature_generator::{Derivation, WavelengthSet};
use spectral_quadrature_math::{delta_e2000, lab_from_xyz};
use spectral_quadrature_spectra::Curve;

use super::camera::{view, View};
use super::geometry::{form_factors, mesh, Mesh, Quad};
use super::radiosity::{solve, Bounces};
use super::RANGE_NM;
use crate::Error;
use spectral_quadrature_tools as tools;
use spectral_quadrature_tools::random_wavelengths::{pixel_rng, Sampler};

/// The spatial part, shared by every method: the mesh, its form factors and the camera view.
pub struct Scene {
    /// The meshed box.
    pub mesh: Mesh,
    /// Form factors, n × n.
    pub f: DMatrix<f64>,
    /// The camera's view.
    pub view: View,
    /// Seconds spent on the form factors.
    pub form_factor_seconds: f64,
}

impl Scene {
    /// Meshes `quads` into patches of at most `patch_mm`, computes the form factors and casts
    /// a `size × size` view.
    pub fn new(quads: &[Quad], patch_mm: f64, size: usize) -> Scene {
        let mesh = mesh(quads, patch_mm);
        let t = Instant::now();
        let n = mesh.patches.len();
        let f = DMatrix::from_row_slice(n, n, &form_factors(&mesh, quads));
        let form_factor_seconds = t.elapsed().as_secs_f64();
        let view = view(&mesh, size);
        Scene {
            mesh,
            f,
            view,
            form_factor_seconds,
        }
    }
}

/// One method as radiosity sees it.
#[derive(Debug, Clone, PartialEq)]
pub struct Spectral {
    /// The name in tables.
    pub name: String,
    /// Wavelengths (or channels) evaluated per pixel: the cost model.
    pub cost: usize,
    /// The light's emission in each column.
    pub emission: Vec<f64>,
    /// Each paint's reflectance in each column (white, red, green).
    pub reflectance: [Vec<f64>; 3],
    /// `to_xyz[c][k]`: the weight of column k in X, Y, Z.
    pub to_xyz: [Vec<f64>; 3],
}

impl Spectral {
    /// Solves the box: the radiosities, patches × columns.
    pub fn solve(&self, scene: &Scene, bounces: Bounces) -> DMatrix<f64> {
        let n = scene.mesh.patches.len();
        let k = self.emission.len();
        let mut e = DMatrix::zeros(n, k);
        let mut rho = DMatrix::zeros(n, k);
        for (i, p) in scene.mesh.patches.iter().enumerate() {
            for c in 0..k {
                match p.material.paint_index() {
                    Some(m) => rho[(i, c)] = self.reflectance[m][c],
                    None => e[(i, c)] = self.emission[c],
                }
            }
        }
        solve(&scene.f, &e, &rho, bounces).0
    }

    /// Each patch's XYZ from its radiosities.
    pub fn patch_xyz(&self, b: &DMatrix<f64>) -> Vec<[f64; 3]> {
        (0..b.nrows())
            .map(|i| {
                [0, 1, 2].map(|c| {
                    self.to_xyz[c]
                        .iter()
                        .enumerate()
                        .map(|(k, w)| w * b[(i, k)])
                        .sum()
                })
            })
            .collect()
    }

    /// The image, XYZ per pixel, and the seconds it took (solve and shading).
    pub fn render(&self, scene: &Scene, bounces: Bounces) -> (Vec<[f64; 3]>, f64) {
        let t = Instant::now();
        let b = self.solve(scene, bounces);
        let img = scene.view.shade(&self.patch_xyz(&b));
        (img, t.elapsed().as_secs_f64())
    }
}

fn paint_columns(paints: &[Curve; 3], nodes: &[f64]) -> [Vec<f64>; 3] {
    [0, 1, 2].map(|m| nodes.iter().map(|&l| paints[m].at(l)).collect())
}

/// The reference: every nm of 400-700, weights x̄ȳz̄ · 1 nm of the derivation's observer.
pub fn reference(d: &Derivation, light: &Curve, paints: &[Curve; 3]) -> Result<Spectral, Error> {
    let full = d.observer.full_integration(RANGE_NM, 1.0)?;
    let nodes = full.wavelengths_nm.clone();
    Ok(Spectral {
        name: "reference (1 nm)".into(),
        cost: nodes.len(),
        emission: nodes.iter().map(|&l| light.at(l)).collect(),
        reflectance: paint_columns(paints, &nodes),
        to_xyz: full.xyz_weights,
    })
}

/// A shared set with a light folded in, and the generator's scale of that light.
#[derive(Debug, Clone, PartialEq)]
pub struct FoldedSet {
    /// `KQ_<light>_<n>`.
    pub name: String,
    /// The set.
    pub shared: Shared,
    /// The generator's light over the light given: the problem scales the light to the
    /// luminance of an equal-energy spectrum of 1 ([`spectral_quadrature_generator::shared::Problem::light`]),
    /// so the folded weights give `scale` times the reference's XYZ.
    pub scale: f64,
}

impl FoldedSet {
    /// The set as the runtime bakes it, AC1C2 rows (for the upsampling's bake).
    pub fn wavelength_set(&self, d: &Derivation) -> WavelengthSet {
        let m = d.opponent.xyz_to_ac1c2;
        let w = &self.shared.xyz_weights;
        WavelengthSet {
            name: self.name.clone(),
            doc: String::new(),
            wavelengths_nm: self.shared.wavelengths_nm.clone(),
            weights: [0, 1, 2].map(|r| {
                (0..w[0].len())
                    .map(|k| (0..3).map(|c| m[r][c] * w[c][k]).sum())
                    .collect()
            }),
            light: self.shared.light.clone(),
            sensor: None,
        }
    }
}

/// The shared sets `KQ_<light>_<n>` for `light` (windowed), searched by the generator
/// ([`problem_for`], then [`spectral_quadrature_generator::shared::Problem::shared`]).
pub fn folded_sets(
    d: &Derivation,
    light: &Curve,
    sizes: &[usize],
) -> Result<Vec<FoldedSet>, Error> {
    let p = problem_for(d, Some(light))?;
    let given: f64 = p.grid_nm.iter().map(|&l| light.at(l)).sum();
    let scale = p.light.iter().sum::<f64>() / given;
    sizes
        .iter()
        .map(|&n| {
            Ok(FoldedSet {
                name: format!("KQ_{}_{n}", light.name),
                shared: p.shared(n)?,
                scale,
            })
        })
        .collect()
}

/// A folded set in radiosity: emission 1 at every node, the paints' reflectances there.
pub fn folded(set: &FoldedSet, paints: &[Curve; 3]) -> Spectral {
    let nodes = &set.shared.wavelengths_nm;
    with_node_values(set, set.name.clone(), paint_columns(paints, nodes))
}

/// A folded set with the paints' node values given (by an upsampling).
pub fn with_node_values(set: &FoldedSet, name: String, values: [Vec<f64>; 3]) -> Spectral {
    let nodes = &set.shared.wavelengths_nm;
    Spectral {
        name,
        cost: nodes.len(),
        emission: vec![1.0; nodes.len()],
        reflectance: values,
        to_xyz: set
            .shared
            .xyz_weights
            .clone()
            .map(|row| row.iter().map(|w| w / set.scale).collect()),
    }
}

/// The crate's radiance set `KQ_<n>` (from the node cache): the light's emission at the nodes.
pub fn radiance(
    d: &Derivation,
    n: usize,
    light: &Curve,
    paints: &[Curve; 3],
) -> Result<Spectral, Error> {
    let set = spectral_quadrature_generator::catalog::resolve(d, &format!("KQ_{n}"))?;
    let eval = d.eval_set(&set, "KQ");
    let nodes = eval.wavelengths_nm.clone();
    Ok(Spectral {
        name: format!("KQ_{n}"),
        cost: nodes.len(),
        emission: nodes.iter().map(|&l| light.at(l)).collect(),
        reflectance: paint_columns(paints, &nodes),
        to_xyz: eval.xyz_weights,
    })
}

/// The XYZ of `f` integrated every nm over 400-700 nm.
pub fn xyz_1nm(d: &Derivation, f: impl Fn(f64) -> f64) -> Result<[f64; 3], Error> {
    Ok(d.observer.full_integration(RANGE_NM, 1.0)?.xyz(f))
}

/// Where an RGB renderer's paint colours come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Albedo {
    /// The usual practice: each paint's linear sRGB under D65, white-balanced (a perfect white
    /// is (1, 1, 1)): the colour a texture holds (`upsampling::srgb_under_d65`).
    D65,
    /// Each paint's linear sRGB under the scene's own light, white-balanced: the direct
    /// light's colour is then exact, and only interreflection errs.
    UnderLight,
}

/// An RGB renderer: the paints as linear sRGB reflectances ([`Albedo`]), the light as the
/// linear sRGB of its 1 nm XYZ, three channels multiplied and solved, XYZ from sRGB.
pub fn rgb(
    d: &Derivation,
    light: &Curve,
    paints: &[Curve; 3],
    albedo: Albedo,
) -> Result<Spectral, Error> {
    let (_, m) = d.display("SRGB")?;
    let rgb_paints = match albedo {
        Albedo::D65 => tools::upsampling::srgb_under_d65(d, paints)?,
        Albedo::UnderLight => {
            spectral_quadrature_generator::upsampling::exact_rgb(d, m, light, paints)?
        }
    };
    let xyz = xyz_1nm(d, |l| light.at(l))?;
    let light_rgb = [0, 1, 2].map(|c| (0..3).map(|k| m.xyz_to_rgb[c][k] * xyz[k]).sum::<f64>());
    Ok(Spectral {
        name: match albedo {
            Albedo::D65 => "RGB (paints' sRGB under D65)".into(),
            Albedo::UnderLight => "RGB (paints' sRGB under the light)".into(),
        },
        cost: 3,
        emission: light_rgb.to_vec(),
        reflectance: [0, 1, 2].map(|p| rgb_paints[p].to_vec()),
        to_xyz: [0, 1, 2].map(|c| m.rgb_to_xyz[c].to_vec()),
    })
}

/// How the paints' RGB reach a folded set's nodes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Upsampler {
    /// The crate's map for the set, baked by the generator
    /// ([`spectral_quadrature_generator::upsampling::bake`], the programme the build runs for a
    /// scene's `[upsampling]`) under the set's light and evaluated by the runtime's
    /// [`spectral_quadrature::Upsampling`]; the RGB is the paint's white-balanced linear sRGB
    /// under that light (the map's convention).
    CrateMap,
    /// Jakob-Hanika ([`tools::upsampling::jakob_hanika`]), fitted to the paint's
    /// white-balanced linear sRGB under D65 (its convention), evaluated at the nodes.
    JakobHanika,
}

/// The paints given as RGB, upsampled to `set`'s nodes by `how`.
pub fn upsampled(
    d: &Derivation,
    set: &FoldedSet,
    light: &Curve,
    paints: &[Curve; 3],
    how: Upsampler,
) -> Result<Spectral, Error> {
    let nodes = &set.shared.wavelengths_nm;
    let (_, m) = d.display("SRGB")?;
    let values: Vec<Vec<f64>> = match how {
        Upsampler::CrateMap => {
            let rgb = spectral_quadrature_generator::upsampling::exact_rgb(d, m, light, paints)?;
            let training = spectral_quadrature_generator::upsampling::training(
                &d.settings.data_dir,
                d.settings.range_nm,
            )?;
            let baked = spectral_quadrature_generator::upsampling::bake(
                d,
                &set.wavelength_set(d),
                ("SRGB", m),
                light,
                true,
                &training,
                spectral_quadrature_generator::upsampling::DEFAULT_GRID,
            )?;
            tools::upsampling::runtime_values(&baked, &rgb)?.ok_or_else(|| {
                Error::Derive(spectral_quadrature_generator::Error::Numerical(format!(
                    "no runtime upsampling path for {} nodes",
                    baked.wavelengths_nm.len()
                )))
            })?
        }
        Upsampler::JakobHanika => {
            let jh = tools::upsampling::jakob_hanika::JakobHanika::srgb(d)?;
            tools::upsampling::srgb_under_d65(d, paints)?
                .iter()
                .map(|c| jh.at(*c, nodes))
                .collect()
        }
    };
    let name = match how {
        Upsampler::CrateMap => format!("{} + crate's map", set.name),
        Upsampler::JakobHanika => format!("{} + Jakob-Hanika", set.name),
    };
    let [w, r, g]: [Vec<f64>; 3] = values.try_into().expect("three paints");
    Ok(with_node_values(set, name, [w, r, g]))
}

/// The reference's integrand per patch and 1 nm cell: `x̄ȳz̄(λₖ) · 1 nm · B(λₖ)` for the
/// cells centred on 400, 401, …, 700 nm (as [`tools::random_wavelengths::Cells`] reads a grid
/// sum: its integral is exactly the reference's XYZ).
pub fn cells(reference: &Spectral, b: &DMatrix<f64>) -> Vec<Vec<[f64; 3]>> {
    (0..b.nrows())
        .map(|i| {
            (0..b.ncols())
                .map(|k| [0, 1, 2].map(|c| reference.to_xyz[c][k] * b[(i, k)]))
                .collect()
        })
        .collect()
}

/// The range hero and uniform sampling draw on: the reference's cells, 399.5-700.5 nm.
pub const CELL_SPAN_NM: [f64; 2] = [RANGE_NM[0] - 0.5, RANGE_NM[1] + 0.5];

/// Random wavelengths per pixel: each pixel draws `spp.last()` samples of `per_sample`
/// wavelengths from `sampler` (its own PCG stream, `[stream, pixel]` of `seed`) and adds
/// `f(λ)/p(λ)` of the reference's integrand ([`cells`]) at the pixel; returns the image (XYZ
/// per pixel) after each level of `spp` (ascending), and the seconds per image at the last.
pub fn random_image(
    scene: &Scene,
    cells: &[Vec<[f64; 3]>],
    sampler: Sampler,
    per_sample: usize,
    spp: &[usize],
    seed: u64,
    stream: u64,
) -> (Vec<Vec<[f64; 3]>>, f64) {
    let t = Instant::now();
    let px: Vec<usize> = (0..scene.view.pixels.len()).collect();
    let last = spp.last().copied().unwrap_or(0);
    let per_pixel = tools::par_map(&px, |&k| {
        let p = &scene.view.pixels[k];
        let mut out = Vec::with_capacity(spp.len());
        if p.weights.is_empty() {
            return vec![[0.0; 3]; spp.len()];
        }
        let mut rng = pixel_rng(seed, &[stream, k as u64]);
        let mut buf = vec![0.0; per_sample];
        let mut sum = [0.0; 3];
        let mut level = 0;
        for s in 1..=last {
            sampler.wavelengths(&mut rng, &mut buf);
            for &l in &buf {
                let cell = (l - RANGE_NM[0] + 0.5).floor();
                let pdf = sampler.pdf(l);
                if !(0.0..=RANGE_NM[1] - RANGE_NM[0]).contains(&cell) || pdf <= 0.0 {
                    continue;
                }
                let cell = cell as usize;
                for &(i, w) in &p.weights {
                    let v = cells[i][cell];
                    for c in 0..3 {
                        sum[c] += w * v[c] / pdf;
                    }
                }
            }
            if s == spp[level] {
                let n = (s * per_sample) as f64;
                out.push(sum.map(|v| v / n));
                level += 1;
            }
        }
        out
    });
    let seconds = t.elapsed().as_secs_f64();
    let images = (0..spp.len())
        .map(|l| per_pixel.iter().map(|p| p[l]).collect())
        .collect();
    (images, seconds)
}

/// The white every image is judged against: the reference XYZ of the light itself (1 nm,
/// 400-700 nm) scaled to the luminance of the reference image's brightest painted pixel, so
/// that pixel has L* = 100 and the white has the light's chromaticity.
pub fn white(
    d: &Derivation,
    light: &Curve,
    reference: &[[f64; 3]],
    painted: &[usize],
) -> Result<[f64; 3], Error> {
    let xyz = xyz_1nm(d, |l| light.at(l))?;
    let y = painted
        .iter()
        .map(|&k| reference[k][1])
        .fold(0.0f64, f64::max);
    Ok(xyz.map(|v| v * y / xyz[1]))
}

/// CIEDE2000 of each painted pixel of `image` against `reference`, with `white`.
pub fn de00(
    image: &[[f64; 3]],
    reference: &[[f64; 3]],
    painted: &[usize],
    white: [f64; 3],
) -> Vec<f64> {
    painted
        .iter()
        .map(|&k| {
            delta_e2000(
                lab_from_xyz(reference[k], white),
                lab_from_xyz(image[k], white),
            )
        })
        .collect()
}
