//! The render scenes: a TOML file per scene and light (`examples/render/*.toml`), read into the
//! box's geometry, its lights and its materials, with what each method may see of them.
//!
//! ```toml
//! scene = "c"                       # the scene's letter, a column of the CSV
//! light = "F11"                     # the lighting's label, a column of the CSV
//! description = "..."               # one line, for the docs and the plot's title
//! paints = "srgb"                   # "measured" (the methods see the paints' reflectances) or
//!                                   # "srgb" (they see each paint's sRGB under D65, `[[paint]]`)
//!
//! [[paint]]                         # only with paints = "srgb": the colour a material holds
//! name = "white"
//! srgb = [0.745, 0.744, 0.724]      # sRGB-encoded, white-balanced under D65
//!
//! [[lights]]
//! spectrum = "F11"                  # "box" (data/cornell_box_light.csv) or a CIE illuminant
//! quad = "light"                    # the geometry's lamp, or four corners in mm:
//! # corners = [[x, y, z], ...]      # a second emitter, facing the room's centre
//! power = 0.5                       # luminous power against the first light's (default 1)
//!
//! [texture]                         # optional: an sRGB PNG on the back wall
//! image = "colorchecker.png"        # relative to the scene file
//! reflectances = "data/reflectance_colorchecker_ohta.csv"   # what its patches are made of
//! patches = [6, 4]                  # columns × rows of patches, one reflectance each
//! rect_mm = [450.0, 150.0, 106.0, 380.0]  # image left x, bottom y, right x, top y on the wall
//! ```
//!
//! Every spectrum is taken over 400-700 nm, the lights as 0 outside it ([`crate::cornell::window`]),
//! as the Cornell tool does: the paints are measured only there.

use std::path::{Path, PathBuf};

use serde::Deserialize;
use spectral_quadrature_generator::Derivation;
use spectral_quadrature_spectra::{DataError, Spectra};
use toml::Spanned;

use crate::cornell::{self, BoxData, Light};
use crate::Error;
use spectral_quadrature_tools as tools;

/// A light of a scene, as every method receives it: its spectrum (windowed to 400-700 nm, in
/// the scene's units: the first light as its data file gives it, the others scaled to their
/// `power`) and where it is.
#[derive(Debug, Clone)]
pub struct SceneLight {
    /// `box`, `F11`, `LED_B2`, ….
    pub name: String,
    /// The spectral radiance, every 1 nm over 400-700 nm and 0 outside.
    pub curve: spectral_quadrature_spectra::Curve,
    /// The emitting parallelogram: a corner and the two edges from it, mm.
    pub corner: [f64; 3],
    /// The edges from `corner`.
    pub edges: [[f64; 3]; 2],
    /// The unit normal it emits along (into the room).
    pub normal: [f64; 3],
}

impl SceneLight {
    /// Its area, mm².
    pub fn area(&self) -> f64 {
        let c = cross(self.edges[0], self.edges[1]);
        (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt()
    }
}

/// The sRGB texture on the back wall and what it is made of.
#[derive(Debug, Clone)]
pub struct Texture {
    /// The PNG's path.
    pub image: PathBuf,
    /// Width, texels.
    pub width: usize,
    /// Height, texels.
    pub height: usize,
    /// Each texel's linear sRGB (white-balanced under D65), row by row from the top: what the
    /// methods see.
    pub linear: Vec<[f64; 3]>,
    /// Each texel's patch: an index into `reflectances`, what the reference sees.
    pub patch: Vec<u16>,
    /// The patches' measured reflectances (400-700 nm).
    pub reflectances: Vec<spectral_quadrature_spectra::Curve>,
    /// The image's left edge's x, its bottom's y, its right edge's x, its top's y, mm on the
    /// back wall (the camera looks along +z, so the image's left is the larger x).
    pub rect_mm: [f64; 4],
}

/// A scene: the box, its lights, its materials and what the methods see of them.
#[derive(Debug, Clone)]
pub struct Scene {
    /// The file it came from.
    pub file: PathBuf,
    /// The scene's letter (`a`, `b`, `c`).
    pub scene: String,
    /// The lighting's label (`box`, `box+F11`, `F11`, …).
    pub light: String,
    /// One line.
    pub description: String,
    /// The box's data: geometry, paints (measured), the lamp.
    pub data: BoxData,
    /// The lights, the first the reference for `power`.
    pub lights: Vec<SceneLight>,
    /// `Some`: the methods see the paints only as these linear sRGB colours (white-balanced
    /// under D65; white, red, green); `None`: they see the measured reflectances.
    pub paint_srgb: Option<[[f64; 3]; 3]>,
    /// The texture on the back wall, if any.
    pub texture: Option<Texture>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    scene: String,
    light: String,
    description: String,
    paints: Spanned<String>,
    #[serde(default)]
    paint: Vec<RawPaint>,
    lights: Vec<RawLight>,
    texture: Option<RawTexture>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPaint {
    name: Spanned<String>,
    srgb: [f64; 3],
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLight {
    spectrum: Spanned<String>,
    quad: Option<Spanned<String>>,
    corners: Option<Spanned<[[f64; 3]; 4]>>,
    power: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTexture {
    image: Spanned<String>,
    reflectances: Spanned<String>,
    patches: Spanned<[usize; 2]>,
    rect_mm: [f64; 4],
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The 1-based line of byte `offset` in `text`.
fn line_of(text: &str, offset: usize) -> u64 {
    text[..offset.min(text.len())].matches('\n').count() as u64 + 1
}

/// The sRGB transfer function's inverse: an encoded value in [0, 1] to linear.
pub fn srgb_decode(v: f64) -> f64 {
    if v <= 0.040_45 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// The sRGB transfer function: linear to encoded, clamped to [0, 1].
pub fn srgb_encode(v: f64) -> f64 {
    let v = v.clamp(0.0, 1.0);
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// The room's centre, mm: the lights' and the walls' normals point toward it.
const ROOM_CENTRE: [f64; 3] = [278.0, 274.4, 279.6];

impl Scene {
    /// Reads a scene file. `d` gives the data folder and the spectral range the lights are read
    /// on. Errors name the file and the line.
    pub fn read(path: &Path, d: &Derivation) -> Result<Scene, Error> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| DataError {
            file: file.clone(),
            line: 0,
            message: format!("cannot read: {e}"),
        })?;
        let bad = |offset: usize, message: String| -> Error {
            DataError {
                file: file.clone(),
                line: line_of(&text, offset),
                message,
            }
            .into()
        };
        let raw: RawScene = toml::from_str(&text).map_err(|e| DataError {
            file: file.clone(),
            line: e.span().map_or(0, |s| line_of(&text, s.start)),
            message: e.message().to_string(),
        })?;
        let data = cornell::read_data(Path::new(tools::DATA_DIR))?;
        let paint_names = ["white", "red", "green"];
        let paint_srgb = match raw.paints.get_ref().as_str() {
            "measured" => {
                if let Some(p) = raw.paint.first() {
                    return Err(bad(
                        p.name.span().start,
                        "[[paint]] colours are for paints = \"srgb\"".into(),
                    ));
                }
                None
            }
            "srgb" => {
                let mut out = [[f64::NAN; 3]; 3];
                for p in &raw.paint {
                    let k = paint_names
                        .iter()
                        .position(|n| n == p.name.get_ref())
                        .ok_or_else(|| {
                            bad(
                                p.name.span().start,
                                format!(
                                    "unknown paint {}: the box's are white, red and green",
                                    p.name.get_ref()
                                ),
                            )
                        })?;
                    if p.srgb.iter().any(|v| !(0.0..=1.0).contains(v)) {
                        return Err(bad(
                            p.name.span().start,
                            format!("paint {}: sRGB values lie in [0, 1]", p.name.get_ref()),
                        ));
                    }
                    out[k] = p.srgb.map(srgb_decode);
                }
                if let Some(k) = (0..3).find(|&k| out[k][0].is_nan()) {
                    return Err(bad(
                        raw.paints.span().start,
                        format!(
                            "paints = \"srgb\" needs a [[paint]] named {}",
                            paint_names[k]
                        ),
                    ));
                }
                Some(out)
            }
            other => {
                return Err(bad(
                    raw.paints.span().start,
                    format!("paints is \"measured\" or \"srgb\", not \"{other}\""),
                ))
            }
        };
        if raw.lights.is_empty() {
            return Err(bad(0, "a scene needs at least one [[lights]]".into()));
        }
        let mut lights: Vec<SceneLight> = Vec::new();
        let mut first_flux = None;
        for l in &raw.lights {
            let name = l.spectrum.get_ref().clone();
            let which = Light::from_name(&name);
            let raw_curve = match which {
                Some(w) => cornell::light_curve(&data, d, w)?,
                None => {
                    let c = spectral_quadrature_spectra::builtin_illuminant(
                        &d.settings.data_dir,
                        &name,
                        d.settings.range_nm,
                    )
                    .map_err(|e| bad(l.spectrum.span().start, e.to_string()))?;
                    let mut w = cornell::window(&c);
                    w.name = name.clone();
                    w
                }
            };
            let corners: [[f64; 3]; 4] = match (&l.quad, &l.corners) {
                (Some(q), None) if q.get_ref() == "light" => data
                    .quads
                    .iter()
                    .find(|q| q.material == cornell::geometry::Material::Light)
                    .map(|q| q.corners)
                    .ok_or_else(|| bad(q.span().start, "the geometry has no light".into()))?,
                (Some(q), None) => {
                    return Err(bad(
                        q.span().start,
                        format!(
                            "quad = \"light\" (the geometry's lamp), not \"{}\"",
                            q.get_ref()
                        ),
                    ))
                }
                (None, Some(c)) => *c.get_ref(),
                _ => {
                    return Err(bad(
                        l.spectrum.span().start,
                        "a light has either quad = \"light\" or corners = [...]".into(),
                    ))
                }
            };
            let e1 = sub(corners[1], corners[0]);
            let e2 = sub(corners[3], corners[0]);
            // A parallelogram: the fourth corner is the first plus both edges.
            let far = [0, 1, 2].map(|k| corners[0][k] + e1[k] + e2[k]);
            if (0..3).any(|k| (far[k] - corners[2][k]).abs() > 1e-6 * (1.0 + far[k].abs())) {
                return Err(bad(
                    l.spectrum.span().start,
                    "a light's four corners must make a parallelogram (corner 3 = corner 2 + corner 4 - corner 1)".into(),
                ));
            }
            let mut n = cross(e1, e2);
            let len = dot(n, n).sqrt();
            if len <= 0.0 {
                return Err(bad(l.spectrum.span().start, "a light has no area".into()));
            }
            n = n.map(|v| v / len);
            if dot(n, sub(ROOM_CENTRE, corners[0])) < 0.0 {
                n = n.map(|v| -v);
            }
            let mut light = SceneLight {
                name,
                curve: raw_curve,
                corner: corners[0],
                edges: [e1, e2],
                normal: n,
            };
            // Luminous power ∝ Y of the radiance × area (a Lambertian emitter's flux is π L A).
            let y: f64 = crate::cornell::methods::xyz_1nm(d, |nm| light.curve.at(nm))?[1];
            let flux = y * light.area();
            match first_flux {
                None => {
                    if let Some(p) = &l.power {
                        if (*p.get_ref() - 1.0).abs() > 0.0 {
                            return Err(bad(
                                p.span().start,
                                "the first light sets the scale: its power is 1".into(),
                            ));
                        }
                    }
                    first_flux = Some(flux);
                }
                Some(f0) => {
                    let power = l.power.as_ref().map_or(1.0, |p| *p.get_ref());
                    if !(power > 0.0 && power.is_finite()) {
                        return Err(bad(
                            l.power.as_ref().map_or(0, |p| p.span().start),
                            "power is a positive number".into(),
                        ));
                    }
                    let s = power * f0 / flux;
                    for v in &mut light.curve.values {
                        *v *= s;
                    }
                }
            }
            lights.push(light);
        }
        let texture = match &raw.texture {
            None => None,
            Some(t) => Some(read_texture(path, &text, t, d, &file)?),
        };
        Ok(Scene {
            file: path.to_path_buf(),
            scene: raw.scene,
            light: raw.light,
            description: raw.description,
            data,
            lights,
            paint_srgb,
            texture,
        })
    }
}

/// Reads the PNG (8- or 16-bit RGB, sRGB-encoded) and the reflectances of its patches.
fn read_texture(
    scene_path: &Path,
    text: &str,
    t: &RawTexture,
    d: &Derivation,
    file: &str,
) -> Result<Texture, Error> {
    let bad = |offset: usize, message: String| -> Error {
        DataError {
            file: file.to_string(),
            line: line_of(text, offset),
            message,
        }
        .into()
    };
    let image = scene_path
        .parent()
        .unwrap_or(Path::new("."))
        .join(t.image.get_ref());
    let (width, height, encoded) = read_png(&image).map_err(|m| bad(t.image.span().start, m))?;
    let label = t.reflectances.get_ref();
    let spectra = Spectra::builtin(&d.settings.data_dir, label)
        .map_err(|e| bad(t.reflectances.span().start, e.to_string()))?;
    let reflectances = (0..spectra.len())
        .map(|k| spectra.curve(k, d.settings.range_nm))
        .collect::<Result<Vec<_>, _>>()?;
    let [cols, rows] = *t.patches.get_ref();
    if cols * rows != reflectances.len() || cols == 0 || width % cols != 0 || height % rows != 0 {
        return Err(bad(
            t.patches.span().start,
            format!(
                "{cols} × {rows} patches for {} reflectances on a {width} × {height} image (each patch a whole number of texels)",
                reflectances.len()
            ),
        ));
    }
    let (pw, ph) = (width / cols, height / rows);
    let patch = (0..width * height)
        .map(|k| (((k / width) / ph) * cols + (k % width) / pw) as u16)
        .collect();
    Ok(Texture {
        image,
        width,
        height,
        linear: encoded.iter().map(|c| c.map(srgb_decode)).collect(),
        patch,
        reflectances,
        rect_mm: t.rect_mm,
    })
}

/// An RGB PNG's size and its sRGB-encoded values in [0, 1], 8 or 16 bits a channel.
pub fn read_png(path: &Path) -> Result<(usize, usize, Vec<[f64; 3]>), String> {
    let f = std::fs::File::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let decoder = png::Decoder::new(std::io::BufReader::new(f));
    let mut reader = decoder
        .read_info()
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let mut buf = vec![0; reader.output_buffer_size().unwrap_or(0)];
    let info = reader
        .next_frame(&mut buf)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    if info.color_type != png::ColorType::Rgb {
        return Err(format!(
            "{}: an RGB PNG is needed, not {:?}",
            path.display(),
            info.color_type
        ));
    }
    let (w, h) = (info.width as usize, info.height as usize);
    let px: Vec<[f64; 3]> = match info.bit_depth {
        png::BitDepth::Eight => buf[..w * h * 3]
            .chunks_exact(3)
            .map(|c| [0, 1, 2].map(|k| f64::from(c[k]) / 255.0))
            .collect(),
        png::BitDepth::Sixteen => buf[..w * h * 6]
            .chunks_exact(6)
            .map(|c| {
                [0, 1, 2].map(|k| f64::from(u16::from_be_bytes([c[2 * k], c[2 * k + 1]])) / 65535.0)
            })
            .collect(),
        other => return Err(format!("{}: {other:?} bits a channel", path.display())),
    };
    Ok((w, h, px))
}

/// Writes a 16-bit RGB PNG of sRGB-encoded values in [0, 1].
pub fn write_png16(path: &Path, width: usize, height: usize, px: &[[f64; 3]]) -> Result<(), Error> {
    let err = |e: String| Error::Write {
        path: path.to_path_buf(),
        source: std::io::Error::other(e),
    };
    let file = std::fs::File::create(path).map_err(|e| Error::Write {
        path: path.to_path_buf(),
        source: e,
    })?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), width as u32, height as u32);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Sixteen);
    enc.set_compression(png::Compression::High);
    let mut w = enc.write_header().map_err(|e| err(e.to_string()))?;
    let bytes: Vec<u8> = px
        .iter()
        .flat_map(|c| {
            c.iter()
                .flat_map(|v| ((v.clamp(0.0, 1.0) * 65535.0).round() as u16).to_be_bytes())
        })
        .collect();
    w.write_image_data(&bytes).map_err(|e| err(e.to_string()))?;
    w.finish().map_err(|e| err(e.to_string()))
}
