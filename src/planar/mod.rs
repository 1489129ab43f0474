//! The planar path, over samples in planes (structure of arrays: one slice per wavelength):
//! [`FoldedSet::linear_rgb_planar`], [`FoldedSet::encode_u8_planar_to_interleaved`] and
//! [`FoldedSet::encode_u8_planar`] (its bytes in three planes), and the 16-bit
//! [`FoldedSet::encode_u16_planar`] and [`FoldedSet::encode_u16_planar_to_interleaved`]. Nothing
//! allocates; a length mismatch is an [`Error`], checked before any output is written.
//!
//! The loops: an accelerated x86-64 loop where the CPU has one ([`simd`](crate::simd)), the
//! portable chunked loops ([`portable`]) where the target has f32 vector units, and a loop one
//! pixel at a time ([`scalar`]) for the sRGB 8-bit case where it has none.

#![forbid(unsafe_code)]

pub(crate) mod portable;
mod scalar;

use crate::model::error::planar_pixels;
use crate::{Error, FoldedSet, GamutMapping, LengthOf};
use portable::{encode_srgb8_planar_portable, linear_planar_portable, VECTOR_UNITS};

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
    /// output has the same length, at the first that differs from `samples[0]`'s (`expected`):
    /// [`LengthOf::InputPlane`] for another plane of `samples`, [`LengthOf::OutputPlane`] for a
    /// plane of `out`.
    ///
    /// With N = 0 there are no planes: the number of pixels is the length of `out[0]`
    /// (`expected` in the error), the other outputs must have it too, and every pixel is
    /// [`linear_rgb`](Self::linear_rgb) of no samples, `[0.0, 0.0, 0.0]`, as for
    /// [`linear_rgb_batch`](Self::linear_rgb_batch) with that many pixels. N above
    /// [`MAX_WAVELENGTHS`](crate::MAX_WAVELENGTHS) does not compile (its stack use grows with
    /// N).
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
        crate::model::set::assert_width::<N>();
        planar_pixels(
            samples.iter().map(|p| p.len()),
            LengthOf::OutputPlane,
            &[out[0].len(), out[1].len(), out[2].len()],
        )?;
        let [r, g, b] = out;
        // The AVX-512 or AVX2 loop where the CPU has one (the same bits; see `simd`), then the
        // rest in the portable one.
        let weights = core::array::from_ref(self.weights_ref());
        let done = crate::simd::linear_planar(weights, [samples], [&mut *r, &mut *g, &mut *b]);
        linear_planar_portable(
            weights,
            [samples.map(|p| &p[done..])],
            [&mut r[done..], &mut g[done..], &mut b[done..]],
        );
        Ok(())
    }

    /// Planar samples (as for [`linear_rgb_planar`](Self::linear_rgb_planar)) → gamut-mapped,
    /// encoded 8-bit RGB with the set's [`display`](Self::display), interleaved (planes in,
    /// pixels out; [`encode_u8_planar`](Self::encode_u8_planar) writes three planes instead):
    /// `out[p] = [r, g, b]`, the layout of RGB8 images and frame buffers, and of
    /// [`encode_u8_batch`](Self::encode_u8_batch).
    ///
    /// When the display's transfer function is
    /// [`TransferFunction::Srgb`](crate::TransferFunction::Srgb) (sRGB, Display P3) and
    /// [`GamutMapping::Clip`], on a target with f32 vector units (x86, NEON), this is the
    /// fast path: a vectorized product, a clip and the table encoder of
    /// [`srgb8_from_linear`](crate::srgb8_from_linear), correctly rounded and branch-free
    /// (docs/performance.md has its speed against the memory bound). On x86-64 CPUs
    /// with AVX-512 (F, BW and VBMI; detected at run time, once) it runs sixteen pixels per
    /// register and computes the code values with a polynomial, handing every value near a
    /// rounding boundary (and every NaN) back to the per-pixel function; on those with AVX2,
    /// eight pixels per AVX2 register; else chunks of 16 pixels that the compiler vectorizes
    /// for the target. It equals [`encode_u8`](Self::encode_u8) exactly
    /// ([`SRGB8_MAX_ERROR`](crate::SRGB8_MAX_ERROR) is 0): every loop uses the same
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
    /// have the same length, reported as for [`linear_rgb_planar`](Self::linear_rgb_planar)
    /// ([`LengthOf::Output`] for `out`).
    ///
    /// With N = 0 there are no planes: `out.len()` is the number of pixels, and every pixel is
    /// [`encode_u8`](Self::encode_u8) of no samples (the display's encoding of black,
    /// `[0, 0, 0]` for every built-in transfer function), as for
    /// [`encode_u8_batch`](Self::encode_u8_batch) with that many pixels. N above
    /// [`MAX_WAVELENGTHS`](crate::MAX_WAVELENGTHS) does not compile (its stack use grows with
    /// N).
    ///
    /// ```
    /// use spectral_quadrature::tables::folded::TABLE2_ROW2_SRGB as SET;
    /// use spectral_quadrature::GamutMapping;
    /// let planes = [[0.5f32; 20], [0.4; 20], [0.3; 20], [0.2; 20]];
    /// let mut out = [[0u8; 3]; 20];
    /// SET.encode_u8_planar_to_interleaved(
    ///     GamutMapping::Clip,
    ///     planes.each_ref().map(|p| &p[..]),
    ///     &mut out,
    /// )
    /// .unwrap();
    /// assert_eq!(out[7], SET.encode_u8(GamutMapping::Clip, &[0.5, 0.4, 0.3, 0.2]));
    /// ```
    pub fn encode_u8_planar_to_interleaved(
        &self,
        mapping: GamutMapping,
        samples: [&[f32]; N],
        out: &mut [[u8; 3]],
    ) -> Result<(), Error> {
        crate::model::set::assert_width::<N>();
        let pixels = planar_pixels(
            samples.iter().map(|p| p.len()),
            LengthOf::Output,
            &[out.len()],
        )?;
        let srgb_clip = self.display_ref().is_srgb_clip(mapping);
        let vector_units = VECTOR_UNITS && crate::simd::allowed!(Portable);
        if !(vector_units && srgb_clip) {
            if srgb_clip {
                // No vector units: one pixel at a time, the weights in registers.
                crate::simd::note!(Scalar, false);
                scalar::encode_srgb8_clip(self.weights_ref(), samples, out);
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
        let weights = core::array::from_ref(self.weights_ref());
        let done = crate::simd::encode_srgb8_planar(weights, [samples], out.as_flattened_mut());
        encode_srgb8_planar_portable(
            weights,
            [samples.map(|p| &p[done..])],
            &mut out[done..pixels],
        );
        Ok(())
    }

    /// [`encode_u8_planar_to_interleaved`](Self::encode_u8_planar_to_interleaved) with the
    /// output in planes too: `out[c][p]` receives channel c (R, G, B) of pixel p. The same
    /// loops, run on chunks of 64 pixels through a small buffer on the stack (192 bytes), so the
    /// same bytes as [`encode_u8`](Self::encode_u8) on every pixel, and the same input handling
    /// (NaN anywhere in a pixel → black; ±Inf and huge channels clip; never panics).
    ///
    /// Errors with [`Error::LengthMismatch`] (and writes nothing) unless every plane of
    /// `samples` and of `out` has the same length, reported as for
    /// [`linear_rgb_planar`](Self::linear_rgb_planar) (with N = 0, `out[0]` gives the number of
    /// pixels). N above [`MAX_WAVELENGTHS`](crate::MAX_WAVELENGTHS) does not compile.
    ///
    /// ```
    /// use spectral_quadrature::tables::folded::TABLE2_ROW2_SRGB as SET;
    /// use spectral_quadrature::GamutMapping;
    /// let planes = [[0.5f32; 20], [0.4; 20], [0.3; 20], [0.2; 20]];
    /// let (mut r, mut g, mut b) = ([0u8; 20], [0u8; 20], [0u8; 20]);
    /// SET.encode_u8_planar(GamutMapping::Clip, planes.each_ref().map(|p| &p[..]), [&mut r, &mut g, &mut b])
    ///     .unwrap();
    /// assert_eq!([r[7], g[7], b[7]], SET.encode_u8(GamutMapping::Clip, &[0.5, 0.4, 0.3, 0.2]));
    /// ```
    pub fn encode_u8_planar(
        &self,
        mapping: GamutMapping,
        samples: [&[f32]; N],
        out: [&mut [u8]; 3],
    ) -> Result<(), Error> {
        crate::model::set::assert_width::<N>();
        let pixels = planar_pixels(
            samples.iter().map(|p| p.len()),
            LengthOf::OutputPlane,
            &[out[0].len(), out[1].len(), out[2].len()],
        )?;
        let [r, g, b] = out;
        let mut buf = [[0u8; 3]; CHUNK];
        let mut start = 0;
        while start < pixels {
            let end = pixels.min(start + CHUNK);
            let chunk = &mut buf[..end - start];
            self.encode_u8_planar_to_interleaved(mapping, samples.map(|p| &p[start..end]), chunk)?;
            for (k, px) in chunk.iter().enumerate() {
                r[start + k] = px[0];
                g[start + k] = px[1];
                b[start + k] = px[2];
            }
            start = end;
        }
        Ok(())
    }

    /// Planar samples (as for [`linear_rgb_planar`](Self::linear_rgb_planar)) → gamut-mapped,
    /// encoded 16-bit RGB, interleaved: `out[p] = encode_u16(samples of pixel p)`. Pixel by
    /// pixel through [`encode_u16`](Self::encode_u16), so the same values and input handling
    /// (NaN anywhere in a pixel → black; ±Inf and huge channels clip; never panics).
    ///
    /// Errors with [`Error::LengthMismatch`] (and writes nothing) unless every plane and `out`
    /// have the same length, reported as for [`linear_rgb_planar`](Self::linear_rgb_planar)
    /// ([`LengthOf::Output`] for `out`; with N = 0, `out.len()` is the number of pixels). N above
    /// [`MAX_WAVELENGTHS`](crate::MAX_WAVELENGTHS) does not compile.
    ///
    /// ```
    /// use spectral_quadrature::tables::folded::TABLE2_ROW2_SRGB as SET;
    /// use spectral_quadrature::GamutMapping;
    /// let planes = [[0.5f32; 20], [0.4; 20], [0.3; 20], [0.2; 20]];
    /// let mut out = [[0u16; 3]; 20];
    /// SET.encode_u16_planar_to_interleaved(GamutMapping::Clip, planes.each_ref().map(|p| &p[..]), &mut out)
    ///     .unwrap();
    /// assert_eq!(out[7], SET.encode_u16(GamutMapping::Clip, &[0.5, 0.4, 0.3, 0.2]));
    /// ```
    pub fn encode_u16_planar_to_interleaved(
        &self,
        mapping: GamutMapping,
        samples: [&[f32]; N],
        out: &mut [[u16; 3]],
    ) -> Result<(), Error> {
        crate::model::set::assert_width::<N>();
        let pixels = planar_pixels(
            samples.iter().map(|p| p.len()),
            LengthOf::Output,
            &[out.len()],
        )?;
        let planes: [&[f32]; N] = samples.map(|plane| &plane[..pixels]);
        for (p, o) in out[..pixels].iter_mut().enumerate() {
            let s: [f32; N] = core::array::from_fn(|i| planes[i][p]);
            *o = self.encode_u16(mapping, &s);
        }
        Ok(())
    }

    /// [`encode_u16_planar_to_interleaved`](Self::encode_u16_planar_to_interleaved) with the
    /// output in planes: `out[c][p]` receives channel c (R, G, B) of pixel p. The same values
    /// as [`encode_u16`](Self::encode_u16) on every pixel, the same input handling.
    ///
    /// Errors with [`Error::LengthMismatch`] (and writes nothing) unless every plane of
    /// `samples` and of `out` has the same length, reported as for
    /// [`linear_rgb_planar`](Self::linear_rgb_planar). N above
    /// [`MAX_WAVELENGTHS`](crate::MAX_WAVELENGTHS) does not compile.
    ///
    /// ```
    /// use spectral_quadrature::tables::folded::TABLE2_ROW2_SRGB as SET;
    /// use spectral_quadrature::GamutMapping;
    /// let planes = [[0.5f32; 20], [0.4; 20], [0.3; 20], [0.2; 20]];
    /// let (mut r, mut g, mut b) = ([0u16; 20], [0u16; 20], [0u16; 20]);
    /// SET.encode_u16_planar(GamutMapping::Clip, planes.each_ref().map(|p| &p[..]), [&mut r, &mut g, &mut b])
    ///     .unwrap();
    /// assert_eq!([r[7], g[7], b[7]], SET.encode_u16(GamutMapping::Clip, &[0.5, 0.4, 0.3, 0.2]));
    /// ```
    pub fn encode_u16_planar(
        &self,
        mapping: GamutMapping,
        samples: [&[f32]; N],
        out: [&mut [u16]; 3],
    ) -> Result<(), Error> {
        crate::model::set::assert_width::<N>();
        let pixels = planar_pixels(
            samples.iter().map(|p| p.len()),
            LengthOf::OutputPlane,
            &[out[0].len(), out[1].len(), out[2].len()],
        )?;
        let planes: [&[f32]; N] = samples.map(|plane| &plane[..pixels]);
        let [r, g, b] = out;
        let (r, g, b) = (&mut r[..pixels], &mut g[..pixels], &mut b[..pixels]);
        for p in 0..pixels {
            let s: [f32; N] = core::array::from_fn(|i| planes[i][p]);
            [r[p], g[p], b[p]] = self.encode_u16(mapping, &s);
        }
        Ok(())
    }
}

/// Pixels per chunk of [`FoldedSet::encode_u8_planar`]: its stack buffer holds 3 · 64 bytes.
const CHUNK: usize = 64;
