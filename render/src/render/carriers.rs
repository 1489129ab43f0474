//! What a path carries, one [`Carrier`] per kind of method: [`Rgb`], [`Random`] wavelengths,
//! a [`Folded`] set, a light [`Group`], and the [`Reference`] (every nm). Each holds its
//! surfaces' values in its own form, made once when the scene is loaded ([`super::methods`]):
//! a texture lookup returns the values a path multiplies by, with nothing left to convert.

use spectral_quadrature::{FoldedSet, LightGroupSet};

use super::transport::{
    add_product, add_scaled, frame_display, matrix_planes, scale_planes, Carrier, Film, Pcg32,
    Surface,
};
use spectral_quadrature_tools::random_wavelengths::Sampler;

/// The reference's wavelengths: every nm of 400-700 (the paints' measured range).
pub const GRID_NM: [f64; 2] = [400.0, 700.0];
/// How many: 301.
pub const GRID_LEN: usize = 301;
/// The reference's lanes: 301 rounded up to whole eight-lane vectors (the last three are 0).
pub const REFERENCE_LANES: usize = 304;
/// A table on the 1 nm grid with one more entry, 0, for wavelengths outside it.
pub type Grid = [f32; GRID_LEN + 1];

/// RGB rendering: three channels, the surfaces as linear sRGB reflectances, each light as the
/// linear sRGB of its XYZ. The film is the frame: its frame is the mean.
#[derive(Debug, Clone)]
pub struct Rgb {
    /// Per surface row ([`Surface::index`]): its linear sRGB.
    pub table: Vec<[f32; 3]>,
    /// Per light: its linear sRGB.
    pub emission: Vec<[f32; 3]>,
}

impl Carrier<3> for Rgb {
    type Path = ();
    type Radiance = [f32; 3];
    type Sum = f32;

    #[inline(always)]
    fn start(&self, _: &mut Pcg32) {}
    #[inline(always)]
    fn reflectance(&self, _: &(), s: Surface) -> [f32; 3] {
        self.table[s.index()]
    }
    #[inline(always)]
    fn no_radiance(&self) -> [f32; 3] {
        [0.0; 3]
    }
    #[inline(always)]
    fn add_light(&self, r: &mut [f32; 3], _: &(), light: usize, w: &[f32; 3], g: f32) {
        add_product(r, w, &self.emission[light], g);
    }
    fn planes(&self) -> usize {
        3
    }
    #[inline(always)]
    fn accumulate(&self, film: &mut Film<f32>, pixel: usize, _: &(), r: &[f32; 3]) {
        film.add(0, pixel, r);
    }
    fn frame(&self, film: &Film<f32>, paths: usize, out: [&mut [f32]; 3]) {
        let s = 1.0 / paths.max(1) as f32;
        for (c, o) in out.into_iter().enumerate() {
            for (o, &v) in o.iter_mut().zip(film.plane(c)) {
                *o = v * s;
            }
        }
    }
}

/// How a surface's reflectance is known to a random-wavelength method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RandomMaterial {
    /// A measured reflectance: row `usize` of [`Random::spectra`], read at the wavelength's
    /// 1 nm cell.
    Measured(usize),
    /// Jakob-Hanika's sigmoid of a quadratic, coefficients fitted at load to the surface's
    /// sRGB under D65 (for `x = (λ − 360 nm) / 470 nm`), evaluated at each wavelength.
    Sigmoid([f32; 3]),
}

/// Random wavelengths, K a path, drawn by a [`Sampler`] (pbrt-v4's visible-wavelength density,
/// or hero wavelengths): each path's radiance at its wavelengths becomes XYZ through the 1 nm
/// colour-matching weights at their cells over the density (`f(λ)/p(λ)`, as
/// [`random_wavelengths`](spectral_quadrature_tools::random_wavelengths)), so its expected value
/// is the reference's 1 nm sum. The film sums XYZ (as pbrt-v4's film sums each path's colour);
/// its frame is their mean in linear sRGB.
#[derive(Debug, Clone)]
pub struct Random<const K: usize> {
    /// How the wavelengths are drawn.
    pub sampler: Sampler,
    /// Per surface row: how its reflectance is known.
    pub materials: Vec<RandomMaterial>,
    /// Measured reflectances on the 1 nm grid.
    pub spectra: Vec<Grid>,
    /// Per light: its radiance on the 1 nm grid.
    pub emission: Vec<Grid>,
    /// X, Y, Z weights of each 1 nm cell (the reference's, 1 nm included).
    pub xyz: [Grid; 3],
}

/// One random path's wavelengths.
#[derive(Debug, Clone, Copy)]
pub struct Wavelengths<const K: usize> {
    /// Each wavelength's 1 nm cell on the reference's grid ([`GRID_LEN`]: outside it).
    pub cell: [u16; K],
    /// Jakob-Hanika's coordinate `(λ − 360) / 470`.
    pub x: [f32; K],
    /// `1 / (K p(λ))`.
    pub inv_kpdf: [f32; K],
}

/// Jakob-Hanika's sigmoid, in f32 as pbrt-v4 evaluates it.
#[inline(always)]
pub fn sigmoid(z: f32) -> f32 {
    if z.is_infinite() {
        return if z > 0.0 { 1.0 } else { 0.0 };
    }
    0.5 + z / (2.0 * (1.0 + z * z).sqrt())
}

impl<const K: usize> Carrier<K> for Random<K> {
    type Path = Wavelengths<K>;
    type Radiance = [f32; K];
    type Sum = f32;

    #[inline(always)]
    fn start(&self, rng: &mut Pcg32) -> Wavelengths<K> {
        let mut w = Wavelengths {
            cell: [GRID_LEN as u16; K],
            x: [0.0; K],
            inv_kpdf: [0.0; K],
        };
        // One random number stratifies all K (pbrt-v4's `u + i/K`; hero's even spacing).
        let u = rng.f32();
        for i in 0..K {
            let mut v = u + i as f32 / K as f32;
            if v >= 1.0 {
                v -= 1.0;
            }
            let l = self.sampler.wavelength_f32(v);
            let p = self.sampler.pdf_f32(l);
            let cell = (l - (GRID_NM[0] as f32 - 0.5)).floor();
            if p > 0.0 && (0.0..GRID_LEN as f32).contains(&cell) {
                w.cell[i] = cell as u16;
                w.inv_kpdf[i] = 1.0 / (K as f32 * p);
            }
            w.x[i] = (l - 360.0) / 470.0;
        }
        w
    }
    #[inline(always)]
    fn reflectance(&self, p: &Wavelengths<K>, s: Surface) -> [f32; K] {
        let mut o = [0.0; K];
        match self.materials[s.index()] {
            RandomMaterial::Measured(row) => {
                let t = &self.spectra[row];
                for (o, &cell) in o.iter_mut().zip(&p.cell) {
                    *o = t[cell as usize];
                }
            }
            RandomMaterial::Sigmoid(c) => {
                for (o, &x) in o.iter_mut().zip(&p.x) {
                    *o = sigmoid((c[0] * x + c[1]) * x + c[2]);
                }
            }
        }
        o
    }
    #[inline(always)]
    fn no_radiance(&self) -> [f32; K] {
        [0.0; K]
    }
    #[inline(always)]
    fn add_light(&self, r: &mut [f32; K], p: &Wavelengths<K>, light: usize, w: &[f32; K], g: f32) {
        let e = &self.emission[light];
        for ((r, &w), &cell) in r.iter_mut().zip(w).zip(&p.cell) {
            *r += w * e[cell as usize] * g;
        }
    }
    fn planes(&self) -> usize {
        3
    }
    #[inline(always)]
    fn accumulate(&self, film: &mut Film<f32>, pixel: usize, p: &Wavelengths<K>, r: &[f32; K]) {
        let mut xyz = [0.0f32; 3];
        for ((&r, &inv), &cell) in r.iter().zip(&p.inv_kpdf).zip(&p.cell) {
            let v = r * inv;
            let cell = cell as usize;
            for (c, s) in xyz.iter_mut().enumerate() {
                *s += v * self.xyz[c][cell];
            }
        }
        film.add(0, pixel, &xyz);
    }
    fn frame(&self, film: &Film<f32>, paths: usize, out: [&mut [f32]; 3]) {
        let m = frame_display().xyz_to_rgb();
        matrix_planes(&m, [0, 1, 2].map(|c| film.plane(c)), paths, out);
    }
}

/// A folded set, N nodes, the one light of the scene folded into its weights: a light emits 1
/// at every node. The film holds N planes of node values; its frame is the runtime's
/// [`FoldedSet::linear_rgb_planar`] over the whole film (the set is linear: the sums' colour
/// over the paths is the mean's).
#[derive(Debug, Clone)]
pub struct Folded<const N: usize> {
    /// Per surface row: its reflectance at the nodes.
    pub table: Vec<[f32; N]>,
    /// The set, its weights in the reference's units.
    pub set: FoldedSet<N>,
}

impl<const N: usize> Carrier<N> for Folded<N> {
    type Path = ();
    type Radiance = [f32; N];
    type Sum = f32;

    #[inline(always)]
    fn start(&self, _: &mut Pcg32) {}
    #[inline(always)]
    fn reflectance(&self, _: &(), s: Surface) -> [f32; N] {
        self.table[s.index()]
    }
    #[inline(always)]
    fn no_radiance(&self) -> [f32; N] {
        [0.0; N]
    }
    #[inline(always)]
    fn add_light(&self, r: &mut [f32; N], _: &(), _: usize, w: &[f32; N], g: f32) {
        add_scaled(r, w, g);
    }
    fn planes(&self) -> usize {
        N
    }
    #[inline(always)]
    fn accumulate(&self, film: &mut Film<f32>, pixel: usize, _: &(), r: &[f32; N]) {
        film.add(0, pixel, r);
    }
    fn frame(&self, film: &Film<f32>, paths: usize, out: [&mut [f32]; 3]) {
        let [r, g, b] = out;
        // The planes and outputs have the film's length: no length error can arise.
        let _ = self.set.linear_rgb_planar(
            std::array::from_fn(|i| film.plane(i)),
            [&mut *r, &mut *g, &mut *b],
        );
        scale_planes([r, g, b], 1.0 / paths.max(1) as f32);
    }
}

/// A light group: N shared nodes, one accumulator of node values per light (the light itself
/// left out: it is in that light's weights). The film holds N planes per light; its frame is
/// the runtime's [`LightGroupSet::linear_rgb_planar`], which sums the lights' linear RGB.
#[derive(Debug, Clone)]
pub struct Group<const N: usize, const L: usize> {
    /// Per surface row: its reflectance at the nodes.
    pub table: Vec<[f32; N]>,
    /// The group, each light's weights in the reference's units.
    pub set: LightGroupSet<N, L>,
}

impl<const N: usize, const L: usize> Carrier<N> for Group<N, L> {
    type Path = ();
    type Radiance = [[f32; N]; L];
    type Sum = f32;

    #[inline(always)]
    fn start(&self, _: &mut Pcg32) {}
    #[inline(always)]
    fn reflectance(&self, _: &(), s: Surface) -> [f32; N] {
        self.table[s.index()]
    }
    #[inline(always)]
    fn no_radiance(&self) -> [[f32; N]; L] {
        [[0.0; N]; L]
    }
    #[inline(always)]
    fn add_light(&self, r: &mut [[f32; N]; L], _: &(), light: usize, w: &[f32; N], g: f32) {
        add_scaled(&mut r[light], w, g);
    }
    fn planes(&self) -> usize {
        N * L
    }
    #[inline(always)]
    fn accumulate(&self, film: &mut Film<f32>, pixel: usize, _: &(), r: &[[f32; N]; L]) {
        for (l, r) in r.iter().enumerate() {
            film.add(l * N, pixel, r);
        }
    }
    fn frame(&self, film: &Film<f32>, paths: usize, out: [&mut [f32]; 3]) {
        let [r, g, b] = out;
        // The planes and outputs have the film's length: no length error can arise.
        let _ = self.set.linear_rgb_planar(
            std::array::from_fn(|l| std::array::from_fn(|i| film.plane(l * N + i))),
            [&mut *r, &mut *g, &mut *b],
        );
        scale_planes([r, g, b], 1.0 / paths.max(1) as f32);
    }
}

/// The reference: every nm of 400-700 through the same paths, the measured reflectances (the
/// texture's patches too), each light's spectrum, and the 1 nm colour-matching weights. Its film
/// sums every nm in f64 (tens of thousands of paths a pixel); its frame integrates them in f64.
#[derive(Debug, Clone)]
pub struct Reference {
    /// Per surface row: its row of `spectra`.
    pub rows: Vec<u16>,
    /// Measured reflectances, every nm (the last lanes 0).
    pub spectra: Vec<[f32; REFERENCE_LANES]>,
    /// Per light: its radiance every nm.
    pub emission: Vec<[f32; REFERENCE_LANES]>,
    /// X, Y, Z weights every nm (1 nm included).
    pub xyz: [[f64; REFERENCE_LANES]; 3],
}

impl Carrier<REFERENCE_LANES> for Reference {
    type Path = ();
    type Radiance = [f32; REFERENCE_LANES];
    type Sum = f64;

    #[inline(always)]
    fn start(&self, _: &mut Pcg32) {}
    #[inline(always)]
    fn reflectance(&self, _: &(), s: Surface) -> [f32; REFERENCE_LANES] {
        self.spectra[self.rows[s.index()] as usize]
    }
    #[inline(always)]
    fn no_radiance(&self) -> [f32; REFERENCE_LANES] {
        [0.0; REFERENCE_LANES]
    }
    #[inline(always)]
    fn add_light(
        &self,
        r: &mut [f32; REFERENCE_LANES],
        _: &(),
        light: usize,
        w: &[f32; REFERENCE_LANES],
        g: f32,
    ) {
        add_product(r, w, &self.emission[light], g);
    }
    fn planes(&self) -> usize {
        GRID_LEN
    }
    #[inline(always)]
    fn accumulate(&self, film: &mut Film<f64>, pixel: usize, _: &(), r: &[f32; REFERENCE_LANES]) {
        let r: &[f32; GRID_LEN] = r[..GRID_LEN].try_into().unwrap_or(&[0.0; GRID_LEN]);
        film.add(0, pixel, r);
    }
    fn frame(&self, film: &Film<f64>, paths: usize, out: [&mut [f32]; 3]) {
        let n = paths.max(1) as f64;
        let mut xyz = vec![[0.0f64; 3]; film.pixels()];
        for j in 0..GRID_LEN {
            let w = [0, 1, 2].map(|c| self.xyz[c][j] / n);
            for (o, &v) in xyz.iter_mut().zip(film.plane(j)) {
                for c in 0..3 {
                    o[c] += w[c] * v;
                }
            }
        }
        let m = frame_display().xyz_to_rgb().map(|row| row.map(f64::from));
        let [r, g, b] = out;
        for (k, v) in xyz.iter().enumerate() {
            let o = [0, 1, 2].map(|c| m[c][0] * v[0] + m[c][1] * v[1] + m[c][2] * v[2]);
            (r[k], g[k], b[k]) = (o[0] as f32, o[1] as f32, o[2] as f32);
        }
    }
}
