//! The methods, each made from a scene: what a path carries and every surface's values in that
//! form, computed once at load. The runtime's types are built in [`runtime`], the one place
//! that calls their constructors.
//!
//! - **RGB**: each surface as its linear sRGB under D65, white-balanced (a perfect white is
//!   (1, 1, 1): what an sRGB texture holds; measured paints are converted as
//!   [`tools::upsampling::srgb_under_d65`] does), each light as the linear sRGB of its own
//!   1 nm XYZ over 400-700 nm, in the reference's units (not white-balanced: a white surface
//!   lit by it has exactly the light's colour). Pixels: linear sRGB to XYZ.
//! - **Random wavelengths** (pbrt-v4's visible-wavelength density, hero wavelengths; K = 4 or
//!   16 a path): measured spectra read at each wavelength's 1 nm cell; an sRGB surface through
//!   Jakob-Hanika, its three coefficients fitted once per colour at load, the sigmoid
//!   evaluated per wavelength.
//! - **Fixed sets** (N = 4, 6, 8, 16): one light, a folded set `KQ_<light>_<n>` searched by the
//!   generator for the scene's light (`shared::problem_for`, `Problem::shared`); several
//!   lights, a light group fitted by the generator (`shared::GroupFit`, the mean objective, one
//!   matrix per light) on the upsampling's training reflectances. Measured spectra sampled at
//!   the nodes; an sRGB surface through the crate's upsampling map at the set's nodes
//!   ([`texel_map`]), converted once when the texture is loaded.
//! - **Reference**: every nm of 400-700, the measured reflectances the sRGB came from.

use std::collections::HashMap;

use spectral_quadrature::{FoldedSet, LightGroupSet, Samples, Upsampling};
use spectral_quadrature_generator::shared::{
    nodes_of, problem_for, GroupFit, GroupObjective, Weights,
};
use spectral_quadrature_generator::upsampling::{bake, Baked, DEFAULT_GRID};
use spectral_quadrature_generator::{Derivation, WavelengthSet};
use spectral_quadrature_spectra::Curve;

use super::carriers::{
    Folded, Grid, Group, Random, RandomMaterial, Reference, Rgb, GRID_LEN, GRID_NM, REFERENCE_LANES,
};
use super::scene::Scene;
use super::transport::{run_levels, Carrier, Geometry, Options, Progress, Progressive, Rendered};
use crate::Error;
use spectral_quadrature_tools as tools;
use spectral_quadrature_tools::random_wavelengths::Sampler;
use spectral_quadrature_tools::upsampling::jakob_hanika::JakobHanika;

/// A spectral method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    /// Every nm of 400-700 (the reference).
    Reference,
    /// Three RGB channels.
    Rgb,
    /// K random wavelengths a path.
    Random {
        /// How they are drawn.
        sampler: Sampler,
        /// K: 4 or 16.
        k: usize,
    },
    /// A fixed set of N nodes: folded for one light, a light group for several.
    Fixed {
        /// N: 4, 6, 8 or 16.
        n: usize,
    },
}

/// The range hero wavelengths are drawn on: the reference's 1 nm cells, 399.5-700.5 nm.
pub const HERO: Sampler = Sampler::Hero {
    range_nm: [GRID_NM[0] - 0.5, GRID_NM[1] + 0.5],
};

/// The fixed sets' sizes.
pub const FIXED_SIZES: [usize; 4] = [4, 6, 8, 16];

impl Method {
    /// Its name in tables, plots and pictures.
    pub fn name(&self) -> String {
        match self {
            Method::Reference => "reference (1 nm)".into(),
            Method::Rgb => "RGB".into(),
            Method::Random { sampler, k } => format!("{} ×{k}", sampler.name()),
            Method::Fixed { n } => format!("fixed {n}"),
        }
    }

    /// `N` of the CSV: channels, wavelengths or nodes a path carries.
    pub fn lanes(&self) -> usize {
        match self {
            Method::Reference => GRID_LEN,
            Method::Rgb => 3,
            Method::Random { k, .. } => *k,
            Method::Fixed { n } => *n,
        }
    }

    /// The methods measured in a scene: RGB, pbrt-v4 ×4, hero ×4, the fixed sets, and where a
    /// light is F11 or LED-B2, random wavelengths with 16 a path.
    pub fn all_for(scene: &Scene) -> Vec<Method> {
        let mut v = vec![
            Method::Rgb,
            Method::Random {
                sampler: Sampler::Visible,
                k: 4,
            },
            Method::Random {
                sampler: HERO,
                k: 4,
            },
        ];
        if scene
            .lights
            .iter()
            .any(|l| l.name == "F11" || l.name == "LED_B2")
        {
            v.push(Method::Random {
                sampler: Sampler::Visible,
                k: 16,
            });
            v.push(Method::Random {
                sampler: HERO,
                k: 16,
            });
        }
        v.extend(FIXED_SIZES.map(|n| Method::Fixed { n }));
        v
    }
}

/// A fixed set's nodes (nm) and, per light, its folded XYZ weights.
pub type FixedSet = (Vec<f64>, Vec<[Vec<f64>; 3]>);

/// What every method of a scene shares: the derivation, the display and the 1 nm integration.
pub struct Setup<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// The derivation (observer, displays, data folder).
    pub d: &'a Derivation,
    /// The 1 nm X, Y, Z weights over 400-700 nm.
    pub xyz_1nm: [Vec<f64>; 3],
    /// The reflectances the fits train on: the upsampling's (the CIE test colours and the 190
    /// rawtoaces patches; never the ColorChecker).
    pub training: Vec<Curve>,
    /// How long each fixed set took to build (search, fit, map), seconds, by N.
    pub build_seconds: std::sync::Mutex<Vec<(usize, f64)>>,
    /// The fixed sets found so far, by N (a search runs once per scene).
    fixed_sets: std::sync::Mutex<HashMap<usize, FixedSet>>,
}

/// One paint's error at a fixed set's nodes: [`Setup::paint_errors`].
#[derive(Debug, Clone, PartialEq)]
pub struct PaintError {
    /// The light it is lit by.
    pub light: String,
    /// The paint.
    pub paint: String,
    /// Light reflected this many times off the paint: the reflectance raised to this power.
    pub bounces: i32,
    /// CIEDE2000 of the set's colour against the 1 nm colour, under the light.
    pub de00: f64,
    /// The same with the paint's reflectance smoothed over [`SMOOTH_NM`] first.
    pub de00_smoothed: f64,
}

/// The width of the moving average of [`PaintError::de00_smoothed`], nm: it removes the
/// measured reflectances' ripple of 10-20 nm and keeps their shape.
pub const SMOOTH_NM: usize = 21;

impl<'a> Setup<'a> {
    /// The shared parts for `scene`.
    pub fn new(scene: &'a Scene, d: &'a Derivation) -> Result<Setup<'a>, Error> {
        let full = d.observer.full_integration(GRID_NM, 1.0)?;
        let training = spectral_quadrature_generator::upsampling::training(
            &d.settings.data_dir,
            d.settings.range_nm,
        )?;
        Ok(Setup {
            scene,
            d,
            xyz_1nm: full.xyz_weights,
            training,
            build_seconds: std::sync::Mutex::new(Vec::new()),
            fixed_sets: std::sync::Mutex::new(HashMap::new()),
        })
    }

    /// Every surface row's linear sRGB as the methods see it (white-balanced under D65): the
    /// paints' (given, or of their measured reflectances), then the texels'.
    pub fn srgb_rows(&self) -> Result<Vec<[f64; 3]>, Error> {
        let mut rows: Vec<[f64; 3]> = match self.scene.paint_srgb {
            Some(p) => p.to_vec(),
            None => tools::upsampling::srgb_under_d65(self.d, &self.scene.data.paints)?,
        };
        if let Some(t) = &self.scene.texture {
            rows.extend(t.linear.iter().copied());
        }
        Ok(rows)
    }

    /// Whether the methods see the paints' measured reflectances (else their sRGB).
    fn measured_paints(&self) -> bool {
        self.scene.paint_srgb.is_none()
    }

    /// The number of surface rows.
    fn rows(&self) -> usize {
        3 + self
            .scene
            .texture
            .as_ref()
            .map_or(0, |t| t.width * t.height)
    }

    /// A curve on the 1 nm grid, with a 0 for outside it.
    fn grid(c: &Curve) -> Grid {
        let mut g = [0.0f32; GRID_LEN + 1];
        for (k, v) in g.iter_mut().take(GRID_LEN).enumerate() {
            *v = c.at(GRID_NM[0] + k as f64) as f32;
        }
        g
    }

    /// The RGB method.
    pub fn rgb(&self) -> Result<Rgb, Error> {
        let (_, m) = self.d.display("SRGB")?;
        let table = self
            .srgb_rows()?
            .iter()
            .map(|c| c.map(|v| v as f32))
            .collect();
        let emission = self
            .scene
            .lights
            .iter()
            .map(|l| {
                let xyz = crate::cornell::methods::xyz_1nm(self.d, |nm| l.curve.at(nm))?;
                Ok([0, 1, 2]
                    .map(|c| (0..3).map(|k| m.xyz_to_rgb[c][k] * xyz[k]).sum::<f64>() as f32))
            })
            .collect::<Result<Vec<_>, Error>>()?;
        Ok(Rgb { table, emission })
    }

    /// A random-wavelength method of K wavelengths a path.
    pub fn random<const K: usize>(&self, sampler: Sampler) -> Result<Random<K>, Error> {
        let mut spectra: Vec<Grid> = Vec::new();
        let mut materials = Vec::with_capacity(self.rows());
        let srgb = self.srgb_rows()?;
        let jh = JakobHanika::srgb(self.d)?;
        let mut fitted: HashMap<[u64; 3], [f32; 3]> = HashMap::new();
        let mut sigmoid = |rgb: [f64; 3]| -> RandomMaterial {
            let c = *fitted
                .entry(rgb.map(f64::to_bits))
                .or_insert_with(|| jh.fit(rgb).map(|v| v as f32));
            RandomMaterial::Sigmoid(c)
        };
        for (row, rgb) in srgb.iter().enumerate() {
            if row < 3 && self.measured_paints() {
                spectra.push(Self::grid(&self.scene.data.paints[row]));
                materials.push(RandomMaterial::Measured(spectra.len() - 1));
            } else {
                materials.push(sigmoid(*rgb));
            }
        }
        Ok(Random {
            sampler,
            materials,
            spectra,
            emission: self
                .scene
                .lights
                .iter()
                .map(|l| Self::grid(&l.curve))
                .collect(),
            xyz: [0, 1, 2].map(|c| {
                let mut g = [0.0f32; GRID_LEN + 1];
                for (k, v) in g.iter_mut().take(GRID_LEN).enumerate() {
                    *v = self.xyz_1nm[c][k] as f32;
                }
                g
            }),
        })
    }

    /// The reference.
    pub fn reference(&self) -> Reference {
        let lanes = |c: &Curve| {
            let mut g = [0.0f32; REFERENCE_LANES];
            for (k, v) in g.iter_mut().take(GRID_LEN).enumerate() {
                *v = c.at(GRID_NM[0] + k as f64) as f32;
            }
            g
        };
        let mut spectra: Vec<[f32; REFERENCE_LANES]> =
            self.scene.data.paints.iter().map(lanes).collect();
        let mut rows: Vec<u16> = vec![0, 1, 2];
        if let Some(t) = &self.scene.texture {
            spectra.extend(t.reflectances.iter().map(lanes));
            rows.extend(t.patch.iter().map(|&p| 3 + p));
        }
        Reference {
            rows,
            spectra,
            emission: self.scene.lights.iter().map(|l| lanes(&l.curve)).collect(),
            xyz: [0, 1, 2].map(|c| {
                let mut g = [0.0f64; REFERENCE_LANES];
                g[..GRID_LEN].copy_from_slice(&self.xyz_1nm[c]);
                g
            }),
        }
    }

    /// A fixed set's nodes and, per light, its folded XYZ weights in the reference's units
    /// (a reflectance of 1 gives that light's own 1 nm XYZ): the folded set of the scene's one
    /// light, or the light group of its lights.
    pub fn fixed_set(&self, n: usize) -> Result<FixedSet, Error> {
        if let Some(f) = self.fixed_sets.lock().ok().and_then(|m| m.get(&n).cloned()) {
            return Ok(f);
        }
        let f = self.search_fixed_set(n)?;
        if let Ok(mut m) = self.fixed_sets.lock() {
            m.insert(n, f.clone());
        }
        Ok(f)
    }

    /// Each measured paint's error at the nodes of the fixed set of `n` (its weights under each
    /// light), alone and as light reflected twice and four times off it (its reflectance
    /// squared and to the fourth: what interreflection between walls of one paint makes), and
    /// the same with the paint smoothed over [`SMOOTH_NM`]. Empty where the paints are given as
    /// sRGB.
    pub fn paint_errors(&self, n: usize) -> Result<Vec<PaintError>, Error> {
        if !self.measured_paints() {
            return Ok(Vec::new());
        }
        let (nodes, weights) = self.fixed_set(n)?;
        let mut out = Vec::new();
        for (light, w) in self.scene.lights.iter().zip(&weights) {
            let truth = |f: &dyn Fn(f64) -> f64| -> [f64; 3] {
                [0, 1, 2].map(|c| {
                    self.xyz_1nm[c]
                        .iter()
                        .enumerate()
                        .map(|(k, x)| {
                            let nm = GRID_NM[0] + k as f64;
                            x * light.curve.at(nm) * f(nm)
                        })
                        .sum()
                })
            };
            let at_nodes = |f: &dyn Fn(f64) -> f64| -> [f64; 3] {
                [0, 1, 2].map(|c| nodes.iter().zip(&w[c]).map(|(&nm, w)| w * f(nm)).sum())
            };
            let white = truth(&|_| 1.0);
            let de = |f: &dyn Fn(f64) -> f64| {
                spectral_quadrature_math::delta_e2000(
                    spectral_quadrature_math::lab_from_xyz(truth(f), white),
                    spectral_quadrature_math::lab_from_xyz(at_nodes(f), white),
                )
            };
            for paint in &self.scene.data.paints {
                let half = (SMOOTH_NM / 2) as f64;
                let smooth = |nm: f64| {
                    (0..SMOOTH_NM)
                        .map(|k| paint.at((nm - half + k as f64).clamp(GRID_NM[0], GRID_NM[1])))
                        .sum::<f64>()
                        / SMOOTH_NM as f64
                };
                for bounces in [1, 2, 4] {
                    out.push(PaintError {
                        light: light.name.clone(),
                        paint: paint.name.clone(),
                        bounces,
                        de00: de(&|nm| paint.at(nm).powi(bounces)),
                        de00_smoothed: de(&|nm| smooth(nm).powi(bounces)),
                    });
                }
            }
        }
        Ok(out)
    }

    /// [`fixed_set`](Self::fixed_set), searched.
    fn search_fixed_set(&self, n: usize) -> Result<FixedSet, Error> {
        let d = self.d;
        let problems = self
            .scene
            .lights
            .iter()
            .map(|l| problem_for(d, Some(&l.curve)))
            .collect::<Result<Vec<_>, _>>()?;
        // The generator scales each light to the luminance of an equal-energy spectrum of 1:
        // its weights give `scale` times the reference's XYZ.
        let scales: Vec<f64> = problems
            .iter()
            .zip(&self.scene.lights)
            .map(|(p, l)| {
                let given: f64 = p.grid_nm.iter().map(|&nm| l.curve.at(nm)).sum();
                p.light.iter().sum::<f64>() / given
            })
            .collect();
        let unscale =
            |w: &[Vec<f64>; 3], s: f64| w.clone().map(|r| r.iter().map(|v| v / s).collect());
        if problems.len() == 1 {
            let shared = problems[0].shared(n)?;
            let w = unscale(&shared.xyz_weights, scales[0]);
            return Ok((shared.wavelengths_nm, vec![w]));
        }
        let own: Vec<Vec<usize>> = problems
            .iter()
            .map(|p| Ok(nodes_of(p, &p.shared(n)?)))
            .collect::<Result<_, Error>>()?;
        let fit = GroupFit::new(problems, &self.training)?;
        let g = fit.optimize(n, &own, GroupObjective::Mean, Weights::PerLight)?;
        let w = g
            .members
            .iter()
            .zip(&scales)
            .map(|(m, &s)| unscale(&m.xyz_weights, s))
            .collect();
        Ok((g.wavelengths_nm, w))
    }

    /// Each surface row's values at `nodes`: measured paints sampled there, sRGB colours
    /// through [`texel_map`].
    fn node_table<const N: usize>(&self, nodes: &[f64]) -> Result<Vec<[f32; N]>, Error> {
        let srgb = self.srgb_rows()?;
        let needs_map = !self.measured_paints() || self.scene.texture.is_some();
        let map = if needs_map {
            Some(runtime::upsampling::<N>(&texel_map(
                self.d,
                nodes,
                &self.training,
            )?)?)
        } else {
            None
        };
        srgb.iter()
            .enumerate()
            .map(|(row, rgb)| {
                if row < 3 && self.measured_paints() {
                    Ok(std::array::from_fn(|i| {
                        self.scene.data.paints[row].at(nodes[i]) as f32
                    }))
                } else {
                    let m = map
                        .as_ref()
                        .ok_or_else(|| Error::Sampling("an sRGB surface without a map".into()))?;
                    Ok(m.reflectance(rgb.map(|v| v as f32)))
                }
            })
            .collect()
    }

    /// The fixed set of N nodes, as a carrier (the set's build timed into `build_seconds`).
    pub fn folded<const N: usize>(&self) -> Result<Folded<N>, Error> {
        let t = std::time::Instant::now();
        let (nodes, w) = self.fixed_set(N)?;
        let table = self.node_table::<N>(&nodes)?;
        let set = runtime::folded::<N>(&nodes, &w[0], &self.scene.lights[0].name)?;
        self.timed(N, t);
        Ok(Folded { table, set })
    }

    /// The light group of N nodes for the scene's L lights.
    pub fn group<const N: usize, const L: usize>(&self) -> Result<Group<N, L>, Error> {
        let t = std::time::Instant::now();
        let (nodes, w) = self.fixed_set(N)?;
        let table = self.node_table::<N>(&nodes)?;
        let names: Vec<&str> = self.scene.lights.iter().map(|l| l.name.as_str()).collect();
        let set = runtime::group::<N, L>(&nodes, &w, &names)?;
        self.timed(N, t);
        Ok(Group { table, set })
    }

    fn timed(&self, n: usize, t: std::time::Instant) {
        if let Ok(mut v) = self.build_seconds.lock() {
            v.push((n, t.elapsed().as_secs_f64()));
        }
    }

    /// `method` on `g`, ready to render pass by pass (its tables made now, outside the
    /// render's time).
    pub fn progress<'g>(
        &self,
        method: Method,
        g: &'g Geometry,
        opts: Options,
    ) -> Result<Box<dyn Progressive + 'g>, Error> {
        fn boxed<'g, const M: usize, C: Carrier<M> + 'g>(
            g: &'g Geometry,
            c: C,
            opts: Options,
        ) -> Box<dyn Progressive + 'g> {
            Box::new(Progress::new(g, c, opts))
        }
        let lights = self.scene.lights.len();
        Ok(match method {
            Method::Reference => boxed(g, self.reference(), opts),
            Method::Rgb => boxed(g, self.rgb()?, opts),
            Method::Random { sampler, k: 4 } => boxed(g, self.random::<4>(sampler)?, opts),
            Method::Random { sampler, k: 16 } => boxed(g, self.random::<16>(sampler)?, opts),
            Method::Fixed { n } => match (n, lights) {
                (4, 1) => boxed(g, self.folded::<4>()?, opts),
                (6, 1) => boxed(g, self.folded::<6>()?, opts),
                (8, 1) => boxed(g, self.folded::<8>()?, opts),
                (16, 1) => boxed(g, self.folded::<16>()?, opts),
                (4, 2) => boxed(g, self.group::<4, 2>()?, opts),
                (6, 2) => boxed(g, self.group::<6, 2>()?, opts),
                (8, 2) => boxed(g, self.group::<8, 2>()?, opts),
                (16, 2) => boxed(g, self.group::<16, 2>()?, opts),
                _ => {
                    return Err(Error::Sampling(format!(
                        "no fixed set of {n} nodes for {lights} lights"
                    )))
                }
            },
            Method::Random { k, .. } => {
                return Err(Error::Sampling(format!("no random method of {k} a path")))
            }
        })
    }

    /// Renders `method` on `g` at each level of `spp`, in one go.
    pub fn render(
        &self,
        method: Method,
        g: &Geometry,
        spp: &[usize],
        opts: Options,
    ) -> Result<Rendered, Error> {
        Ok(run_levels(self.progress(method, g, opts)?.as_mut(), spp))
    }
}

/// D65's folded XYZ weights at `nodes`: for each of X, Y, Z the least-squares fit of the
/// training reflectances' 1 nm XYZ under D65 (over the derivation's range, as the texels' sRGB
/// is computed) from their values at the nodes, with the white pinned (a reflectance of 1 gives
/// D65's white exactly), as the generator fits a light group's weights.
pub fn d65_weights(
    d: &Derivation,
    nodes: &[f64],
    training: &[Curve],
) -> Result<[Vec<f64>; 3], Error> {
    let d65 = tools::upsampling::d65(d)?;
    let full = d.observer.full_integration(d.settings.range_nm, 1.0)?;
    let xyz = |f: &dyn Fn(f64) -> f64| -> [f64; 3] {
        [0, 1, 2].map(|c| {
            full.wavelengths_nm
                .iter()
                .zip(&full.xyz_weights[c])
                .map(|(&nm, w)| w * d65.at(nm) * f(nm))
                .sum()
        })
    };
    let n = nodes.len();
    let white = xyz(&|_| 1.0);
    let mut ata = nalgebra::DMatrix::<f64>::zeros(n + 1, n + 1);
    let mut atb = [
        nalgebra::DVector::<f64>::zeros(n + 1),
        nalgebra::DVector::zeros(n + 1),
        nalgebra::DVector::zeros(n + 1),
    ];
    for r in training {
        let s: Vec<f64> = nodes.iter().map(|&l| r.at(l)).collect();
        let t = xyz(&|nm| r.at(nm));
        for i in 0..n {
            for j in 0..n {
                ata[(i, j)] += s[i] * s[j];
            }
            for c in 0..3 {
                atb[c][i] += s[i] * t[c];
            }
        }
    }
    for i in 0..n {
        ata[(i, n)] = 1.0;
        ata[(n, i)] = 1.0;
    }
    let lu = ata.lu();
    let mut out: [Vec<f64>; 3] = Default::default();
    for c in 0..3 {
        atb[c][n] = white[c];
        let w = lu.solve(&atb[c]).ok_or_else(|| {
            Error::Sampling(format!(
                "no D65 weights at {nodes:?} nm: the system is singular"
            ))
        })?;
        out[c] = w.iter().take(n).copied().collect();
    }
    Ok(out)
}

/// The crate's upsampling map at `nodes` for sRGB colours under D65 (what a texture holds):
/// the generator's `upsampling::bake` (the programme a scene's `[upsampling]` runs, on the
/// default grid and training reflectances) for the set at `nodes` with D65 folded into its
/// weights ([`d65_weights`]), so that each texel's node values are reflectances whose colour
/// under D65 is the texel's. The renderer then lights them with the scene's own set.
pub fn texel_map(d: &Derivation, nodes: &[f64], training: &[Curve]) -> Result<Baked, Error> {
    let xyz = d65_weights(d, nodes, training)?;
    let m = d.opponent.xyz_to_ac1c2;
    let set = WavelengthSet {
        name: format!("D65_AT_{}", nodes.len()),
        doc: String::new(),
        wavelengths_nm: nodes.to_vec(),
        weights: [0, 1, 2].map(|r| {
            (0..nodes.len())
                .map(|k| (0..3).map(|c| m[r][c] * xyz[c][k]).sum())
                .collect()
        }),
        light: Some("D65".into()),
        sensor: None,
    };
    let (_, srgb) = d.display("SRGB")?;
    let d65 = tools::upsampling::d65(d)?;
    Ok(bake(
        d,
        &set,
        ("SRGB", srgb),
        &d65,
        true,
        training,
        DEFAULT_GRID,
    )?)
}

/// The runtime's types, built from the generator's f64 results with their public checked
/// constructors: the one place that calls them.
pub mod runtime {
    use super::*;

    fn leak(s: &str) -> &'static str {
        Box::leak(s.to_string().into_boxed_str())
    }

    fn derive_err(e: spectral_quadrature::Error) -> Error {
        Error::Derive(spectral_quadrature_generator::Error::Numerical(
            e.to_string(),
        ))
    }

    /// Linear sRGB rows from XYZ rows, in f32.
    fn rgb_rows<const N: usize>(xyz: &[Vec<f64>; 3]) -> [[f32; N]; 3] {
        let m = spectral_quadrature::tables::displays::SRGB.xyz_to_rgb();
        [0, 1, 2].map(|c| {
            std::array::from_fn(|i| {
                (0..3).map(|k| f64::from(m[c][k]) * xyz[k][i]).sum::<f64>() as f32
            })
        })
    }

    /// A [`FoldedSet`] for sRGB at `nodes` with folded XYZ weights `xyz`, for `light`.
    pub fn folded<const N: usize>(
        nodes: &[f64],
        xyz: &[Vec<f64>; 3],
        light: &str,
    ) -> Result<FoldedSet<N>, Error> {
        FoldedSet::new(
            std::array::from_fn(|i| nodes[i] as f32),
            rgb_rows::<N>(xyz),
            Samples::Reflectance { light: leak(light) },
            spectral_quadrature::tables::displays::SRGB,
        )
        .map_err(derive_err)
    }

    /// A [`LightGroupSet`] for sRGB at `nodes`, one XYZ weight matrix per light.
    pub fn group<const N: usize, const L: usize>(
        nodes: &[f64],
        xyz: &[[Vec<f64>; 3]],
        names: &[&str],
    ) -> Result<LightGroupSet<N, L>, Error> {
        LightGroupSet::new(
            std::array::from_fn(|i| nodes[i] as f32),
            std::array::from_fn(|l| rgb_rows::<N>(&xyz[l])),
            std::array::from_fn(|l| leak(names[l])),
            spectral_quadrature::tables::displays::SRGB,
        )
        .map_err(derive_err)
    }

    /// The runtime's [`Upsampling`] on a bake's codes.
    pub fn upsampling<const N: usize>(b: &Baked) -> Result<Upsampling<N>, Error> {
        let table: Vec<[u16; N]> = b
            .codes
            .iter()
            .map(|c| std::array::from_fn(|i| c[i]))
            .collect();
        // The runtime's tables are 'static (baked into the binary); the tool leaks its few.
        let table: &'static [[u16; N]] = Box::leak(table.into_boxed_slice());
        // The set the bake is for, as the runtime holds it: the nodes, the bake's encoding
        // (node values to sRGB under the reference light, D65) and that light.
        let set = FoldedSet::new(
            std::array::from_fn(|i| b.wavelengths_nm[i] as f32),
            std::array::from_fn(|c| std::array::from_fn(|i| b.encoding[c][i] as f32)),
            Samples::Reflectance {
                light: leak(&b.light),
            },
            spectral_quadrature::tables::displays::SRGB,
        )
        .map_err(derive_err)?;
        Upsampling::new(set, b.grid, table, None).map_err(derive_err)
    }
}
