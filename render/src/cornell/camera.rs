//! The camera of the box's data: at (278, 273, −800) mm looking along +z, up +y, a 35 mm lens on
//! a 25 × 25 mm film. One ray through each pixel's centre; the pixel's radiosity is the
//! bilinear interpolation of the hit surface's patch radiosities between patch centres (clamped
//! at the surface's edges), so every pixel is a fixed linear combination of at most four
//! patches, the same for every method.

use super::geometry::{unit, Material, Mesh, V3};

/// The camera's position, mm.
pub const EYE: V3 = [278.0, 273.0, -800.0];
/// Focal length, mm.
pub const FOCAL_MM: f64 = 35.0;
/// Film width and height, mm.
pub const FILM_MM: f64 = 25.0;

/// What a pixel sees.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Seen {
    /// Nothing of the box.
    Miss,
    /// The light.
    Light,
    /// A painted surface.
    Paint,
}

/// One pixel: what it sees and its patches with their weights (summing to 1).
#[derive(Debug, Clone, PartialEq)]
pub struct Pixel {
    /// What the ray hit.
    pub seen: Seen,
    /// (patch, weight) pairs.
    pub weights: Vec<(usize, f64)>,
}

/// The image: `size × size` pixels, row by row from the top.
#[derive(Debug, Clone, PartialEq)]
pub struct View {
    /// Pixels per side.
    pub size: usize,
    /// The pixels.
    pub pixels: Vec<Pixel>,
}

impl View {
    /// The indices of the pixels that see paint (the pixels every statistic is taken over).
    pub fn painted(&self) -> Vec<usize> {
        (0..self.pixels.len())
            .filter(|&k| self.pixels[k].seen == Seen::Paint)
            .collect()
    }

    /// A per-patch quantity (`values[patch]`) at each pixel, zero where nothing is seen.
    pub fn shade<const C: usize>(&self, values: &[[f64; C]]) -> Vec<[f64; C]> {
        self.pixels
            .iter()
            .map(|p| {
                let mut v = [0.0; C];
                for &(k, w) in &p.weights {
                    for c in 0..C {
                        v[c] += w * values[k][c];
                    }
                }
                v
            })
            .collect()
    }
}

/// Casts one ray per pixel into the mesh.
pub fn view(mesh: &Mesh, size: usize) -> View {
    let half = 0.5 * FILM_MM;
    let pixels = (0..size * size)
        .map(|k| {
            let (px, py) = (k % size, k / size);
            let sx = ((px as f64 + 0.5) / size as f64 * 2.0 - 1.0) * half;
            let sy = (1.0 - (py as f64 + 0.5) / size as f64 * 2.0) * half;
            // Looking along +z with +y up, the image's right is −x.
            let dir = unit([-sx, sy, FOCAL_MM]);
            let mut best: Option<(f64, usize, f64, f64)> = None;
            for (s, surf) in mesh.surfaces.iter().enumerate() {
                if let Some((t, u, v)) = surf.quad.hit(EYE, dir, 1e-6) {
                    if best.is_none_or(|b| t < b.0) {
                        best = Some((t, s, u, v));
                    }
                }
            }
            let Some((_, s, u, v)) = best else {
                return Pixel {
                    seen: Seen::Miss,
                    weights: Vec::new(),
                };
            };
            let surf = &mesh.surfaces[s];
            let seen = if surf.quad.material == Material::Light {
                Seen::Light
            } else {
                Seen::Paint
            };
            let axis = |x: f64, n: usize| {
                let c = (x * n as f64 - 0.5).clamp(0.0, (n - 1) as f64);
                let i0 = (c.floor() as usize).min(n - 1);
                let i1 = (i0 + 1).min(n - 1);
                (i0, i1, c - i0 as f64)
            };
            let (i0, i1, fu) = axis(u, surf.nu);
            let (j0, j1, fv) = axis(v, surf.nv);
            let idx = |i: usize, j: usize| surf.first + j * surf.nu + i;
            let mut weights: Vec<(usize, f64)> = Vec::with_capacity(4);
            for (i, j, w) in [
                (i0, j0, (1.0 - fu) * (1.0 - fv)),
                (i1, j0, fu * (1.0 - fv)),
                (i0, j1, (1.0 - fu) * fv),
                (i1, j1, fu * fv),
            ] {
                if w > 0.0 {
                    match weights.iter_mut().find(|p| p.0 == idx(i, j)) {
                        Some(p) => p.1 += w,
                        None => weights.push((idx(i, j), w)),
                    }
                }
            }
            Pixel { seen, weights }
        })
        .collect();
    View { size, pixels }
}
