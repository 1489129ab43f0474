//! Images judged against the reference: the pixels that see the scene, the white, CIEDE2000 per
//! pixel, the reference's own error from two seeds, and the reference's cache file.

use std::path::Path;

use spectral_quadrature_math::{delta_e2000, lab_from_xyz};
use spectral_quadrature_spectra::DataError;

use super::scene::Scene;
use super::transport::Geometry;
use crate::Error;
use spectral_quadrature_tools::upsampling::mean_p95;

/// The pixels whose camera ray meets a surface (not a light, not the outside): every
/// statistic is taken over them.
pub fn seen(g: &Geometry) -> Vec<usize> {
    (0..g.size * g.size).filter(|&k| g.sees_scene(k)).collect()
}

/// The white images are judged with: the chromaticity of the scene's light (several lights:
/// their XYZ summed, each times its area, so weighted by its luminous power), at the luminance
/// of the reference's brightest seen pixel, which then has L* = 100.
pub fn white(
    d: &spectral_quadrature_generator::Derivation,
    scene: &Scene,
    reference: &[[f64; 3]],
    seen: &[usize],
) -> Result<[f64; 3], Error> {
    let mut xyz = [0.0; 3];
    for l in &scene.lights {
        let v = crate::cornell::methods::xyz_1nm(d, |nm| l.curve.at(nm))?;
        for c in 0..3 {
            xyz[c] += v[c] * l.area();
        }
    }
    let y = seen.iter().map(|&k| reference[k][1]).fold(0.0f64, f64::max);
    Ok(xyz.map(|v| v * y / xyz[1]))
}

/// CIEDE2000 of each seen pixel of `image` against `reference`.
pub fn de00(
    image: &[[f64; 3]],
    reference: &[[f64; 3]],
    seen: &[usize],
    white: [f64; 3],
) -> Vec<f64> {
    seen.iter()
        .map(|&k| {
            delta_e2000(
                lab_from_xyz(reference[k], white),
                lab_from_xyz(image[k], white),
            )
        })
        .collect()
}

/// The mean and 95th percentile of [`de00`].
pub fn stats(
    image: &[[f64; 3]],
    reference: &[[f64; 3]],
    seen: &[usize],
    white: [f64; 3],
) -> (f64, f64) {
    mean_p95(&de00(image, reference, seen, white))
}

/// The reference: the mean of two images from independent seeds, and its own error.
#[derive(Debug, Clone, PartialEq)]
pub struct CachedReference {
    /// Pixels a side.
    pub size: usize,
    /// Paths a pixel in each of the two images.
    pub spp: usize,
    /// The two seeds.
    pub seeds: [u64; 2],
    /// The mean of the two, XYZ per pixel.
    pub xyz: Vec<[f64; 3]>,
    /// Its own error, mean ΔE00 over the seen pixels: half the mean ΔE00 between the two seeds'
    /// images. (Two independent estimates' errors e₁ and e₂ are alike in size and direction-free;
    /// the mean's error is (e₁ + e₂)/2, which has the size of (e₁ − e₂)/2, their difference
    /// halved; CIEDE2000 is locally linear at these sizes.)
    pub own_mean: f64,
    /// Its own error at the 95th percentile, likewise.
    pub own_p95: f64,
    /// Wall seconds for the two images.
    pub seconds: f64,
    /// The scene file's text, which it was rendered for.
    pub scene_text: String,
}

impl CachedReference {
    /// From the two seeds' images.
    pub fn from_pair(
        a: &[[f64; 3]],
        b: &[[f64; 3]],
        seen: &[usize],
        white: [f64; 3],
        meta: (usize, usize, [u64; 2], f64, String),
    ) -> CachedReference {
        let (size, spp, seeds, seconds, scene_text) = meta;
        let (m, p) = stats(a, b, seen, white);
        CachedReference {
            size,
            spp,
            seeds,
            xyz: a
                .iter()
                .zip(b)
                .map(|(x, y)| [0, 1, 2].map(|c| 0.5 * (x[c] + y[c])))
                .collect(),
            own_mean: 0.5 * m,
            own_p95: 0.5 * p,
            seconds,
            scene_text,
        }
    }

    /// The cache file's text: `#` lines (the command that remakes it, size, paths a pixel,
    /// seeds, own error, seconds, the scene file's text), then `x,y,z` per pixel.
    pub fn to_text(&self, command: &str) -> String {
        use std::fmt::Write as _;
        let mut s = format!(
            "# The 1 nm reference of the render tool, remade by: {command}\n# size {}\n# spp {}\n# seeds {} {}\n# own_mean_de00 {:.6}\n# own_p95_de00 {:.6}\n# seconds {:.1}\n",
            self.size, self.spp, self.seeds[0], self.seeds[1], self.own_mean, self.own_p95, self.seconds
        );
        for line in self.scene_text.lines() {
            let _ = writeln!(s, "#| {line}");
        }
        s.push_str("x,y,z\n");
        for v in &self.xyz {
            let _ = writeln!(s, "{:.7e},{:.7e},{:.7e}", v[0], v[1], v[2]);
        }
        s
    }

    /// Reads a cache file; errors name the file and the line.
    pub fn read(path: &Path) -> Result<CachedReference, Error> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| DataError {
            file: file.clone(),
            line: 0,
            message: format!("cannot read: {e}"),
        })?;
        let bad = |line: usize, message: &str| -> Error {
            DataError {
                file: file.clone(),
                line: line as u64 + 1,
                message: message.to_string(),
            }
            .into()
        };
        let mut r = CachedReference {
            size: 0,
            spp: 0,
            seeds: [0; 2],
            xyz: Vec::new(),
            own_mean: f64::NAN,
            own_p95: f64::NAN,
            seconds: f64::NAN,
            scene_text: String::new(),
        };
        for (i, line) in text.lines().enumerate() {
            if let Some(rest) = line.strip_prefix("#| ") {
                r.scene_text.push_str(rest);
                r.scene_text.push('\n');
                continue;
            }
            if line == "#|" {
                r.scene_text.push('\n');
                continue;
            }
            let f: Vec<&str> = line.split_whitespace().collect();
            let num = |k: usize| -> Result<f64, Error> {
                f.get(k)
                    .and_then(|v| v.parse().ok())
                    .ok_or_else(|| bad(i, "expected a number"))
            };
            match f.as_slice() {
                ["#", "size", ..] => r.size = num(2)? as usize,
                ["#", "spp", ..] => r.spp = num(2)? as usize,
                ["#", "seeds", ..] => r.seeds = [num(2)? as u64, num(3)? as u64],
                ["#", "own_mean_de00", ..] => r.own_mean = num(2)?,
                ["#", "own_p95_de00", ..] => r.own_p95 = num(2)?,
                ["#", "seconds", ..] => r.seconds = num(2)?,
                ["#", ..] | ["x,y,z"] | [] => {}
                _ => {
                    let v: Vec<f64> = line
                        .split(',')
                        .map(|x| x.trim().parse::<f64>())
                        .collect::<Result<_, _>>()
                        .map_err(|_| bad(i, "expected x,y,z"))?;
                    let v: [f64; 3] = v.try_into().map_err(|_| bad(i, "expected x,y,z"))?;
                    r.xyz.push(v);
                }
            }
        }
        if r.size == 0 || r.xyz.len() != r.size * r.size || r.own_mean.is_nan() {
            return Err(bad(
                0,
                &format!(
                    "{} pixels for size {} (or no own error): not a reference file",
                    r.xyz.len(),
                    r.size
                ),
            ));
        }
        Ok(r)
    }
}
