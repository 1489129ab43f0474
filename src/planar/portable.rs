//! The portable planar loops, and the interleaved sRGB loop built on them: fixed chunks of
//! [`CHUNK`] pixels with the 3×N product written as plain loops over arrays, so that the compiler
//! vectorizes them for the baseline target (SSE2 on x86-64, NEON on aarch64; no `target-cpu`
//! needed), with no branch per pixel. They run wherever no loop of [`simd`](crate::simd) does,
//! and after one for the pixels it leaves.
//!
//! The weights and samples are light by light, `[[f32; N]; 3]` and N planes per light: a
//! folded set is one light, a [`LightGroupSet`](crate::LightGroupSet) L, whose lights'
//! products are added in light order.

#![forbid(unsafe_code)]

use crate::encode::{entry, segment_bits};
use crate::simd::Lights;

/// Pixels per step of the planar loops. A partial last chunk is padded with zeros on the stack.
const CHUNK: usize = 16;

/// One chunk's samples: plane i of light l's `CHUNK` values starting at pixel `start`, or the
/// zero-padded rest of it when fewer remain.
#[inline(always)]
fn gather<const N: usize, const L: usize>(
    samples: &[[&[f32]; N]; L],
    start: usize,
) -> [[[f32; CHUNK]; N]; L] {
    samples.map(|light| {
        light.map(|plane| {
            let mut chunk = [0.0f32; CHUNK];
            let rest = plane.get(start..).unwrap_or(&[]);
            let n = rest.len().min(CHUNK);
            chunk[..n].copy_from_slice(&rest[..n]);
            chunk
        })
    })
}

/// References to one chunk's planes, light by light.
#[inline(always)]
fn refs<const N: usize, const L: usize>(chunk: &[[[f32; CHUNK]; N]; L]) -> [[&[f32; CHUNK]; N]; L] {
    chunk.each_ref().map(|light| light.each_ref())
}

/// `weights · samples` for one chunk, each pixel accumulated in index order from 0.0 in f32,
/// light by light, and the lights added in order: exactly as
/// [`FoldedSet::linear_rgb`](crate::FoldedSet::linear_rgb) (one light) and
/// [`LightGroupSet::linear_rgb`](crate::LightGroupSet::linear_rgb) do, so the results are bit for
/// bit the same.
#[inline(always)]
fn product<const N: usize, const L: usize>(
    weights: &[[[f32; N]; 3]; L],
    samples: [[&[f32; CHUNK]; N]; L],
) -> [[f32; CHUNK]; 3] {
    let mut out = [[0.0f32; CHUNK]; 3];
    // Pixels outermost, so the loop over them vectorizes once the short loops inside unroll.
    for p in 0..CHUNK {
        for (c, o) in out.iter_mut().enumerate() {
            let mut sum = 0.0f32;
            for (l, (light, samples)) in weights.iter().zip(&samples).enumerate() {
                let mut acc = 0.0f32;
                for (w, s) in light[c].iter().zip(samples) {
                    acc += w * s[p];
                }
                sum = if l == 0 { acc } else { sum + acc };
            }
            o[p] = sum;
        }
    }
    out
}

/// As [`product`], but each light's sum starting from its first product instead of 0.0: one
/// addition less per channel and light, and the same result except that an exact zero may be
/// −0.0, which encodes as +0.0 (as in `sse2::encode_srgb8_groups`, the per-pixel function on
/// x86-64).
#[inline(always)]
fn product_for_encoding<const N: usize, const L: usize>(
    weights: &[[[f32; N]; 3]; L],
    samples: [[&[f32; CHUNK]; N]; L],
) -> [[f32; CHUNK]; 3] {
    let mut out = [[0.0f32; CHUNK]; 3];
    if N == 0 {
        return out;
    }
    for p in 0..CHUNK {
        for (c, o) in out.iter_mut().enumerate() {
            let mut sum = 0.0f32;
            for (l, (light, samples)) in weights.iter().zip(&samples).enumerate() {
                let (Some((w0, ws)), Some((first, rest))) =
                    (light[c].split_first(), samples.split_first())
                else {
                    continue;
                };
                let mut acc = w0 * first[p];
                for (w, s) in ws.iter().zip(rest) {
                    acc += w * s[p];
                }
                sum = if l == 0 { acc } else { sum + acc };
            }
            o[p] = sum;
        }
    }
    out
}

/// Whether the target has vector units for f32 that the chunked loops vectorize for (defined
/// in `simd::target`, below this module, which the loop caps of `simd::forced` read too).
pub(crate) use crate::simd::VECTOR_UNITS;

/// Bytes one chunk of interleaved 8-bit RGB takes.
const CHUNK_BYTES: usize = 3 * CHUNK;

/// Whether [`encode_chunk`] interleaves through whole 32-bit pixels ([`interleave_words`])
/// rather than planes of code values ([`interleave_planes`]). Both give the same bytes (a unit
/// test checks both on every target), so this only picks the faster one for the target. Built
/// with AVX-512 (`-C target-cpu` for such a CPU), the table loads become gathers and the word
/// form turns into a few byte shuffles, and it was the faster one, in cache and from memory;
/// with SSE2 alone the planes were (the bench's `soa/srgb_u8` cases with this constant forced
/// each way, on a Xeon of the Sapphire Rapids generation; docs/performance.md has the
/// figures).
const WORD_INTERLEAVE: bool = cfg!(all(
    target_feature = "avx512f",
    target_feature = "avx512bw",
    target_feature = "avx512vl"
));

/// Clips and encodes one chunk of linear RGB to 8-bit sRGB into `dst`, interleaved; a pixel
/// with a NaN channel is black. Passes that each vectorize or pipeline well: each value's
/// segment bits (see `encode::SEGMENT_TABLE`), then the table entries and the code values
/// (the top byte of entry + bits · 2⁸), interleaved in a buffer and stored whole, in one of the
/// two ways [`WORD_INTERLEAVE`] picks between. Writing whole chunks front to back in passes
/// was faster than one pass of overlapping 32-bit stores per value.
#[inline(always)]
fn encode_chunk(rgb: &[[f32; CHUNK]; 3], dst: &mut [u8; CHUNK_BYTES]) {
    let mut bits = [[0u32; CHUNK]; 3];
    for p in 0..CHUNK {
        let [r, g, b] = [rgb[0][p], rgb[1][p], rgb[2][p]];
        // NaN in any channel makes the whole pixel black, as the per-pixel path does.
        let ok = !(r.is_nan() | g.is_nan() | b.is_nan());
        for (c, x) in [r, g, b].into_iter().enumerate() {
            bits[c][p] = segment_bits(if ok { x } else { 0.0 });
        }
    }
    *dst = if WORD_INTERLEAVE {
        interleave_words(&bits)
    } else {
        interleave_planes(&bits)
    };
}

/// The code value of segment bits `v` with table entry `e`: the top byte of `e + v · 2⁸`.
#[inline(always)]
fn code(v: u32, e: u32) -> u32 {
    e.wrapping_add(v << 8) >> 24
}

/// The table entries in a pass of their own (scalar loads), code values one plane at a time,
/// then interleaved byte by byte.
#[inline(always)]
fn interleave_planes(bits: &[[u32; CHUNK]; 3]) -> [u8; CHUNK_BYTES] {
    let mut entries = [[0u32; CHUNK]; 3];
    for (e, v) in entries.iter_mut().zip(bits) {
        for (e, v) in e.iter_mut().zip(v) {
            *e = entry(*v);
        }
    }
    let mut codes = [[0u8; CHUNK]; 3];
    for ((k, e), v) in codes.iter_mut().zip(&entries).zip(bits) {
        for ((k, e), v) in k.iter_mut().zip(e).zip(v) {
            *k = code(*v, *e) as u8;
        }
    }
    let mut out = [0u8; CHUNK_BYTES];
    for (p, px) in out.chunks_exact_mut(3).enumerate() {
        px[0] = codes[0][p];
        px[1] = codes[1][p];
        px[2] = codes[2][p];
    }
    out
}

/// Each pixel as one little-endian word `r | g << 8 | b << 16`, its table entries looked up
/// (gathered) in the same pass, then the first three bytes of each word: a fixed byte shuffle.
#[inline(always)]
fn interleave_words(bits: &[[u32; CHUNK]; 3]) -> [u8; CHUNK_BYTES] {
    let mut words = [0u8; 4 * CHUNK];
    for (p, w) in words.chunks_exact_mut(4).enumerate() {
        let [r, g, b] = [0, 1, 2].map(|c| code(bits[c][p], entry(bits[c][p])));
        w.copy_from_slice(&(r | g << 8 | b << 16).to_le_bytes());
    }
    core::array::from_fn(|i| words[i / 3 * 4 + i % 3])
}

/// [`encode_chunk`] into the first `out.len()` (at most `CHUNK_BYTES`) bytes of `out`, through
/// a buffer on the stack.
#[inline(always)]
fn encode_chunk_buffered(rgb: &[[f32; CHUNK]; 3], out: &mut [u8]) {
    let mut buffer = [0u8; CHUNK_BYTES];
    encode_chunk(rgb, &mut buffer);
    let n = out.len().min(CHUNK_BYTES);
    out[..n].copy_from_slice(&buffer[..n]);
}

/// The portable planar linear loop (chunks of [`CHUNK`] pixels that the compiler vectorizes
/// for the baseline target). Every plane and output holds the same number of pixels.
pub(crate) fn linear_planar_portable<const N: usize, const L: usize>(
    weights: &[[[f32; N]; 3]; L],
    samples: [[&[f32]; N]; L],
    out: [&mut [f32]; 3],
) {
    let pixels = out[0].len();
    let [r, g, b] = out;
    let (r_chunks, r_rest) = r.as_chunks_mut::<CHUNK>();
    let (g_chunks, g_rest) = g.as_chunks_mut::<CHUNK>();
    let (b_chunks, b_rest) = b.as_chunks_mut::<CHUNK>();
    let full: [[&[[f32; CHUNK]]; N]; L] =
        samples.map(|light| light.map(|p| p.as_chunks::<CHUNK>().0));
    let chunks = r_chunks.iter_mut().zip(g_chunks).zip(b_chunks);
    for (j, ((r, g), b)) in chunks.enumerate() {
        let rgb = product(weights, full.map(|light| light.map(|p| &p[j])));
        *r = rgb[0];
        *g = rgb[1];
        *b = rgb[2];
    }
    let done = pixels - r_rest.len();
    if done < pixels {
        let tail = gather(&samples, done);
        let rgb = product(weights, refs(&tail));
        let n = r_rest.len();
        r_rest.copy_from_slice(&rgb[0][..n]);
        g_rest.copy_from_slice(&rgb[1][..n]);
        b_rest.copy_from_slice(&rgb[2][..n]);
    }
}

/// The portable planar sRGB 8-bit loop with `Clip` (chunks of [`CHUNK`] pixels that the
/// compiler vectorizes for the baseline target). Every plane holds `out.len()` pixels.
pub(crate) fn encode_srgb8_planar_portable<const N: usize, const L: usize>(
    weights: &[[[f32; N]; 3]; L],
    samples: [[&[f32]; N]; L],
    out: &mut [[u8; 3]],
) {
    let pixels = out.len();
    let full: [[&[[f32; CHUNK]]; N]; L] =
        samples.map(|light| light.map(|p| p.as_chunks::<CHUNK>().0));
    let bytes = out.as_flattened_mut();
    let (byte_chunks, byte_rest) = bytes.as_chunks_mut::<CHUNK_BYTES>();
    for (j, dst) in byte_chunks.iter_mut().enumerate() {
        let rgb = product_for_encoding(weights, full.map(|light| light.map(|p| &p[j])));
        encode_chunk(&rgb, dst);
    }
    if !byte_rest.is_empty() {
        let done = pixels - byte_rest.len() / 3;
        let tail = gather(&samples, done);
        let rgb = product_for_encoding(weights, refs(&tail));
        encode_chunk_buffered(&rgb, byte_rest);
    }
}

/// The portable interleaved sRGB 8-bit loop with `Clip`, for
/// [`FoldedSet::encode_u8_batch`](crate::FoldedSet::encode_u8_batch) (one light) and [`LightGroupSet::encode_u8_batch`](crate::LightGroupSet::encode_u8_batch):
/// each chunk of [`CHUNK`] pixels transposed into planes on the stack, then encoded as by
/// [`encode_srgb8_planar_portable`] (a partial last chunk padded with zeros). `out` holds as
/// many pixels as `samples`.
pub(crate) fn encode_srgb8_batch_portable<const N: usize, const L: usize, P: Lights<N, L>>(
    weights: &[[[f32; N]; 3]; L],
    samples: &[P],
    out: &mut [[u8; 3]],
) {
    debug_assert_eq!(samples.len(), out.len());
    let (chunks, rest) = samples.as_chunks::<CHUNK>();
    let (byte_chunks, byte_rest) = out.as_flattened_mut().as_chunks_mut::<CHUNK_BYTES>();
    for (pixels, dst) in chunks.iter().zip(byte_chunks) {
        let planes = transpose(pixels);
        encode_chunk(&product_for_encoding(weights, refs(&planes)), dst);
    }
    if !rest.is_empty() {
        let mut tail = [[[0.0f32; N]; L]; CHUNK];
        for (t, s) in tail.iter_mut().zip(rest) {
            *t = *s.lights();
        }
        let planes = transpose(&tail);
        encode_chunk_buffered(&product_for_encoding(weights, refs(&planes)), byte_rest);
    }
}

/// One chunk of pixels as planes: `out[l][i][p]` is sample i of light l of pixel p.
#[inline(always)]
fn transpose<const N: usize, const L: usize, P: Lights<N, L>>(
    pixels: &[P; CHUNK],
) -> [[[f32; CHUNK]; N]; L] {
    core::array::from_fn(|l| {
        core::array::from_fn(|i| core::array::from_fn(|p| pixels[p].lights()[l][i]))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both interleaves give the same bytes, so [`WORD_INTERLEAVE`] changes only speed: every
    /// segment of the table, at its start, its middle and its end, for each channel (under
    /// Miri, every 17th segment).
    #[test]
    fn interleaves_agree() {
        let seg = |s: u32, pos: u32| (s << 16) | pos;
        let mut values = [[0u32; CHUNK]; 3];
        let mut n = 0;
        for s in (0..2048u32).step_by(if cfg!(miri) { 17 } else { 1 }) {
            for pos in [0, 0x7FFF, 0xFFFF] {
                for (c, plane) in (0u32..).zip(&mut values) {
                    // Channels offset from each other so that neighbours differ.
                    plane[n % CHUNK] = seg((s + 97 * c) % 2048, pos);
                }
                n += 1;
                if n % CHUNK == 0 {
                    assert_eq!(interleave_words(&values), interleave_planes(&values));
                }
            }
        }
    }
}
