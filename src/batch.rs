//! Batch conversion over caller-provided slices: one pixel's samples per `[f32; N]`, one
//! output per pixel. Nothing allocates; a length mismatch is an [`Error`], checked before any
//! output is written.

#![forbid(unsafe_code)]

use crate::model::error::check_length;
use crate::{Error, FoldedSet, GamutMapping, LengthOf, WavelengthSet};

impl<const N: usize> WavelengthSet<N> {
    /// [`ac1c2`](Self::ac1c2) for every pixel: `out[p] = ac1c2(&samples[p])`.
    ///
    /// Errors with [`Error::LengthMismatch`] (and writes nothing) unless
    /// `samples.len() == out.len()`: [`LengthOf::Output`], `expected` the input's pixels, `got`
    /// the output's. Per-pixel input handling as [`ac1c2`](Self::ac1c2); with
    /// N = 0 every pixel is `[0.0, 0.0, 0.0]`.
    ///
    /// On x86-64 from 28 to [`MAX_WAVELENGTHS`](crate::MAX_WAVELENGTHS) wavelengths, four
    /// pixels' products run side by side, each in its own order: the same bits as pixel by
    /// pixel, about twice as fast (docs/performance.md).
    pub fn ac1c2_batch(&self, samples: &[[f32; N]], out: &mut [[f32; 3]]) -> Result<(), Error> {
        check_length(LengthOf::Output, samples.len(), out.len())?;
        let done = interleaved(self.weights_ref(), samples, out);
        for (o, s) in out[done..].iter_mut().zip(&samples[done..]) {
            *o = self.ac1c2(s);
        }
        Ok(())
    }
}

impl<const N: usize> FoldedSet<N> {
    /// [`linear_rgb`](Self::linear_rgb) for every pixel (with N = 0, `[0.0, 0.0, 0.0]`).
    ///
    /// On x86-64 from 28 to [`MAX_WAVELENGTHS`](crate::MAX_WAVELENGTHS) wavelengths, four
    /// pixels' products run side by side, each in its own order: the same bits as pixel by
    /// pixel, about twice as fast (docs/performance.md).
    ///
    /// Errors with [`Error::LengthMismatch`] (and writes nothing) unless the lengths agree
    /// ([`LengthOf::Output`], as for [`WavelengthSet::ac1c2_batch`]).
    pub fn linear_rgb_batch(
        &self,
        samples: &[[f32; N]],
        out: &mut [[f32; 3]],
    ) -> Result<(), Error> {
        check_length(LengthOf::Output, samples.len(), out.len())?;
        let done = interleaved(self.weights_ref(), samples, out);
        for (o, s) in out[done..].iter_mut().zip(&samples[done..]) {
            *o = self.linear_rgb(s);
        }
        Ok(())
    }

    /// [`encode_u8`](Self::encode_u8) for every pixel (NaN anywhere in a pixel → black).
    ///
    /// With the sRGB curve and [`GamutMapping::Clip`] on an x86-64 CPU with AVX-512 (F, BW and
    /// VBMI; detected at run time, once) and N = 4, sixteen pixels go through each register
    /// and their code values are computed as by [`encode_u8_planar_to_interleaved`](Self::encode_u8_planar_to_interleaved)
    /// there; with AVX2 (and at other N), eight pixels go through each AVX2 register; on other
    /// targets with f32 vector units (SSE2, NEON, WebAssembly SIMD) chunks of 16 pixels are
    /// transposed into planes on the stack and encoded as by
    /// [`encode_u8_planar_to_interleaved`](Self::encode_u8_planar_to_interleaved), in loops the compiler vectorizes; without
    /// vector units (microcontrollers), pixel by pixel. Every way gives
    /// [`encode_u8`](Self::encode_u8)'s bytes, bit for bit (with N = 0, the display's encoding
    /// of black for every pixel). N above [`MAX_WAVELENGTHS`](crate::MAX_WAVELENGTHS) does not
    /// compile (the vector loops' stack use grows with N).
    ///
    /// Errors with [`Error::LengthMismatch`] (and writes nothing) unless the lengths agree
    /// ([`LengthOf::Output`], as for [`WavelengthSet::ac1c2_batch`]).
    pub fn encode_u8_batch(
        &self,
        mapping: GamutMapping,
        samples: &[[f32; N]],
        out: &mut [[u8; 3]],
    ) -> Result<(), Error> {
        crate::model::set::assert_width::<N>();
        check_length(LengthOf::Output, samples.len(), out.len())?;
        let srgb_clip = self.display_ref().is_srgb_clip(mapping);
        let vector_units = crate::planar::portable::VECTOR_UNITS && crate::simd::allowed!(Portable);
        // For the sRGB curve with `Clip` on a target with vector units: the AVX-512 or AVX2
        // loop where the CPU has one (the same bytes; see `simd`), then the portable loop for
        // the rest.
        if vector_units && srgb_clip {
            let weights = core::array::from_ref(self.weights_ref());
            let done = crate::simd::encode_srgb8_batch(weights, samples, out.as_flattened_mut());
            crate::planar::portable::encode_srgb8_batch_portable(
                weights,
                &samples[done..],
                &mut out[done..],
            );
            return Ok(());
        }
        // Pixel by pixel: other curves and mappings, and targets without vector units.
        if srgb_clip {
            crate::simd::note!(Scalar, false);
        }
        for (o, s) in out.iter_mut().zip(samples) {
            *o = self.encode_u8(mapping, s);
        }
        Ok(())
    }

    /// [`encode_u16`](Self::encode_u16) for every pixel (NaN anywhere in a pixel → black; with
    /// N = 0, the display's encoding of black).
    ///
    /// Errors with [`Error::LengthMismatch`] (and writes nothing) unless the lengths agree
    /// ([`LengthOf::Output`], as for [`WavelengthSet::ac1c2_batch`]).
    pub fn encode_u16_batch(
        &self,
        mapping: GamutMapping,
        samples: &[[f32; N]],
        out: &mut [[u16; 3]],
    ) -> Result<(), Error> {
        check_length(LengthOf::Output, samples.len(), out.len())?;
        for (o, s) in out.iter_mut().zip(samples) {
            *o = self.encode_u16(mapping, s);
        }
        Ok(())
    }
}

/// The fewest wavelengths at which [`FoldedSet::linear_rgb_batch`] and
/// [`WavelengthSet::ac1c2_batch`] run four pixels side by side on x86-64.
///
/// Below it the compiler unrolls the per-pixel product (`pixel::mat_vec`) whole, and the
/// processor overlaps one pixel's chain of additions with the next pixel's: pixel by pixel is
/// faster there (1.2-8.1 ns a pixel at 3 to 27 wavelengths against 2.6-10.6 side by side, in
/// `report --sections 4`). From 28 on the compiler keeps the loop, each pixel waits for one
/// addition per wavelength (22-39 ns at 28 to 46), and four pixels side by side take about
/// half that (11-16 ns).
pub(crate) const INTERLEAVED_FROM: usize = 28;

/// Converts the pixels of `samples` into `out` four at a time where [`INTERLEAVED_FROM`] and
/// the CPU allow, and returns how many it converted; the caller converts the rest pixel by
/// pixel.
#[inline]
fn interleaved<const N: usize>(
    weights: &[[f32; N]; 3],
    samples: &[[f32; N]],
    out: &mut [[f32; 3]],
) -> usize {
    #[cfg(target_arch = "x86_64")]
    if (INTERLEAVED_FROM..=crate::MAX_WAVELENGTHS).contains(&N) && crate::simd::allowed!(Portable) {
        return crate::simd::sse2::mat_vec_batch(weights, samples, out);
    }
    // Read only on x86-64 at those sizes: elsewhere the caller converts every pixel.
    let _ = (weights, samples, out);
    0
}
