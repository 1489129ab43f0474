//! The pictures: XYZ images tone-mapped for display, ΔE00 maps on a fixed colour scale, side by
//! side in one PNG per light (written with the `png` crate).
//!
//! **Display.** One exposure for every method of a light: the reference's brightest painted
//! pixel (a wall, never the light) maps to [`EXPOSURE_LEVEL`] in luminance. The colours are
//! white-balanced to the light (each linear sRGB channel divided by the white's, the white of
//! [`super::methods::white`]), clipped to [0, 1] and sRGB-encoded. The light itself clips to
//! white.
//!
//! **ΔE00 maps.** Each painted pixel's CIEDE2000 against the reference on a fixed scale, 0 (black)
//! to [`DE_SCALE_MAX`] and above (white), through dark blue, magenta, orange and yellow
//! ([`de_colour`]); the light and what misses the box are grey.

use std::path::{Path, PathBuf};

use crate::Error;

/// The luminance the reference's brightest painted pixel is displayed at (linear, before the
/// sRGB encoding).
pub const EXPOSURE_LEVEL: f64 = 0.85;

/// ΔE00 at the top of the maps' colour scale.
pub const DE_SCALE_MAX: f64 = 5.0;

/// An 8-bit sRGB image.
#[derive(Debug, Clone, PartialEq)]
pub struct Rgb8 {
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// Row by row from the top, R, G, B.
    pub data: Vec<u8>,
}

impl Rgb8 {
    /// A `width × height` image of one colour.
    pub fn filled(width: usize, height: usize, c: [u8; 3]) -> Rgb8 {
        Rgb8 {
            width,
            height,
            data: c.repeat(width * height),
        }
    }

    /// Copies `tile` with its top left corner at (x, y).
    pub fn paste(&mut self, tile: &Rgb8, x: usize, y: usize) {
        for row in 0..tile.height {
            let dst = ((y + row) * self.width + x) * 3;
            let src = row * tile.width * 3;
            self.data[dst..dst + tile.width * 3]
                .copy_from_slice(&tile.data[src..src + tile.width * 3]);
        }
    }

    /// Writes the image as an 8-bit RGB PNG.
    pub fn write_png(&self, path: &Path) -> Result<PathBuf, Error> {
        let write_err = |e: std::io::Error| Error::Write {
            path: path.to_path_buf(),
            source: e,
        };
        let file = std::fs::File::create(path).map_err(write_err)?;
        let mut enc = png::Encoder::new(
            std::io::BufWriter::new(file),
            self.width as u32,
            self.height as u32,
        );
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_compression(png::Compression::High);
        let png_err = |e: png::EncodingError| Error::Write {
            path: path.to_path_buf(),
            source: std::io::Error::other(e.to_string()),
        };
        let mut w = enc.write_header().map_err(png_err)?;
        w.write_image_data(&self.data).map_err(png_err)?;
        w.finish().map_err(png_err)?;
        Ok(path.to_path_buf())
    }
}

/// The sRGB transfer function, linear [0, 1] to 8 bits.
pub fn encode_srgb(v: f64) -> u8 {
    let v = v.clamp(0.0, 1.0);
    let e = if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    };
    (e * 255.0).round() as u8
}

/// The display image of XYZ pixels: exposure so that `white`'s luminance maps to
/// [`EXPOSURE_LEVEL`], white-balanced to `white` in linear sRGB (`xyz_to_rgb`), sRGB-encoded.
pub fn tone_map(
    xyz: &[[f64; 3]],
    size: usize,
    white: [f64; 3],
    xyz_to_rgb: &[[f64; 3]; 3],
) -> Rgb8 {
    let to_rgb =
        |v: [f64; 3]| [0, 1, 2].map(|c| (0..3).map(|k| xyz_to_rgb[c][k] * v[k]).sum::<f64>());
    let w = to_rgb(white);
    let mut data = Vec::with_capacity(size * size * 3);
    for p in xyz {
        let rgb = to_rgb(*p);
        for c in 0..3 {
            data.push(encode_srgb(rgb[c] / w[c] * EXPOSURE_LEVEL));
        }
    }
    Rgb8 {
        width: size,
        height: size,
        data,
    }
}

/// The colour of a ΔE00 on the maps' scale: 0 black, then dark blue, magenta, orange, yellow at
/// [`DE_SCALE_MAX`], white beyond 1.5 × that.
pub fn de_colour(de: f64) -> [u8; 3] {
    const STOPS: [[f64; 3]; 6] = [
        [0.0, 0.0, 0.0],
        [0.10, 0.05, 0.45],
        [0.65, 0.10, 0.55],
        [0.95, 0.45, 0.15],
        [1.0, 0.95, 0.25],
        [1.0, 1.0, 1.0],
    ];
    // 0..DE_SCALE_MAX over the first five stops, then up to white at 1.5 × DE_SCALE_MAX.
    let x = if de <= DE_SCALE_MAX {
        4.0 * de.max(0.0) / DE_SCALE_MAX
    } else {
        4.0 + ((de - DE_SCALE_MAX) / (0.5 * DE_SCALE_MAX)).min(1.0)
    };
    let i = (x.floor() as usize).min(4);
    let f = x - i as f64;
    [0, 1, 2].map(|c| {
        let v = STOPS[i][c] + f * (STOPS[i + 1][c] - STOPS[i][c]);
        (v * 255.0).round() as u8
    })
}

/// The ΔE00 map: `de[k]` at pixel `painted[k]`, grey elsewhere.
pub fn de_map(de: &[f64], painted: &[usize], size: usize) -> Rgb8 {
    let mut img = Rgb8::filled(size, size, [96, 96, 96]);
    for (&k, &v) in painted.iter().zip(de) {
        img.data[k * 3..k * 3 + 3].copy_from_slice(&de_colour(v));
    }
    img
}

/// The colour scale as a strip `width × height`, 0 at the left to 1.5 × [`DE_SCALE_MAX`] at the
/// right, with black ticks at every whole ΔE00 up to the maximum.
pub fn scale_strip(width: usize, height: usize) -> Rgb8 {
    let mut img = Rgb8::filled(width, height, [0, 0, 0]);
    let top = 1.5 * DE_SCALE_MAX;
    for x in 0..width {
        let de = (x as f64 + 0.5) / width as f64 * top;
        let c = de_colour(de);
        let tick =
            (0..=(top as usize)).any(|t| ((t as f64 / top) * width as f64 - x as f64).abs() < 0.5);
        for y in 0..height {
            let k = (y * width + x) * 3;
            let c = if tick && y >= height * 2 / 3 {
                [128, 128, 128]
            } else {
                c
            };
            img.data[k..k + 3].copy_from_slice(&c);
        }
    }
    img
}

/// Tiles side by side, in rows: `rows[r][c]` at column c of row r, `gap` pixels apart on a dark
/// background.
pub fn grid(rows: &[Vec<Rgb8>], gap: usize) -> Rgb8 {
    let tw = rows.iter().flatten().map(|t| t.width).max().unwrap_or(0);
    let th = rows.iter().flatten().map(|t| t.height).max().unwrap_or(0);
    let cols = rows.iter().map(Vec::len).max().unwrap_or(0);
    let width = cols * tw + (cols + 1) * gap;
    let height = rows.len() * th + (rows.len() + 1) * gap;
    let mut img = Rgb8::filled(width, height, [24, 24, 24]);
    for (r, row) in rows.iter().enumerate() {
        for (c, t) in row.iter().enumerate() {
            img.paste(t, gap + c * (tw + gap), gap + r * (th + gap));
        }
    }
    img
}

/// The height of one line of [`labelled`]'s text, pixels: the 8 × 8 glyph and a pixel of
/// space above and below.
pub const LABEL_LINE: usize = 10;

/// `text` broken into lines of at most `chars` characters, at spaces where it can be.
fn wrap(text: &str, chars: usize) -> Vec<String> {
    let chars = chars.max(1);
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for word in text.split(' ') {
        let mut word: Vec<char> = word.chars().collect();
        while word.len() > chars {
            if !line.is_empty() {
                lines.push(std::mem::take(&mut line));
            }
            lines.push(word.drain(..chars).collect());
        }
        let word: String = word.into_iter().collect();
        let len = line.chars().count();
        if len > 0 && len + 1 + word.chars().count() > chars {
            lines.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(&word);
    }
    if !line.is_empty() {
        lines.push(line);
    }
    lines
}

/// Draws `text` at (x, y) (its top left) in the 8 × 8 bitmap font of the `font8x8` crate
/// (ASCII; other characters as `?`, except `×` as `x`), in `colour`, clipped to the image.
pub fn draw_text(img: &mut Rgb8, text: &str, x: usize, y: usize, colour: [u8; 3]) {
    for (i, ch) in text.chars().enumerate() {
        let ch = if ch == '×' { 'x' } else { ch };
        let glyph = if ch.is_ascii() {
            font8x8::legacy::BASIC_LEGACY[ch as usize]
        } else {
            font8x8::legacy::BASIC_LEGACY[b'?' as usize]
        };
        for (row, bits) in glyph.iter().enumerate() {
            for col in 0..8 {
                if bits & (1 << col) == 0 {
                    continue;
                }
                let (px, py) = (x + 8 * i + col, y + row);
                if px < img.width && py < img.height {
                    let k = (py * img.width + px) * 3;
                    img.data[k..k + 3].copy_from_slice(&colour);
                }
            }
        }
    }
}

/// The space a label leaves free at its tile's right edge, pixels: with [`grid`]'s gap, what
/// separates one tile's label from the next one's.
pub const LABEL_MARGIN: usize = 8;

/// `tile` with `text` written above it in a strip of `lines` lines (the text wrapped at spaces
/// to the tile's width less [`LABEL_MARGIN`]; what does not fit is cut), light grey on the
/// background of [`grid`].
pub fn labelled(tile: &Rgb8, text: &str, lines: usize) -> Rgb8 {
    let strip = lines * LABEL_LINE;
    let mut img = Rgb8::filled(tile.width, tile.height + strip, [24, 24, 24]);
    let chars = tile.width.saturating_sub(LABEL_MARGIN) / 8;
    for (k, line) in wrap(text, chars).iter().take(lines).enumerate() {
        draw_text(&mut img, line, 0, k * LABEL_LINE + 1, [230, 230, 230]);
    }
    img.paste(tile, 0, strip);
    img
}
