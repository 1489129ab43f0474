//! The spatial part, written once: the box's surfaces, the camera, the paths (next-event
//! estimation to the lights, cosine-weighted bounces, Russian roulette), the per-pixel seeds and
//! the loop over pixels and samples. What a path carries is the [`Carrier`]'s: three RGB
//! channels, K random wavelengths, N node values or every nanometre, so two images at the same
//! samples per pixel differ only spectrally.
//!
//! **Paths.** Each pixel's camera ray goes through the pixel's centre (the Cornell tool's camera,
//! no anti-aliasing). At every surface a path meets it takes one light (uniformly: the choice
//! never looks at a spectrum), one uniform point on it and a shadow ray (next-event estimation),
//! then a cosine-weighted bounce; a light met by a bounce counts only from the camera. From the
//! fourth surface on, the path survives with probability [`SURVIVAL`] (a constant, so no
//! spectral value decides it), and stops after [`MAX_DEPTH`] surfaces. Each step draws the same
//! random numbers whatever happens, from the pixel's own spatial stream ([`Pcg32`], seeded by
//! the seed and the pixel), so every method traces exactly the same paths; a method that draws
//! wavelengths draws them from a second stream of its own.
//!
//! **Vector layout.** A carrier's values are `[f32; M]` arrays with element-wise loops. The loop
//! over pixels is compiled twice: once for the target's baseline, and once with AVX2 enabled
//! (`#[target_feature(enable = "avx2")]`, chosen at run time by CPU detection), so that eight
//! node values are one 256-bit register. The two give the same bits (no fused multiply-add is
//! enabled); `render/tests/render.rs` checks it.

use std::time::Instant;

use super::scene::Scene;
use crate::cornell::camera::{EYE, FILM_MM, FOCAL_MM};
use crate::cornell::geometry::Material;

/// The probability that a path goes on past its third surface.
pub const SURVIVAL: f32 = 0.75;
/// The most surfaces a path meets: with [`SURVIVAL`] the chance to get this far is 0.75^61 ≈
/// 2e-8.
pub const MAX_DEPTH: usize = 64;

/// What a path meets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Surface {
    /// Paint `0..3` (white, red, green).
    Paint(u8),
    /// A texel of the texture, its index row by row from the top.
    Texel(u32),
}

impl Surface {
    /// The index of its row in a carrier's table: the paints first, then the texels.
    #[inline(always)]
    pub fn index(self) -> usize {
        match self {
            Surface::Paint(p) => p as usize,
            Surface::Texel(t) => 3 + t as usize,
        }
    }
}

/// PCG32 (O'Neill's XSH RR, 64-bit state): the per-pixel streams.
#[derive(Debug, Clone, Copy)]
pub struct Pcg32 {
    state: u64,
    inc: u64,
}

impl Pcg32 {
    /// The stream `stream` of `seed`.
    pub fn new(seed: u64, stream: u64) -> Pcg32 {
        let mut rng = Pcg32 {
            state: 0,
            inc: (stream << 1) | 1,
        };
        rng.next_u32();
        rng.state = rng.state.wrapping_add(seed);
        rng.next_u32();
        rng
    }

    /// The next 32 random bits.
    #[inline(always)]
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        xorshifted.rotate_right((old >> 59) as u32)
    }

    /// Uniform in [0, 1), 24 bits.
    #[inline(always)]
    pub fn f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }
}

/// The spatial stream of pixel `k` for `seed`, the same for every method.
pub fn spatial_stream(seed: u64, pixel: usize) -> Pcg32 {
    Pcg32::new(seed, 2 * pixel as u64)
}

/// The spectral stream of pixel `k` for `seed` (wavelengths, for the methods that draw them).
pub fn spectral_stream(seed: u64, pixel: usize) -> Pcg32 {
    Pcg32::new(seed ^ 0x9e37_79b9_7f4a_7c15, 2 * pixel as u64 + 1)
}

/// A value a film sums paths into: `f32` (what a renderer's film holds) or `f64` (the
/// reference's 1 nm sums over tens of thousands of paths).
pub trait FilmValue: Copy + Default + Send + Sync {
    /// `self += v`.
    fn add_f32(&mut self, v: f32);
    /// As f64.
    fn to_f64(self) -> f64;
}

impl FilmValue for f32 {
    #[inline(always)]
    fn add_f32(&mut self, v: f32) {
        *self += v;
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
}

impl FilmValue for f64 {
    #[inline(always)]
    fn add_f32(&mut self, v: f32) {
        *self += f64::from(v);
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self
    }
}

/// A film: the sums of one thread's pixels, plane by plane (structure of arrays, as the
/// runtime's planar path reads them): plane `j` holds value `j` of every pixel.
#[derive(Debug, Clone, PartialEq)]
pub struct Film<T> {
    pixels: usize,
    data: Vec<T>,
}

impl<T: FilmValue> Film<T> {
    /// `planes` planes of `pixels` zeros.
    pub fn new(planes: usize, pixels: usize) -> Film<T> {
        Film {
            pixels,
            data: vec![T::default(); planes * pixels],
        }
    }

    /// The number of pixels.
    pub fn pixels(&self) -> usize {
        self.pixels
    }

    /// Plane `j`.
    pub fn plane(&self, j: usize) -> &[T] {
        &self.data[j * self.pixels..(j + 1) * self.pixels]
    }

    /// Every plane back to zero.
    pub fn clear(&mut self) {
        self.data.fill(T::default());
    }

    /// Adds `v[j]` to pixel `pixel` of plane `first + j`.
    #[inline(always)]
    pub fn add<const M: usize>(&mut self, first: usize, pixel: usize, v: &[f32; M]) {
        for (j, &x) in v.iter().enumerate() {
            self.data[(first + j) * self.pixels + pixel].add_f32(x);
        }
    }
}

/// What a path carries, and how a film of its paths becomes a frame. `M` values a path: the
/// method's channels, wavelengths or nodes.
pub trait Carrier<const M: usize>: Sync {
    /// What one path holds besides its throughput (its wavelengths, for random methods).
    type Path: Copy;
    /// A path's radiance (one accumulator per light for a light group).
    type Radiance: Copy;
    /// What the film sums in.
    type Sum: FilmValue;

    /// A path's start: draws its wavelengths from `spectral` if the method has any to draw.
    fn start(&self, spectral: &mut Pcg32) -> Self::Path;
    /// The reflectance of `surface` at the path's wavelengths (or channels, or nodes).
    fn reflectance(&self, path: &Self::Path, surface: Surface) -> [f32; M];
    /// A radiance of zero.
    fn no_radiance(&self) -> Self::Radiance;
    /// Adds light `light`'s emission, times `weight` (the path's throughput times the
    /// surface's reflectance) and the geometric factor `g`, to `r`.
    fn add_light(
        &self,
        r: &mut Self::Radiance,
        path: &Self::Path,
        light: usize,
        weight: &[f32; M],
        g: f32,
    );
    /// The film's planes: what a pixel's sum holds.
    fn planes(&self) -> usize;
    /// Adds a path's radiance to pixel `pixel` of `film`.
    fn accumulate(
        &self,
        film: &mut Film<Self::Sum>,
        pixel: usize,
        path: &Self::Path,
        r: &Self::Radiance,
    );
    /// The frame a renderer displays: the film's mean over `paths` paths a pixel as linear
    /// sRGB ([`frame_display`]'s), into `out` (R, G and B planes, one value per pixel of the
    /// film). Every method converts its whole film at once, as a renderer converts its
    /// accumulated buffer once per displayed frame.
    fn frame(&self, film: &Film<Self::Sum>, paths: usize, out: [&mut [f32]; 3]);
}

/// The display every method's frame is in: the runtime's sRGB.
pub fn frame_display() -> spectral_quadrature::Display {
    spectral_quadrature::tables::displays::SRGB
}

/// `out *= s`, plane by plane.
#[inline]
pub fn scale_planes(out: [&mut [f32]; 3], s: f32) {
    for p in out {
        for v in p.iter_mut() {
            *v *= s;
        }
    }
}

/// `out = m · xyz / paths` for every pixel: a 3 × 3 matrix over three planes.
pub fn matrix_planes<T: FilmValue>(
    m: &[[f32; 3]; 3],
    xyz: [&[T]; 3],
    paths: usize,
    out: [&mut [f32]; 3],
) {
    let s = 1.0 / paths.max(1) as f32;
    let [r, g, b] = out;
    for (k, ((r, g), b)) in r.iter_mut().zip(g.iter_mut()).zip(b.iter_mut()).enumerate() {
        let v = [0, 1, 2].map(|c| xyz[c][k].to_f64() as f32);
        let o = [0, 1, 2].map(|c| (m[c][0] * v[0] + m[c][1] * v[1] + m[c][2] * v[2]) * s);
        (*r, *g, *b) = (o[0], o[1], o[2]);
    }
}

/// `a ∘ b`.
#[inline(always)]
pub fn mul<const M: usize>(a: &[f32; M], b: &[f32; M]) -> [f32; M] {
    let mut o = [0.0; M];
    for k in 0..M {
        o[k] = a[k] * b[k];
    }
    o
}

/// `acc += a · s`.
#[inline(always)]
pub fn add_scaled<const M: usize>(acc: &mut [f32; M], a: &[f32; M], s: f32) {
    for k in 0..M {
        acc[k] += a[k] * s;
    }
}

/// `acc += a ∘ b · s`.
#[inline(always)]
pub fn add_product<const M: usize>(acc: &mut [f32; M], a: &[f32; M], b: &[f32; M], s: f32) {
    for k in 0..M {
        acc[k] += a[k] * b[k] * s;
    }
}

type V = [f32; 3];

#[inline(always)]
fn v_sub(a: V, b: V) -> V {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
#[inline(always)]
fn v_add(a: V, b: V) -> V {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
#[inline(always)]
fn v_scale(a: V, s: f32) -> V {
    [a[0] * s, a[1] * s, a[2] * s]
}
#[inline(always)]
fn v_dot(a: V, b: V) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
#[inline(always)]
fn v_cross(a: V, b: V) -> V {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn v_unit(a: V) -> V {
    v_scale(a, 1.0 / v_dot(a, a).sqrt())
}
fn f32v(a: [f64; 3]) -> V {
    a.map(|v| v as f32)
}

/// What a quad is.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    Paint(u8),
    /// The back wall: white paint, with the texture where it lies.
    Textured,
    Light(u8),
}

/// A planar convex quad, facing `n`: `n·p = d` on it, and a point is inside when each edge's
/// in-plane normal `m[k]` has `m[k]·p ≥ mo[k]`.
#[derive(Debug, Clone, Copy)]
struct Quad {
    n: V,
    d: f32,
    m: [V; 4],
    mo: [f32; 4],
    kind: Kind,
}

impl Quad {
    fn new(c: [V; 4], n: V, kind: Kind) -> Quad {
        let centre = v_scale(v_add(v_add(c[0], c[1]), v_add(c[2], c[3])), 0.25);
        let mut m = [[0.0; 3]; 4];
        let mut mo = [0.0; 4];
        for k in 0..4 {
            let e = v_sub(c[(k + 1) % 4], c[k]);
            let mut mk = v_unit(v_cross(n, e));
            if v_dot(mk, v_sub(centre, c[k])) < 0.0 {
                mk = v_scale(mk, -1.0);
            }
            m[k] = mk;
            // 1e-3 mm of slack: a ray through an edge shared by two quads meets one of them.
            mo[k] = v_dot(mk, c[k]) - 1e-3;
        }
        Quad {
            n,
            d: v_dot(n, c[0]),
            m,
            mo,
            kind,
        }
    }

    /// The `t` in (`t_min`, `t_max`) at which `o + t·dir` meets the quad's front.
    #[inline(always)]
    fn hit(&self, o: V, dir: V, t_min: f32, t_max: f32) -> Option<f32> {
        let den = v_dot(dir, self.n);
        if den >= -1e-9 {
            return None;
        }
        let t = (self.d - v_dot(self.n, o)) / den;
        if !(t > t_min && t < t_max) {
            return None;
        }
        let p = v_add(o, v_scale(dir, t));
        for k in 0..4 {
            if v_dot(self.m[k], p) < self.mo[k] {
                return None;
            }
        }
        Some(t)
    }
}

/// A box: its faces behind their bounding box.
#[derive(Debug, Clone)]
struct Block {
    lo: V,
    hi: V,
    faces: Vec<Quad>,
}

impl Block {
    /// Whether `o + t·dir` meets the bounding box for some t in (0, t_max).
    #[inline(always)]
    fn meets(&self, o: V, inv: V, t_max: f32) -> bool {
        let (mut t0, mut t1) = (0.0f32, t_max);
        for k in 0..3 {
            let a = (self.lo[k] - o[k]) * inv[k];
            let b = (self.hi[k] - o[k]) * inv[k];
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
        }
        t0 <= t1
    }
}

/// A light as the paths sample it.
#[derive(Debug, Clone, Copy)]
struct Emitter {
    corner: V,
    e1: V,
    e2: V,
    n: V,
    area: f32,
}

/// The texture's place on the back wall.
#[derive(Debug, Clone, Copy)]
struct TexturePlace {
    /// x of the image's left edge, y of its top, mm.
    left_x: f32,
    top_y: f32,
    /// Texels per mm leftward (−x) and downward (−y).
    per_mm: [f32; 2],
    size: [u32; 2],
}

/// The box as the paths see it, in f32.
#[derive(Debug, Clone)]
pub struct Geometry {
    room: Vec<Quad>,
    blocks: Vec<Block>,
    emitters: Vec<Emitter>,
    texture: Option<TexturePlace>,
    /// Pixels a side.
    pub size: usize,
    rays: Vec<V>,
}

/// One surface a ray met.
enum Hit {
    Light(u8),
    Surface(Surface, V, V),
}

impl Geometry {
    /// The scene's box, lights and texture, seen by a `size × size` camera.
    pub fn new(scene: &Scene, size: usize) -> Geometry {
        let mut room = Vec::new();
        let mut blocks: Vec<(String, Block)> = Vec::new();
        for q in &scene.data.quads {
            let c = q.corners.map(f32v);
            let n = f32v(q.normal);
            let kind = match q.material {
                Material::Light => continue,
                Material::White if q.name == "back_wall" && scene.texture.is_some() => {
                    Kind::Textured
                }
                m => Kind::Paint(m.paint_index().unwrap_or(0) as u8),
            };
            let quad = Quad::new(c, n, kind);
            if q.occluder {
                let k = match blocks.iter().position(|b| b.0 == q.name) {
                    Some(k) => k,
                    None => {
                        blocks.push((
                            q.name.clone(),
                            Block {
                                lo: [f32::MAX; 3],
                                hi: [f32::MIN; 3],
                                faces: Vec::new(),
                            },
                        ));
                        blocks.len() - 1
                    }
                };
                let b = &mut blocks[k].1;
                for p in c {
                    for ((lo, hi), v) in b.lo.iter_mut().zip(b.hi.iter_mut()).zip(p) {
                        *lo = lo.min(v - 1e-2);
                        *hi = hi.max(v + 1e-2);
                    }
                }
                b.faces.push(quad);
            } else {
                room.push(quad);
            }
        }
        let mut emitters = Vec::new();
        for (i, l) in scene.lights.iter().enumerate() {
            let c0 = f32v(l.corner);
            let (e1, e2) = (f32v(l.edges[0]), f32v(l.edges[1]));
            let c = [c0, v_add(c0, e1), v_add(v_add(c0, e1), e2), v_add(c0, e2)];
            let n = f32v(l.normal);
            // Lights first, so that a light wins a tie with the wall or ceiling behind it.
            room.insert(i, Quad::new(c, n, Kind::Light(i as u8)));
            emitters.push(Emitter {
                corner: c0,
                e1,
                e2,
                n,
                area: l.area() as f32,
            });
        }
        let texture = scene.texture.as_ref().map(|t| {
            let [lx, by, rx, ty] = t.rect_mm;
            TexturePlace {
                left_x: lx as f32,
                top_y: ty as f32,
                per_mm: [
                    t.width as f32 / (lx - rx) as f32,
                    t.height as f32 / (ty - by) as f32,
                ],
                size: [t.width as u32, t.height as u32],
            }
        });
        let half = 0.5 * FILM_MM;
        let rays = (0..size * size)
            .map(|k| {
                let (px, py) = (k % size, k / size);
                let sx = ((px as f64 + 0.5) / size as f64 * 2.0 - 1.0) * half;
                let sy = (1.0 - (py as f64 + 0.5) / size as f64 * 2.0) * half;
                // Looking along +z with +y up, the image's right is −x (the tool's camera).
                let d = [-sx, sy, FOCAL_MM];
                let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                f32v(d.map(|v| v / l))
            })
            .collect();
        Geometry {
            room,
            blocks: blocks.into_iter().map(|b| b.1).collect(),
            emitters,
            texture,
            size,
            rays,
        }
    }

    /// The number of lights.
    pub fn lights(&self) -> usize {
        self.emitters.len()
    }

    /// The surface at `p` on a quad of `kind`.
    #[inline(always)]
    fn surface(&self, kind: Kind, p: V) -> Surface {
        match (kind, self.texture) {
            (Kind::Textured, Some(t)) => {
                let u = (t.left_x - p[0]) * t.per_mm[0];
                let v = (t.top_y - p[1]) * t.per_mm[1];
                if u >= 0.0 && v >= 0.0 && u < t.size[0] as f32 && v < t.size[1] as f32 {
                    Surface::Texel(v as u32 * t.size[0] + u as u32)
                } else {
                    Surface::Paint(0)
                }
            }
            (Kind::Paint(m), _) => Surface::Paint(m),
            _ => Surface::Paint(0),
        }
    }

    /// The nearest surface `o + t·dir` meets.
    #[inline(always)]
    fn hit(&self, o: V, dir: V) -> Option<(Hit, f32)> {
        const T_MIN: f32 = 1e-3;
        let mut best: Option<(f32, Quad)> = None;
        let mut t_max = f32::INFINITY;
        for q in &self.room {
            if let Some(t) = q.hit(o, dir, T_MIN, t_max) {
                t_max = t;
                best = Some((t, *q));
            }
        }
        let inv = dir.map(|v| 1.0 / v);
        for b in &self.blocks {
            if !b.meets(o, inv, t_max) {
                continue;
            }
            for q in &b.faces {
                if let Some(t) = q.hit(o, dir, T_MIN, t_max) {
                    t_max = t;
                    best = Some((t, *q));
                }
            }
        }
        let (t, q) = best?;
        let p = v_add(o, v_scale(dir, t));
        Some(match q.kind {
            Kind::Light(l) => (Hit::Light(l), t),
            k => (Hit::Surface(self.surface(k, p), p, q.n), t),
        })
    }

    /// Whether nothing lies on the open segment from `x` to `y`, light `l` at `y` (the boxes
    /// and the other lights can block; the room's walls are convex and never do).
    #[inline(always)]
    fn visible(&self, x: V, y: V, light: usize) -> bool {
        let d = v_sub(y, x);
        let inv = d.map(|v| 1.0 / v);
        const EPS: f32 = 1e-5;
        for b in &self.blocks {
            if !b.meets(x, inv, 1.0) {
                continue;
            }
            for q in &b.faces {
                if occludes(q, x, d, EPS) {
                    return false;
                }
            }
        }
        for (i, q) in self.room[..self.emitters.len()].iter().enumerate() {
            if i != light && occludes(q, x, d, EPS) {
                return false;
            }
        }
        true
    }

    /// Whether pixel `k`'s camera ray sees a surface (not a light, not the outside).
    pub fn sees_scene(&self, k: usize) -> bool {
        matches!(
            self.hit(f32v(EYE), self.rays[k]),
            Some((Hit::Surface(..), _))
        )
    }

    /// What pixel `k`'s camera ray meets first: `Some(surface)`, `None` for a light or nothing.
    pub fn first_surface(&self, k: usize) -> Option<Surface> {
        match self.hit(f32v(EYE), self.rays[k]) {
            Some((Hit::Surface(s, ..), _)) => Some(s),
            _ => None,
        }
    }
}

/// Whether `q` (either face) crosses the open segment `x + s·d`, s in (eps, 1 − eps).
#[inline(always)]
fn occludes(q: &Quad, x: V, d: V, eps: f32) -> bool {
    let den = v_dot(d, q.n);
    if den.abs() < 1e-12 {
        return false;
    }
    let s = (q.d - v_dot(q.n, x)) / den;
    if !(s > eps && s < 1.0 - eps) {
        return false;
    }
    let p = v_add(x, v_scale(d, s));
    (0..4).all(|k| v_dot(q.m[k], p) >= q.mo[k])
}

/// One path from the camera through pixel `k`: its radiance, the spatial decisions drawn from
/// `rng`.
#[inline(always)]
fn trace<const M: usize, C: Carrier<M>>(
    g: &Geometry,
    c: &C,
    k: usize,
    path: &C::Path,
    rng: &mut Pcg32,
) -> C::Radiance {
    let mut r = c.no_radiance();
    let mut beta = [1.0f32; M];
    let mut o = f32v(EYE);
    let mut d = g.rays[k];
    let lights = g.emitters.len();
    let p_light = 1.0 / lights as f32;
    for depth in 0..MAX_DEPTH {
        let Some((hit, _)) = g.hit(o, d) else { break };
        let (surface, x, n) = match hit {
            Hit::Light(l) => {
                // Seen from the camera; after a bounce next-event estimation has counted it.
                if depth == 0 {
                    c.add_light(&mut r, path, l as usize, &beta, 1.0);
                }
                break;
            }
            Hit::Surface(s, x, n) => (s, x, n),
        };
        let rho = c.reflectance(path, surface);
        let weight = mul(&beta, &rho);
        // Next-event estimation: one light (uniformly), a uniform point on it.
        let (ul, u1, u2) = (rng.f32(), rng.f32(), rng.f32());
        let l = ((ul * lights as f32) as usize).min(lights - 1);
        let e = &g.emitters[l];
        let y = v_add(e.corner, v_add(v_scale(e.e1, u1), v_scale(e.e2, u2)));
        let to = v_sub(y, x);
        let r2 = v_dot(to, to);
        let inv_len = 1.0 / r2.sqrt();
        let w = v_scale(to, inv_len);
        let (cos_x, cos_l) = (v_dot(w, n), -v_dot(w, e.n));
        if cos_x > 0.0 && cos_l > 0.0 && g.visible(x, y, l) {
            // BRDF ρ/π, the light's solid angle cos_l·A/r², over the choice's probability.
            let geo = cos_x * cos_l / r2 * e.area * std::f32::consts::FRAC_1_PI / p_light;
            c.add_light(&mut r, path, l, &weight, geo);
        }
        // A cosine-weighted bounce: ρ/π · cos over the density cos/π is ρ.
        beta = weight;
        let (u3, u4) = (rng.f32(), rng.f32());
        if depth >= 3 {
            if rng.f32() >= SURVIVAL {
                break;
            }
            for b in &mut beta {
                *b *= 1.0 / SURVIVAL;
            }
        }
        let (rad, phi) = (u3.sqrt(), 2.0 * std::f32::consts::PI * u4);
        let a = if n[0].abs() > 0.9 {
            [0.0, 1.0, 0.0]
        } else {
            [1.0, 0.0, 0.0]
        };
        let tu = v_unit(v_cross(a, n));
        let tv = v_cross(n, tu);
        let z = (1.0 - u3).max(0.0).sqrt();
        o = x;
        d = v_add(
            v_add(v_scale(tu, rad * phi.cos()), v_scale(tv, rad * phi.sin())),
            v_scale(n, z),
        );
    }
    r
}

/// One thread's share of the pixels: their indices, each one's two streams, and their film.
struct Part<T> {
    pixels: Vec<usize>,
    streams: Vec<(Pcg32, Pcg32)>,
    film: Film<T>,
}

/// Sample passes `from + 1 ..= to` over one thread's pixels.
#[inline(always)]
fn passes<const M: usize, C: Carrier<M>>(
    g: &Geometry,
    c: &C,
    part: &mut Part<C::Sum>,
    from: usize,
    to: usize,
) {
    for _ in from..to {
        for (i, &k) in part.pixels.iter().enumerate() {
            let (spatial, spectral) = &mut part.streams[i];
            let path = c.start(spectral);
            let r = trace(g, c, k, &path, spatial);
            c.accumulate(&mut part.film, i, &path, &r);
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn passes_avx2<const M: usize, C: Carrier<M>>(
    g: &Geometry,
    c: &C,
    part: &mut Part<C::Sum>,
    from: usize,
    to: usize,
) {
    passes(g, c, part, from, to)
}

/// Whether this CPU runs the AVX2 instance of the loop.
pub fn has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// How to render.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Options {
    /// The seed of every pixel's streams.
    pub seed: u64,
    /// Threads (each takes every `threads`-th row).
    pub threads: usize,
    /// Allow the AVX2 instance where the CPU has AVX2 (`false`: the baseline instance).
    pub simd: bool,
}

/// An image being rendered, one pass of one path per pixel after another: it can be taken at
/// any number of passes and rendered further, so that several methods can take turns on the
/// machine (their times then see the same load), and started again from nothing with the same
/// paths, so that a short render can be timed several times.
pub trait Progressive {
    /// Renders passes up to `spp` paths a pixel in all; returns the wall seconds it took.
    fn advance(&mut self, spp: usize) -> f64;
    /// The frame so far: XYZ per pixel (zero where nothing is seen) and the wall seconds its
    /// conversion took. The conversion timed is the renderer's: every film into its linear
    /// sRGB frame ([`Carrier::frame`]) and the frame's pixels into place; the frame's XYZ,
    /// which the images are judged in, is computed after, untimed.
    fn image(&mut self) -> (Vec<[f64; 3]>, f64);
    /// Back to no paths: the films cleared, every pixel's streams seeded again (the same
    /// paths follow).
    fn reset(&mut self);
    /// Paths a pixel so far.
    fn spp(&self) -> usize;
    /// Whether the AVX2 instance of the loop runs.
    fn avx2(&self) -> bool;
}

/// A [`Progressive`] image of carrier `C`.
pub struct Progress<'g, const M: usize, C: Carrier<M>> {
    g: &'g Geometry,
    c: C,
    parts: Vec<Part<C::Sum>>,
    /// Each part's frame, R, G and B planes.
    frames: Vec<[Vec<f32>; 3]>,
    /// The frame in pixel order, linear sRGB.
    frame: Vec<[f32; 3]>,
    seed: u64,
    done: usize,
    avx2: bool,
}

impl<'g, const M: usize, C: Carrier<M>> Progress<'g, M, C> {
    /// No paths yet: each pixel's streams seeded, the films empty.
    pub fn new(g: &'g Geometry, c: C, opts: Options) -> Self {
        let n = g.size * g.size;
        let threads = opts.threads.clamp(1, g.size.max(1));
        let parts: Vec<Part<C::Sum>> = (0..threads)
            .map(|t| {
                let pixels: Vec<usize> = (0..n).filter(|k| (k / g.size) % threads == t).collect();
                let streams = pixels
                    .iter()
                    .map(|&k| (spatial_stream(opts.seed, k), spectral_stream(opts.seed, k)))
                    .collect();
                let film = Film::new(c.planes(), pixels.len());
                Part {
                    pixels,
                    streams,
                    film,
                }
            })
            .collect();
        let frames = parts
            .iter()
            .map(|p| [0, 1, 2].map(|_| vec![0.0f32; p.pixels.len()]))
            .collect();
        Progress {
            g,
            c,
            parts,
            frames,
            frame: vec![[0.0; 3]; n],
            seed: opts.seed,
            done: 0,
            avx2: opts.simd && has_avx2(),
        }
    }
}

impl<const M: usize, C: Carrier<M>> Progressive for Progress<'_, M, C> {
    fn advance(&mut self, spp: usize) -> f64 {
        if spp <= self.done {
            return 0.0;
        }
        let (g, c, from, avx2) = (self.g, &self.c, self.done, self.avx2);
        let start = Instant::now();
        std::thread::scope(|s| {
            let handles: Vec<_> = self
                .parts
                .iter_mut()
                .map(|part| {
                    s.spawn(move || {
                        #[cfg(target_arch = "x86_64")]
                        if avx2 {
                            // SAFETY: `avx2` is true only where the CPU reports AVX2
                            // (`has_avx2`).
                            unsafe { passes_avx2(g, c, part, from, spp) };
                            return;
                        }
                        passes(g, c, part, from, spp)
                    })
                })
                .collect();
            for h in handles {
                h.join().unwrap_or_else(|p| std::panic::resume_unwind(p));
            }
        });
        self.done = spp;
        start.elapsed().as_secs_f64()
    }

    fn image(&mut self) -> (Vec<[f64; 3]>, f64) {
        let start = Instant::now();
        for (part, out) in self.parts.iter().zip(self.frames.iter_mut()) {
            let [r, g, b] = out;
            self.c.frame(&part.film, self.done, [r, g, b]);
            for (i, &k) in part.pixels.iter().enumerate() {
                self.frame[k] = [r[i], g[i], b[i]];
            }
        }
        let seconds = start.elapsed().as_secs_f64();
        let m = frame_display().rgb_to_xyz().map(|row| row.map(f64::from));
        let xyz = self
            .frame
            .iter()
            .map(|p| {
                let v = p.map(f64::from);
                [0, 1, 2].map(|c| m[c][0] * v[0] + m[c][1] * v[1] + m[c][2] * v[2])
            })
            .collect();
        (xyz, seconds)
    }

    fn reset(&mut self) {
        for part in &mut self.parts {
            part.film.clear();
            for (s, &k) in part.streams.iter_mut().zip(&part.pixels) {
                *s = (spatial_stream(self.seed, k), spectral_stream(self.seed, k));
            }
        }
        self.done = 0;
    }

    fn spp(&self) -> usize {
        self.done
    }

    fn avx2(&self) -> bool {
        self.avx2
    }
}

/// What [`render`] returns: each level's image and time.
#[derive(Debug, Clone)]
pub struct Rendered {
    /// Samples per pixel at each level, ascending.
    pub spp: Vec<usize>,
    /// Per level: XYZ per pixel (row by row from the top; zero where nothing is seen).
    pub images: Vec<Vec<[f64; 3]>>,
    /// Per level: the wall-clock seconds of the passes and conversions up to that level.
    pub seconds: Vec<f64>,
    /// Paths traced in all.
    pub paths: usize,
    /// Whether the AVX2 instance of the loop ran.
    pub avx2: bool,
}

/// Renders every pixel at each level of `spp` (ascending, each ≥ 1) in one go: a
/// [`Progress`] advanced level by level.
pub fn render<const M: usize, C: Carrier<M>>(
    g: &Geometry,
    c: C,
    spp: &[usize],
    opts: Options,
) -> Rendered {
    run_levels(&mut Progress::new(g, c, opts), spp)
}

/// Advances `p` level by level of `spp`, taking the image at each.
pub fn run_levels(p: &mut dyn Progressive, spp: &[usize]) -> Rendered {
    let mut images = Vec::with_capacity(spp.len());
    let mut seconds = Vec::with_capacity(spp.len());
    let mut total = 0.0;
    for &s in spp {
        total += p.advance(s);
        let (img, t) = p.image();
        total += t;
        images.push(img);
        seconds.push(total);
    }
    Rendered {
        spp: spp.to_vec(),
        images,
        seconds,
        paths: 0,
        avx2: p.avx2(),
    }
    .with_paths()
}

impl Rendered {
    fn with_paths(mut self) -> Rendered {
        let n = self.images.first().map_or(0, Vec::len);
        self.paths = n * self.spp.last().copied().unwrap_or(0);
        self
    }
}
