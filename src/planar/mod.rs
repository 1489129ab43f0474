//! Batch conversion over planar (structure-of-arrays) samples: one slice per wavelength.
//!
//! The loops work on fixed chunks of [`CHUNK`] pixels with the 3×N product written as plain
//! loops over arrays, so the compiler vectorizes them for the baseline target (SSE2 on x86-64;
//! no `target-cpu` needed), and there is no branch per pixel. Nothing allocates; a length
//! mismatch is an [`Error`], checked before any output is written.

mod scalar;

use crate::encode::{entry, segment_bits};
use crate::{Error, FoldedSet, GamutMapping};

/// Pixels per step of the planar loops. A partial last chunk is padded with zeros on the stack.
const CHUNK: usize = 16;

/// Checks that every sample plane has the length of plane 0 and that every output length
/// equals it.
fn check_planes<const N: usize>(samples: &[&[f32]; N], outputs: &[usize]) -> Result<usize, Error> {
    let pixels = samples.first().map_or(0, |p| p.len());
    for len in samples
        .iter()
        .map(|p| p.len())
        .chain(outputs.iter().copied())
    {
        if len != pixels {
            return Err(Error::LengthMismatch {
                inputs: pixels,
                outputs: len,
            });
        }
    }
    Ok(pixels)
}

/// One chunk's samples: plane i's `CHUNK` values starting at pixel `start`, or the zero-padded
/// rest of it when fewer remain.
#[inline(always)]
fn gather<const N: usize>(samples: &[&[f32]; N], start: usize) -> [[f32; CHUNK]; N] {
    core::array::from_fn(|i| {
        let mut chunk = [0.0f32; CHUNK];
        let rest = samples[i].get(start..).unwrap_or(&[]);
        let n = rest.len().min(CHUNK);
        chunk[..n].copy_from_slice(&rest[..n]);
        chunk
    })
}

/// `weights · samples` for one chunk, each pixel accumulated in index order from 0.0 in f32,
/// exactly as [`FoldedSet::linear_rgb`] does, so the results are bit for bit the same.
#[inline(always)]
fn product<const N: usize>(
    weights: &[[f32; N]; 3],
    samples: [&[f32; CHUNK]; N],
) -> [[f32; CHUNK]; 3] {
    let mut out = [[0.0f32; CHUNK]; 3];
    // Pixels outermost, so the loop over them vectorizes once the short loops inside unroll.
    for p in 0..CHUNK {
        for (o, row) in out.iter_mut().zip(weights) {
            let mut acc = 0.0f32;
            for (w, s) in row.iter().zip(samples) {
                acc += w * s[p];
            }
            o[p] = acc;
        }
    }
    out
}

/// As [`product`], but starting from the first product instead of 0.0: one addition less per
/// channel, and the same result except that an exact zero may be −0.0, which encodes as +0.0.
#[inline(always)]
fn product_for_encoding<const N: usize>(
    weights: &[[f32; N]; 3],
    samples: [&[f32; CHUNK]; N],
) -> [[f32; CHUNK]; 3] {
    let mut out = [[0.0f32; CHUNK]; 3];
    let Some((first, rest)) = samples.split_first() else {
        return out;
    };
    for p in 0..CHUNK {
        for (o, row) in out.iter_mut().zip(weights) {
            let Some((w0, ws)) = row.split_first() else {
                continue;
            };
            let mut acc = w0 * first[p];
            for (w, s) in ws.iter().zip(rest) {
                acc += w * s[p];
            }
            o[p] = acc;
        }
    }
    out
}

/// Whether the target has vector units for f32 that the chunked loops vectorize for (SSE2 on
/// x86, NEON, WebAssembly SIMD). Without them (microcontrollers such as the Cortex-M4F, whose
/// FPU is scalar) the chunks' buffers are only extra loads and stores, and
/// [`FoldedSet::encode_u8_planar`] goes one pixel at a time instead (`planar::scalar` for sRGB with
/// `Clip`): on the M4F 54 instead of 143 instructions per pixel (N = 4, opt-level 3; the
/// README's "On a microcontroller" has the commands). `tests/planar.rs` checks that the chunked
/// form equals `encode_u8`.
pub(crate) const VECTOR_UNITS: bool = cfg!(any(
    target_feature = "sse2",
    target_feature = "neon",
    target_feature = "simd128"
));

/// Bytes one chunk of interleaved 8-bit RGB takes.
const CHUNK_BYTES: usize = 3 * CHUNK;

/// Whether [`encode_chunk`] interleaves through whole 32-bit pixels ([`interleave_words`])
/// rather than planes of code values ([`interleave_planes`]). Both give the same bytes (a unit
/// test checks both on every target), so this only picks the faster one for the target. Built
/// with AVX-512 (`-C target-cpu` for such a CPU), the table loads become gathers and the word
/// form turns into a few byte shuffles: N = 4 over 2²⁵ pixels took 1.70 ns/pixel against 2.56
/// for the planes (1.28 against 2.09 in cache). With SSE2 alone it is the other way round,
/// 3.56 against 2.77 (3.31 against 2.49 in cache). Measured with
/// `cargo bench --bench runtime -- 'bandwidth/(stream/read_write_3B|soa/srgb_u8.*)/N4'` and
/// this constant forced each way, on a Xeon of the Sapphire Rapids generation (AVX-512).
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
/// measured 18 % faster than one pass of overlapping 32-bit stores per value.
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
pub(crate) fn linear_planar_portable<const N: usize>(
    weights: &[[f32; N]; 3],
    samples: [&[f32]; N],
    out: [&mut [f32]; 3],
) {
    let pixels = out[0].len();
    let [r, g, b] = out;
    let (r_chunks, r_rest) = r.as_chunks_mut::<CHUNK>();
    let (g_chunks, g_rest) = g.as_chunks_mut::<CHUNK>();
    let (b_chunks, b_rest) = b.as_chunks_mut::<CHUNK>();
    let full: [&[[f32; CHUNK]]; N] = samples.map(|p| p.as_chunks::<CHUNK>().0);
    let chunks = r_chunks.iter_mut().zip(g_chunks).zip(b_chunks);
    for (j, ((r, g), b)) in chunks.enumerate() {
        let rgb = product(weights, full.map(|p| &p[j]));
        *r = rgb[0];
        *g = rgb[1];
        *b = rgb[2];
    }
    let done = pixels - r_rest.len();
    if done < pixels {
        let tail = gather(&samples, done);
        let rgb = product(weights, core::array::from_fn(|i| &tail[i]));
        let n = r_rest.len();
        r_rest.copy_from_slice(&rgb[0][..n]);
        g_rest.copy_from_slice(&rgb[1][..n]);
        b_rest.copy_from_slice(&rgb[2][..n]);
    }
}

/// The portable planar sRGB 8-bit loop with `Clip` (chunks of [`CHUNK`] pixels that the
/// compiler vectorizes for the baseline target). Every plane holds `out.len()` pixels.
pub(crate) fn encode_srgb8_planar_portable<const N: usize>(
    weights: &[[f32; N]; 3],
    samples: [&[f32]; N],
    out: &mut [[u8; 3]],
) {
    let pixels = out.len();
    let full: [&[[f32; CHUNK]]; N] = samples.map(|p| p.as_chunks::<CHUNK>().0);
    let bytes = out.as_flattened_mut();
    let (byte_chunks, byte_rest) = bytes.as_chunks_mut::<CHUNK_BYTES>();
    for (j, dst) in byte_chunks.iter_mut().enumerate() {
        let rgb = product_for_encoding(weights, full.map(|p| &p[j]));
        encode_chunk(&rgb, dst);
    }
    if !byte_rest.is_empty() {
        let done = pixels - byte_rest.len() / 3;
        let tail = gather(&samples, done);
        let rgb = product_for_encoding(weights, core::array::from_fn(|i| &tail[i]));
        encode_chunk_buffered(&rgb, byte_rest);
    }
}

/// The portable interleaved sRGB 8-bit loop with `Clip`, for
/// [`FoldedSet::encode_u8_batch`]: each chunk of [`CHUNK`] pixels transposed into planes on
/// the stack, then encoded as by [`encode_srgb8_planar_portable`] (a partial last chunk padded
/// with zeros). `out` holds as many pixels as `samples`.
pub(crate) fn encode_srgb8_batch_portable<const N: usize>(
    weights: &[[f32; N]; 3],
    samples: &[[f32; N]],
    out: &mut [[u8; 3]],
) {
    debug_assert_eq!(samples.len(), out.len());
    let (chunks, rest) = samples.as_chunks::<CHUNK>();
    let (byte_chunks, byte_rest) = out.as_flattened_mut().as_chunks_mut::<CHUNK_BYTES>();
    for (pixels, dst) in chunks.iter().zip(byte_chunks) {
        let planes = transpose(pixels);
        encode_chunk(&product_for_encoding(weights, planes.each_ref()), dst);
    }
    if !rest.is_empty() {
        let mut tail = [[0.0f32; N]; CHUNK];
        tail[..rest.len()].copy_from_slice(rest);
        let planes = transpose(&tail);
        encode_chunk_buffered(&product_for_encoding(weights, planes.each_ref()), byte_rest);
    }
}

/// One chunk of pixels as planes: `out[i][p]` is sample i of pixel p.
#[inline(always)]
fn transpose<const N: usize>(pixels: &[[f32; N]; CHUNK]) -> [[f32; CHUNK]; N] {
    core::array::from_fn(|i| core::array::from_fn(|p| pixels[p][i]))
}

impl<const N: usize> FoldedSet<N> {
    /// [`linear_rgb`](Self::linear_rgb) for planar samples: `samples[i][p]` is pixel p's sample
    /// at `wavelengths_nm[i]`, and `out[c][p]` receives channel c (R, G, B) of pixel p.
    ///
    /// Bit for bit the same as [`linear_rgb`](Self::linear_rgb) on every pixel (NaN payloads
    /// aside), so the same IEEE input handling and [`f32_budget`](crate::f32_budget) accuracy
    /// apply: NaN samples give NaN channels, infinities give ±Inf or NaN, overflow gives ±Inf.
    /// Never panics. On x86-64 CPUs with AVX-512 (F, BW and VBMI; detected at run time,
    /// once) the loop runs sixteen pixels per register, on those with AVX2 eight; elsewhere
    /// over chunks of 16 pixels that the compiler vectorizes for the target (SSE2, NEON).
    /// Every loop computes each channel with the same f32 operations in the same order, so all
    /// give the same bits.
    ///
    /// With at least 2²⁰ pixels (12 MiB of output) and AVX-512, or AVX2 and more than four
    /// samples, the output is written with non-temporal stores, which skip reading its lines
    /// from memory first: faster for an image far larger than the caches, but the output is
    /// then not in the caches. Work on a large image in smaller calls (rows or tiles) to keep
    /// each call's output cached for what reads it next.
    ///
    /// Errors with [`Error::LengthMismatch`] (and writes nothing) unless every plane and every
    /// output has the same length; `inputs` is then the length of `samples[0]` and `outputs`
    /// the first length (another plane's or an output's) that differs from it.
    ///
    /// ```
    /// use spectral_quadrature::tables::folded::TABLE2_ROW2_SRGB as SET;
    /// let (a, b, c, d) = ([0.5f32; 20], [0.4f32; 20], [0.3f32; 20], [0.2f32; 20]);
    /// let (mut r, mut g, mut bl) = ([0.0f32; 20], [0.0f32; 20], [0.0f32; 20]);
    /// SET.linear_rgb_planar([&a, &b, &c, &d], [&mut r, &mut g, &mut bl]).unwrap();
    /// assert_eq!([r[19], g[19], bl[19]], SET.linear_rgb(&[0.5, 0.4, 0.3, 0.2]));
    /// ```
    pub fn linear_rgb_planar(
        &self,
        samples: [&[f32]; N],
        out: [&mut [f32]; 3],
    ) -> Result<(), Error> {
        check_planes(&samples, &[out[0].len(), out[1].len(), out[2].len()])?;
        let [r, g, b] = out;
        // The AVX-512 or AVX2 loop where the CPU has one (the same bits; see `simd`), then the
        // rest in the portable one.
        let done = crate::simd::linear_planar(&self.weights, samples, [&mut *r, &mut *g, &mut *b]);
        linear_planar_portable(
            &self.weights,
            samples.map(|p| &p[done..]),
            [&mut r[done..], &mut g[done..], &mut b[done..]],
        );
        Ok(())
    }

    /// Planar samples (as for [`linear_rgb_planar`](Self::linear_rgb_planar)) → gamut-mapped,
    /// encoded 8-bit RGB with the set's [`display`](Self::display), interleaved: `out[p] = [r, g, b]`, the layout of RGB8
    /// images and frame buffers, and of [`encode_u8_batch`](Self::encode_u8_batch).
    ///
    /// When the display's transfer function is [`TransferFunction::Srgb`](crate::TransferFunction::Srgb) (sRGB, Display P3)
    /// and [`GamutMapping::Clip`], on a target with f32 vector units (x86, NEON), this is the
    /// fast path: a vectorized product, a clip and the table encoder of
    /// [`srgb8_from_linear`](crate::srgb8_from_linear), correctly rounded and branch-free (the
    /// README's Performance section has its speed against the memory bound). On x86-64 CPUs
    /// with AVX-512 (F, BW and VBMI; detected at run time, once) it runs sixteen pixels per
    /// register and computes the code values with a polynomial, handing every value near a
    /// rounding boundary (and every NaN) back to the per-pixel function; on those with AVX2,
    /// eight pixels per AVX2 register; else chunks of 16 pixels that the compiler vectorizes
    /// for the target. It equals [`encode_u8`](Self::encode_u8) exactly
    /// ([`SRGB8_MAX_STEP_ERROR`](crate::SRGB8_MAX_STEP_ERROR) is 0): every loop uses the same
    /// f32 operations in the same order for the product and the table's code values (the
    /// polynomial's wherever it does not hand the value back, checked for every f32 from 0 to
    /// 1), and the unit tests compare each loop with the per-pixel function on a million
    /// random pixels and the edge inputs.
    /// On targets without vector units (microcontrollers) the same case runs a scalar loop, one
    /// pixel at a time with the weights held in registers, and equals
    /// [`encode_u8`](Self::encode_u8) exactly too (same sums, same table). Any other transfer
    /// function, or [`GamutMapping::PreserveA`], goes pixel by pixel through
    /// [`encode_u8`](Self::encode_u8) and equals it exactly.
    ///
    /// Input handling as [`encode_u8`](Self::encode_u8): NaN anywhere in a pixel (a NaN sample,
    /// or infinities that meet as ∞ − ∞ or 0 · ∞ in the product) gives black; ±Inf and huge
    /// channels clip to 0 or 255; never panics.
    ///
    /// Errors with [`Error::LengthMismatch`] (and writes nothing) unless every plane and `out`
    /// have the same length, reported as for [`linear_rgb_planar`](Self::linear_rgb_planar).
    ///
    /// ```
    /// use spectral_quadrature::tables::folded::TABLE2_ROW2_SRGB as SET;
    /// use spectral_quadrature::GamutMapping;
    /// let planes = [[0.5f32; 20], [0.4; 20], [0.3; 20], [0.2; 20]];
    /// let mut out = [[0u8; 3]; 20];
    /// SET.encode_u8_planar(GamutMapping::Clip, planes.each_ref().map(|p| &p[..]), &mut out)
    ///     .unwrap();
    /// let one = SET.encode_u8(GamutMapping::Clip, &[0.5, 0.4, 0.3, 0.2]);
    /// assert!((0..3).all(|c| out[7][c].abs_diff(one[c]) <= 1));
    /// ```
    pub fn encode_u8_planar(
        &self,
        mapping: GamutMapping,
        samples: [&[f32]; N],
        out: &mut [[u8; 3]],
    ) -> Result<(), Error> {
        let pixels = check_planes(&samples, &[out.len()])?;
        let srgb_clip = self.display.is_srgb_clip(mapping);
        if !(VECTOR_UNITS && srgb_clip) {
            if srgb_clip {
                // No vector units: one pixel at a time, the weights in registers.
                scalar::encode_srgb8_clip(&self.weights, samples, out);
                return Ok(());
            }
            // Every plane has `pixels` values (checked above), so the slices are in range, and
            // with them the compiler sees that every index below is.
            let planes: [&[f32]; N] = samples.map(|plane| &plane[..pixels]);
            for (p, o) in out[..pixels].iter_mut().enumerate() {
                let s: [f32; N] = core::array::from_fn(|i| planes[i][p]);
                *o = self.encode_u8(mapping, &s);
            }
            return Ok(());
        }
        // The AVX-512 or AVX2 loop where the CPU has one (the same bytes; see `simd`), then the
        // rest in the portable one.
        let done = crate::simd::encode_srgb8_planar(&self.weights, samples, out.as_flattened_mut());
        encode_srgb8_planar_portable(
            &self.weights,
            samples.map(|p| &p[done..]),
            &mut out[done..pixels],
        );
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both interleaves give the same bytes, so [`WORD_INTERLEAVE`] changes only speed: every
    /// segment of the table, at its start, its middle and its end, for each channel.
    #[test]
    fn interleaves_agree() {
        let seg = |s: u32, pos: u32| (s << 16) | pos;
        let mut values = [[0u32; CHUNK]; 3];
        let mut n = 0;
        for s in 0..2048u32 {
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
