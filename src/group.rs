//! Light groups: one set of N nodes shared by L lights, with one folded weight matrix per light,
//! so that a renderer that keeps one accumulator per light ("light groups") gets the colour of
//! their sum: `rgb = Σ_l W_l · s_l`. Per pixel, batch (interleaved) and planar, each light's
//! product computed as [`FoldedSet`]'s per-pixel functions compute it, and the sum encoded by
//! the set's [`Display`] as [`FoldedSet`]'s encoders encode. The batch and planar forms run the
//! folded sets' vector loops (`simd`, `planar::portable`), which take the planes and weights
//! light by light. Nothing allocates; a length mismatch is an [`Error`], checked before any
//! output is written.

#![forbid(unsafe_code)]

use crate::model::bits::same_f32_bits;
use crate::model::error::{check_length, planar_pixels};
use crate::pixel::{mat_vec, mat_vec_for_encoding};
use crate::planar::portable::{
    encode_srgb8_batch_portable, encode_srgb8_planar_portable, linear_planar_portable, VECTOR_UNITS,
};
use crate::{
    Display, Error, FoldedSet, GamutMapping, LengthOf, LightGroupProblem, Rgb, Samples,
    MAX_WAVELENGTHS,
};

/// N wavelengths shared by L lights, and one 3×N weight matrix (display RGB, like a
/// [`FoldedSet`]'s) per light: the colour of a pixel lit by several lights of different
/// spectra, from one accumulator of N node values per light.
///
/// A [`FoldedSet`] for reflectances has its light folded into the weights, so it is right only
/// under that light. A renderer whose pixels gather light from several lights keeps, per
/// pixel, one accumulator of N values per light (a *light group*): the path throughput at the
/// N nodes, the reflectances multiplied along the path, added into the accumulator of the
/// light the path ends on, without that light's spectrum (which is in that light's weights).
/// This set sums the groups through their own weights:
///
/// `rgb = Σ_l weights[l] · groups[l]`, light 0 first.
///
/// Light l alone is [`member(l)`](Self::member), the [`FoldedSet`] of its weights; with one
/// light (L = 1) every function gives that folded set's bits and bytes exactly. The cost per
/// pixel is L · 3 · N multiply-adds and 3 · (L − 1) additions, then one encoding: L times a
/// folded set's product, one encoder. Each light's contribution is computed exactly as its
/// folded set computes it, so it has that set's accuracy under that light; the lights' sum
/// adds L − 1 roundings (see [`linear_rgb`](Self::linear_rgb), and docs/light-groups.md for
/// when a folded set, a light-group set or a set for radiances is the right tool).
///
/// Build one from folded sets that share their wavelengths and display
/// ([`from_members`](Self::from_members)), or from the arrays
/// ([`new`](Self::new)). Here the second light's weights are made up; a scene bakes real ones.
///
/// ```
/// use spectral_quadrature::tables::folded::KQ_C_8_SRGB as C;
/// use spectral_quadrature::{FoldedSet, GamutMapping, LightGroupSet, Samples};
///
/// // A second light at the same nodes: its own weights, the same wavelengths and display.
/// let warm = C.weights().map(|row| {
///     let mut i = 0.0;
///     row.map(|w| {
///         i += 1.0;
///         w * (0.5 + 0.1 * i)
///     })
/// });
/// let a = FoldedSet::new(C.wavelengths_nm(), warm, Samples::Reflectance { light: "A" }, C.display())
///     .unwrap();
/// let groups = LightGroupSet::from_members([C, a]).unwrap();
/// assert_eq!(groups.lights(), ["C", "A"]);
///
/// // A path tracer's pixel: one accumulator of the N node values per light. Each path
/// // multiplies the reflectances at the N nodes along its bounces, and adds the product (times
/// // the path's geometry and sampling weight, the same at every node) into the accumulator of
/// // the light it ends on. The light's spectrum is NOT multiplied in: it is folded into that
/// // light's weights.
/// let mut acc = [[0.0f32; 8]; 2];
/// let wall = [0.3f32, 0.35, 0.4, 0.45, 0.5, 0.55, 0.6, 0.6]; // reflectance at the nodes
/// let floor = [0.6f32, 0.55, 0.5, 0.45, 0.4, 0.35, 0.3, 0.3];
/// let paths = [(0, 0.7f32, &[&wall][..]), (1, 0.4, &[&wall, &floor][..])];
/// for (light, weight, bounces) in paths {
///     let mut throughput = [weight; 8];
///     for r in bounces {
///         for i in 0..8 {
///             throughput[i] *= r[i];
///         }
///     }
///     for i in 0..8 {
///         acc[light][i] += throughput[i];
///     }
/// }
///
/// let rgb = groups.linear_rgb(&acc);
/// // The sum of each light's folded set on its own accumulator (to f32 rounding: here the
/// // same bits, the sum being computed in that order).
/// let (c, w) = (C.linear_rgb(&acc[0]), a.linear_rgb(&acc[1]));
/// assert_eq!(rgb, [c[0] + w[0], c[1] + w[1], c[2] + w[2]]);
/// let px = groups.encode_u8(GamutMapping::Clip, &acc);
/// assert_eq!(px, C.display().encode_u8(GamutMapping::Clip, rgb));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LightGroupSet<const N: usize, const L: usize> {
    // Private: every set, the baked ones too, is made by `new` or `from_members`.
    wavelengths_nm: [f32; N],
    weights: [[[f32; N]; 3]; L],
    lights: [&'static str; L],
    display: Display,
}

impl<const N: usize, const L: usize> LightGroupSet<N, L> {
    /// The number of wavelengths (nodes), N.
    pub const LEN: usize = N;

    /// The number of lights, L.
    pub const LIGHTS: usize = L;

    /// A light-group set of your own: wavelengths in nm, `weights[light][channel][i]` (rows R,
    /// G, B of `display`'s linear RGB per unit sample, one matrix per light, each as a
    /// [`FoldedSet`]'s), the lights' names, and the display whose transfer function encodes the
    /// output. Checked, never a panic, usable in consts:
    ///
    /// - at least one light, else [`Error::LightGroup`] with
    ///   [`LightGroupProblem::NoLights`] (and `light` 0);
    /// - every wavelength finite, positive and above the one before, else
    ///   [`Error::InvalidWavelength`] at the first that is not (as [`FoldedSet::new`] for
    ///   reflectances);
    /// - every weight finite, else [`Error::LightGroup`] with the light and
    ///   [`LightGroupProblem::InvalidWeight`] with the channel and index, at the first in light,
    ///   channel and index order.
    pub const fn new(
        wavelengths_nm: [f32; N],
        weights: [[[f32; N]; 3]; L],
        lights: [&'static str; L],
        display: Display,
    ) -> Result<Self, Error> {
        if L == 0 {
            return Err(Error::LightGroup {
                light: 0,
                problem: LightGroupProblem::NoLights,
            });
        }
        let mut l = 0;
        while l < L {
            // Each light's matrix checked as a folded set for reflectances under that light.
            let checked = FoldedSet::new(
                wavelengths_nm,
                weights[l],
                Samples::Reflectance { light: lights[l] },
                display,
            );
            match checked {
                Ok(_) => {}
                Err(Error::InvalidWeight { row, index }) => {
                    return Err(Error::LightGroup {
                        light: l,
                        problem: LightGroupProblem::InvalidWeight {
                            channel: Rgb::ALL[row % 3],
                            index,
                        },
                    })
                }
                Err(e) => return Err(e),
            }
            l += 1;
        }
        Ok(LightGroupSet {
            wavelengths_nm,
            weights,
            lights,
            display,
        })
    }

    /// The set of L folded sets, one per light, that share their wavelengths and display:
    /// member l's weights become light l's, its light (`samples()`) light l's name. Checked,
    /// never a panic, usable in consts; else [`Error::LightGroup`] with the first member at
    /// fault (in index order) and the problem:
    ///
    /// - [`LightGroupProblem::NoLights`] with L = 0;
    /// - [`LightGroupProblem::NotReflectance`] where a member's samples are not
    ///   [`Samples::Reflectance`] (radiances, or a sensor's readings);
    /// - [`LightGroupProblem::Wavelengths`] where its wavelengths are not member 0's, bit for
    ///   bit;
    /// - [`LightGroupProblem::Display`] where its display is not member 0's: every field the
    ///   same bits (name, chromaticities, matrices, transfer function and its tables).
    ///
    /// Members' wavelengths and weights were checked by [`FoldedSet::new`] (or baked), so no
    /// other check is needed.
    pub const fn from_members(members: [FoldedSet<N>; L]) -> Result<Self, Error> {
        if L == 0 {
            return Err(Error::LightGroup {
                light: 0,
                problem: LightGroupProblem::NoLights,
            });
        }
        let first = &members[0];
        let mut weights = [[[0.0f32; N]; 3]; L];
        let mut lights = [""; L];
        let mut l = 0;
        while l < L {
            let m = &members[l];
            let problem = match m.samples() {
                Samples::Reflectance { light } => {
                    lights[l] = light;
                    if !same_f32_bits(m.wavelengths_ref(), first.wavelengths_ref()) {
                        Some(LightGroupProblem::Wavelengths)
                    } else if !m.display_ref().same_bits(first.display_ref()) {
                        Some(LightGroupProblem::Display)
                    } else {
                        None
                    }
                }
                _ => Some(LightGroupProblem::NotReflectance),
            };
            if let Some(problem) = problem {
                return Err(Error::LightGroup { light: l, problem });
            }
            weights[l] = *m.weights_ref();
            l += 1;
        }
        Ok(LightGroupSet {
            wavelengths_nm: first.wavelengths_nm(),
            weights,
            lights,
            display: first.display(),
        })
    }

    /// Wavelengths in nm, ascending and distinct: the order of each group's samples.
    pub const fn wavelengths_nm(&self) -> [f32; N] {
        self.wavelengths_nm
    }

    /// `weights[light][channel][i]`, rows R, G, B of each light.
    pub const fn weights(&self) -> [[[f32; N]; 3]; L] {
        self.weights
    }

    /// The weights by reference, for the crate's tests.
    #[cfg(test)]
    pub(crate) const fn weights_ref(&self) -> &[[[f32; N]; 3]; L] {
        &self.weights
    }

    /// The display by reference, for the crate's tests.
    #[cfg(test)]
    pub(crate) const fn display_ref(&self) -> &Display {
        &self.display
    }

    /// The lights' names, in the order of the groups.
    pub const fn lights(&self) -> [&'static str; L] {
        self.lights
    }

    /// The display the weights were folded for: its transfer function encodes the output.
    pub const fn display(&self) -> Display {
        self.display
    }

    /// Light l alone: the [`FoldedSet`] of its weights, for reflectances under it
    /// ([`Samples::Reflectance`] with its name), with the set's wavelengths and display; `None`
    /// for l ≥ L. [`from_members`](Self::from_members) gives back its members.
    pub const fn member(&self, l: usize) -> Option<FoldedSet<N>> {
        if l >= L {
            return None;
        }
        Some(FoldedSet::from_checked(
            self.wavelengths_nm,
            self.weights[l],
            Samples::Reflectance {
                light: self.lights[l],
            },
            self.display,
        ))
    }

    /// Linear RGB from one pixel's light groups: `groups[l][i]` is light l's accumulator at
    /// [`wavelengths_nm`](Self::wavelengths_nm)`[i]`.
    ///
    /// Exactly `m_0 + m_1 + … + m_{L−1}` in f32, added in that order, where `m_l` is
    /// [`member(l)`](Self::member)`.linear_rgb(&groups[l])` (the same f32 operations): with
    /// L = 1, that member's bits. L · 3 · N multiply-adds and 3 · (L − 1) additions.
    ///
    /// Never panics. IEEE arithmetic, as [`FoldedSet::linear_rgb`], on the sum: a NaN in any
    /// group makes every channel NaN; an infinite sample makes every channel ±Inf or NaN (NaN
    /// where its weight is 0, or where infinities of both signs meet, within a light or
    /// between lights); subnormal and negative samples are used as they are; products or sums
    /// beyond `f32::MAX` overflow to ±Inf, the sum of lights included. With N = 0 it is
    /// `[0.0, 0.0, 0.0]`.
    ///
    /// # Accuracy
    /// Each channel within [`f32_budget`](crate::f32_budget)`(L · N, Σ_l Σ_i |w_li · s_li|)`
    /// of the exact sum with the f64 weights: each light's product within its folded set's
    /// budget, `(N + 1) ε Σ_i |w_li · s_li|`, and the L − 1 additions of lights ½ ε each of at
    /// most the whole absolute sum, together below `(L · N + 1) ε` of it for N ≥ 1.
    #[inline]
    pub fn linear_rgb(&self, groups: &[[f32; N]; L]) -> [f32; 3] {
        let mut rgb = [0.0f32; 3];
        for (l, (w, s)) in self.weights.iter().zip(groups).enumerate() {
            let c = mat_vec(w, s);
            rgb = if l == 0 { c } else { add(rgb, c) };
        }
        rgb
    }

    /// One pixel's light groups → gamut-mapped, encoded 8-bit RGB with the set's
    /// [`display`](Self::display): the bytes of
    /// `self.display().encode_u8(mapping, self.linear_rgb(groups))`
    /// ([`Display::encode_u8`]). NaN anywhere in the sum → black; ±Inf and huge channels clip
    /// to 0 or 255; never panics. With N = 0, the display's encoding of black.
    ///
    /// Light 0's product starts each channel's sum from its first product instead of 0.0, as
    /// [`FoldedSet::encode_u8`] does, so with L = 1 this is that member's `encode_u8` exactly;
    /// the value differs from [`linear_rgb`](Self::linear_rgb)'s only where it is an exact
    /// zero (−0.0 for +0.0, and both encode to 0). On x86-64, the sRGB curve with `Clip` runs
    /// with the three channels in one SSE2 register, as [`FoldedSet::encode_u8`] does: the
    /// same sums up to the sign of an exact zero, so the same bytes.
    #[inline]
    pub fn encode_u8(&self, mapping: GamutMapping, groups: &[[f32; N]; L]) -> [u8; 3] {
        // x86-64: each light's product and the encoder with the channels in the lanes of one
        // SSE2 register, as `FoldedSet::encode_u8` (the same bytes; see `simd`).
        #[cfg(target_arch = "x86_64")]
        if self.display.is_srgb_clip(mapping) {
            return crate::simd::sse2::encode_srgb8_groups(&self.weights, groups);
        }
        self.display
            .encode_u8(mapping, self.linear_rgb_for_encoding(groups))
    }

    /// As [`encode_u8`](Self::encode_u8), 16 bits: the values of
    /// `self.display().encode_u16(mapping, self.linear_rgb(groups))`
    /// ([`Display::encode_u16`]), so with L = 1 that member's
    /// [`FoldedSet::encode_u16`] exactly. NaN anywhere in the sum → black; never panics.
    #[inline]
    pub fn encode_u16(&self, mapping: GamutMapping, groups: &[[f32; N]; L]) -> [u16; 3] {
        self.display.encode_u16(mapping, self.linear_rgb(groups))
    }

    /// [`linear_rgb`](Self::linear_rgb) with light 0's sums started from their first product,
    /// as [`FoldedSet::encode_u8`] starts them.
    #[inline]
    fn linear_rgb_for_encoding(&self, groups: &[[f32; N]; L]) -> [f32; 3] {
        let mut rgb = [0.0f32; 3];
        for (l, (w, s)) in self.weights.iter().zip(groups).enumerate() {
            rgb = if l == 0 {
                mat_vec_for_encoding(w, s)
            } else {
                add(rgb, mat_vec(w, s))
            };
        }
        rgb
    }

    /// [`linear_rgb`](Self::linear_rgb) for every pixel: `out[p] = linear_rgb(&groups[p])`,
    /// the same bits.
    ///
    /// Errors with [`Error::LengthMismatch`] (and writes nothing) unless
    /// `groups.len() == out.len()`: [`LengthOf::Output`], `expected` the input's pixels, `got`
    /// the output's.
    pub fn linear_rgb_batch(
        &self,
        groups: &[[[f32; N]; L]],
        out: &mut [[f32; 3]],
    ) -> Result<(), Error> {
        check_length(LengthOf::Output, groups.len(), out.len())?;
        for (o, g) in out.iter_mut().zip(groups) {
            *o = self.linear_rgb(g);
        }
        Ok(())
    }

    /// [`encode_u8`](Self::encode_u8) for every pixel, the same bytes (NaN anywhere in a
    /// pixel's sum → black).
    ///
    /// With the sRGB curve and [`GamutMapping::Clip`], on a target with f32 vector units and
    /// for L · N up to [`MAX_WAVELENGTHS`], the loops of
    /// [`FoldedSet::encode_u8_batch`] run, with each light's product added in light order: on
    /// x86-64 CPUs with AVX2 (detected at run time, once) eight pixels go through each register,
    /// elsewhere (SSE2, NEON, WebAssembly SIMD) chunks of 16 pixels are transposed into planes
    /// on the stack and encoded in loops the compiler vectorizes. Every way computes each
    /// light's product and the lights' sum with the same f32 operations in the same order as
    /// [`encode_u8`](Self::encode_u8), so it gives its bytes, bit for bit. Other curves and
    /// mappings, larger L · N, and targets without vector units (microcontrollers) go pixel by
    /// pixel.
    ///
    /// Errors with [`Error::LengthMismatch`] (and writes nothing) unless the lengths agree
    /// ([`LengthOf::Output`]).
    pub fn encode_u8_batch(
        &self,
        mapping: GamutMapping,
        groups: &[[[f32; N]; L]],
        out: &mut [[u8; 3]],
    ) -> Result<(), Error> {
        check_length(LengthOf::Output, groups.len(), out.len())?;
        let srgb_clip = self.display.is_srgb_clip(mapping);
        let vector_units = VECTOR_UNITS && crate::simd::allowed!(Portable);
        if vector_units && srgb_clip && vector_loops::<N, L>() {
            // The AVX2 loop where the CPU has it (the same bytes; see `simd`), then the
            // portable loop for the rest.
            let done =
                crate::simd::encode_srgb8_batch(&self.weights, groups, out.as_flattened_mut());
            encode_srgb8_batch_portable(&self.weights, &groups[done..], &mut out[done..]);
            return Ok(());
        }
        // Pixel by pixel: other curves and mappings, larger sets, targets without vector units.
        if srgb_clip && vector_loops::<N, L>() {
            crate::simd::note!(Scalar, false);
        }
        for (o, g) in out.iter_mut().zip(groups) {
            *o = self.encode_u8(mapping, g);
        }
        Ok(())
    }

    /// [`encode_u16`](Self::encode_u16) for every pixel, the same values (NaN anywhere in a
    /// pixel's sum → black).
    ///
    /// Errors with [`Error::LengthMismatch`] (and writes nothing) unless the lengths agree
    /// ([`LengthOf::Output`]).
    pub fn encode_u16_batch(
        &self,
        mapping: GamutMapping,
        groups: &[[[f32; N]; L]],
        out: &mut [[u16; 3]],
    ) -> Result<(), Error> {
        check_length(LengthOf::Output, groups.len(), out.len())?;
        for (o, g) in out.iter_mut().zip(groups) {
            *o = self.encode_u16(mapping, g);
        }
        Ok(())
    }

    /// [`linear_rgb`](Self::linear_rgb) for light groups in planes: `planes[l][i][p]` is pixel
    /// p's accumulator of light l at [`wavelengths_nm`](Self::wavelengths_nm)`[i]`, and
    /// `out[c][p]` receives channel c (R, G, B) of pixel p. As
    /// [`FoldedSet::linear_rgb_planar`], with one array of N planes per light.
    ///
    /// For L · N up to [`MAX_WAVELENGTHS`], the loops of [`FoldedSet::linear_rgb_planar`] run
    /// with every light's planes (each light's product summed from 0.0, the lights added in
    /// order): on x86-64 CPUs with AVX-512 (F, BW and VBMI) sixteen pixels per register, with
    /// AVX2 eight (detected at run time, once), elsewhere chunks of 16 pixels that the compiler
    /// vectorizes for the target; larger sets go pixel by pixel. Every way gives
    /// [`linear_rgb`](Self::linear_rgb)'s bits on every pixel (NaN payloads aside), and its
    /// input handling. Never panics. With AVX-512 and at least 2²⁰ pixels the output is written
    /// with non-temporal stores, as [`FoldedSet::linear_rgb_planar`] says.
    ///
    /// Errors with [`Error::LengthMismatch`] (and writes nothing) unless every plane and every
    /// output has the same length, at the first that differs from `planes[0][0]`'s
    /// (`expected`): [`LengthOf::InputPlane`] for another plane, in light then wavelength order,
    /// [`LengthOf::OutputPlane`] for a plane of `out`. With N = 0 there are no planes: the number of pixels is the length of
    /// `out[0]`, and every pixel is `[0.0, 0.0, 0.0]`.
    pub fn linear_rgb_planar(
        &self,
        planes: [[&[f32]; N]; L],
        out: [&mut [f32]; 3],
    ) -> Result<(), Error> {
        if !vector_loops::<N, L>() {
            return to_planes(planes, out, |groups| self.linear_rgb(groups));
        }
        let pixels = planar_pixels(
            plane_lengths(&planes),
            LengthOf::OutputPlane,
            &[out[0].len(), out[1].len(), out[2].len()],
        )?;
        let planes = planes.map(|light| light.map(|plane| &plane[..pixels]));
        let [r, g, b] = out;
        let (r, g, b) = (&mut r[..pixels], &mut g[..pixels], &mut b[..pixels]);
        // The AVX-512 or AVX2 loop where the CPU has one (the same bits; see `simd`), then the
        // rest in the portable one.
        let done = crate::simd::linear_planar(&self.weights, planes, [&mut *r, &mut *g, &mut *b]);
        linear_planar_portable(
            &self.weights,
            planes.map(|light| light.map(|plane| &plane[done..])),
            [&mut r[done..], &mut g[done..], &mut b[done..]],
        );
        Ok(())
    }

    /// Light groups in planes (as for [`linear_rgb_planar`](Self::linear_rgb_planar)) →
    /// gamut-mapped, encoded 8-bit RGB with the set's [`display`](Self::display), interleaved:
    /// `out[p] = [r, g, b]`. As [`FoldedSet::encode_u8_planar_to_interleaved`], with one array
    /// of N planes per light.
    ///
    /// With the sRGB curve and [`GamutMapping::Clip`], on a target with f32 vector units and
    /// for L · N up to [`MAX_WAVELENGTHS`], the loops of
    /// [`FoldedSet::encode_u8_planar_to_interleaved`] run with every light's planes, each
    /// light's product added in light order: on x86-64 CPUs with AVX-512 (F, BW and VBMI)
    /// sixteen pixels per register, the code values from the polynomial and the pixels it
    /// hands back encoded by [`encode_u8`](Self::encode_u8); with AVX2 eight pixels per
    /// register (detected at run time, once); elsewhere chunks of 16 pixels that the compiler
    /// vectorizes. Otherwise (other curves and mappings, larger sets, no vector units) pixel by
    /// pixel through [`encode_u8`](Self::encode_u8). Every way gives its bytes on every pixel,
    /// and its input handling (NaN anywhere in a pixel's sum → black; ±Inf and huge channels
    /// clip; never panics).
    ///
    /// Errors with [`Error::LengthMismatch`] (and writes nothing) unless every plane and `out`
    /// have the same length, reported as for [`linear_rgb_planar`](Self::linear_rgb_planar)
    /// ([`LengthOf::Output`] for `out`; with N = 0, `out.len()` is the number of pixels).
    pub fn encode_u8_planar_to_interleaved(
        &self,
        mapping: GamutMapping,
        planes: [[&[f32]; N]; L],
        out: &mut [[u8; 3]],
    ) -> Result<(), Error> {
        let srgb_clip = self.display.is_srgb_clip(mapping);
        let vector_units = VECTOR_UNITS && crate::simd::allowed!(Portable);
        if !(vector_units && srgb_clip && vector_loops::<N, L>()) {
            if srgb_clip && vector_loops::<N, L>() {
                // No vector units: one pixel at a time.
                crate::simd::note!(Scalar, false);
            }
            return to_interleaved(planes, out, |groups| self.encode_u8(mapping, groups));
        }
        let pixels = planar_pixels(plane_lengths(&planes), LengthOf::Output, &[out.len()])?;
        let planes = planes.map(|light| light.map(|plane| &plane[..pixels]));
        let out = &mut out[..pixels];
        // The AVX-512 or AVX2 loop where the CPU has one (the same bytes; see `simd`), then the
        // rest in the portable one.
        let done = crate::simd::encode_srgb8_planar(&self.weights, planes, out.as_flattened_mut());
        encode_srgb8_planar_portable(
            &self.weights,
            planes.map(|light| light.map(|plane| &plane[done..])),
            &mut out[done..],
        );
        Ok(())
    }

    /// [`encode_u8_planar_to_interleaved`](Self::encode_u8_planar_to_interleaved) with the
    /// output in planes too: `out[c][p]` receives channel c (R, G, B) of pixel p. The same
    /// loops, run on chunks of 64 pixels through a small buffer on the stack (192 bytes), as
    /// [`FoldedSet::encode_u8_planar`]: the same bytes as [`encode_u8`](Self::encode_u8) on
    /// every pixel, the same input handling.
    ///
    /// Errors with [`Error::LengthMismatch`] (and writes nothing) unless every plane of
    /// `planes` and of `out` has the same length, reported as for
    /// [`linear_rgb_planar`](Self::linear_rgb_planar).
    pub fn encode_u8_planar(
        &self,
        mapping: GamutMapping,
        planes: [[&[f32]; N]; L],
        out: [&mut [u8]; 3],
    ) -> Result<(), Error> {
        let pixels = planar_pixels(
            plane_lengths(&planes),
            LengthOf::OutputPlane,
            &[out[0].len(), out[1].len(), out[2].len()],
        )?;
        let [r, g, b] = out;
        let mut buf = [[0u8; 3]; CHUNK];
        let mut start = 0;
        while start < pixels {
            let end = pixels.min(start + CHUNK);
            let chunk = &mut buf[..end - start];
            let planes = planes.map(|light| light.map(|plane| &plane[start..end]));
            self.encode_u8_planar_to_interleaved(mapping, planes, chunk)?;
            for (k, px) in chunk.iter().enumerate() {
                [r[start + k], g[start + k], b[start + k]] = *px;
            }
            start = end;
        }
        Ok(())
    }

    /// Light groups in planes (as for [`linear_rgb_planar`](Self::linear_rgb_planar)) →
    /// gamut-mapped, encoded 16-bit RGB, interleaved: `out[p]` is
    /// [`encode_u16`](Self::encode_u16) of pixel p's groups, the same values and input
    /// handling. As [`FoldedSet::encode_u16_planar_to_interleaved`].
    ///
    /// Errors with [`Error::LengthMismatch`] (and writes nothing) unless every plane and `out`
    /// have the same length, reported as for [`linear_rgb_planar`](Self::linear_rgb_planar)
    /// ([`LengthOf::Output`] for `out`).
    pub fn encode_u16_planar_to_interleaved(
        &self,
        mapping: GamutMapping,
        planes: [[&[f32]; N]; L],
        out: &mut [[u16; 3]],
    ) -> Result<(), Error> {
        to_interleaved(planes, out, |groups| self.encode_u16(mapping, groups))
    }

    /// [`encode_u16_planar_to_interleaved`](Self::encode_u16_planar_to_interleaved) with the
    /// output in planes: `out[c][p]` receives channel c (R, G, B) of pixel p. The same values
    /// as [`encode_u16`](Self::encode_u16) on every pixel, the same input handling.
    ///
    /// Errors with [`Error::LengthMismatch`] (and writes nothing) unless every plane of
    /// `planes` and of `out` has the same length, reported as for
    /// [`linear_rgb_planar`](Self::linear_rgb_planar).
    pub fn encode_u16_planar(
        &self,
        mapping: GamutMapping,
        planes: [[&[f32]; N]; L],
        out: [&mut [u16]; 3],
    ) -> Result<(), Error> {
        to_planes(planes, out, |groups| self.encode_u16(mapping, groups))
    }
}

/// Pixels per chunk of [`LightGroupSet::encode_u8_planar`]: its stack buffer holds 3 · 64
/// bytes.
const CHUNK: usize = 64;

/// Whether the batch and planar functions run the vector loops for N wavelengths and L lights:
/// for L · N up to [`MAX_WAVELENGTHS`], the folded sets' limit (the loops keep arrays of L · N
/// planes and samples on the stack); larger sets go pixel by pixel.
const fn vector_loops<const N: usize, const L: usize>() -> bool {
    matches!(N.checked_mul(L), Some(planes) if planes <= MAX_WAVELENGTHS)
}

/// `a + b` per channel, in f32.
#[inline(always)]
fn add(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// The planar functions' loop, output in planes: `out[c][p]` is channel c of `pixel` of pixel
/// p's groups, after [`planar_pixels`] (nothing written on a mismatch).
#[inline(always)]
fn to_planes<T, const N: usize, const L: usize>(
    planes: [[&[f32]; N]; L],
    out: [&mut [T]; 3],
    pixel: impl Fn(&[[f32; N]; L]) -> [T; 3],
) -> Result<(), Error> {
    let pixels = planar_pixels(
        plane_lengths(&planes),
        LengthOf::OutputPlane,
        &[out[0].len(), out[1].len(), out[2].len()],
    )?;
    let planes = planes.map(|light| light.map(|plane| &plane[..pixels]));
    let [r, g, b] = out;
    let (r, g, b) = (&mut r[..pixels], &mut g[..pixels], &mut b[..pixels]);
    for p in 0..pixels {
        [r[p], g[p], b[p]] = pixel(&gather(&planes, p));
    }
    Ok(())
}

/// The planar functions' loop, output interleaved: `out[p]` is `pixel` of pixel p's groups,
/// after [`planar_pixels`] (nothing written on a mismatch).
#[inline(always)]
fn to_interleaved<T, const N: usize, const L: usize>(
    planes: [[&[f32]; N]; L],
    out: &mut [[T; 3]],
    pixel: impl Fn(&[[f32; N]; L]) -> [T; 3],
) -> Result<(), Error> {
    let pixels = planar_pixels(plane_lengths(&planes), LengthOf::Output, &[out.len()])?;
    let planes = planes.map(|light| light.map(|plane| &plane[..pixels]));
    for (p, o) in out[..pixels].iter_mut().enumerate() {
        *o = pixel(&gather(&planes, p));
    }
    Ok(())
}

/// The planes' lengths, light by light, wavelength by wavelength: the order in which
/// [`planar_pixels`] checks them.
fn plane_lengths<'a, const N: usize, const L: usize>(
    planes: &'a [[&[f32]; N]; L],
) -> impl Iterator<Item = usize> + 'a {
    planes.iter().flatten().map(|p| p.len())
}

/// Pixel p's groups from planes that each hold more than p values.
#[inline(always)]
fn gather<const N: usize, const L: usize>(planes: &[[&[f32]; N]; L], p: usize) -> [[f32; N]; L] {
    planes.map(|light| light.map(|plane| plane[p]))
}
