//! A pixel's samples light by light, as the interleaved (`*_batch`) loops read them: a folded
//! set's pixel, `[f32; N]`, is one light; a light-group set's, `[[f32; N]; L]`, is L. A leaf, so
//! that the x86-64 loops and the portable ones (`planar::portable`) read it without importing
//! each other.

#![forbid(unsafe_code)]

/// One pixel's samples, `L` lights of `N` each.
pub(crate) trait Lights<const N: usize, const L: usize>: Copy {
    /// The samples light by light.
    fn lights(&self) -> &[[f32; N]; L];

    /// Every sample of `pixels`, pixel by pixel, light by light: pixel p's sample i of light l
    /// at `(p · L + l) · N + i` (the x86-64 loops read a group's pixels in whole vectors).
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    fn flatten(pixels: &[Self]) -> &[f32];
}

impl<const N: usize> Lights<N, 1> for [f32; N] {
    #[inline(always)]
    fn lights(&self) -> &[[f32; N]; 1] {
        core::array::from_ref(self)
    }

    #[inline(always)]
    fn flatten(pixels: &[Self]) -> &[f32] {
        pixels.as_flattened()
    }
}

impl<const N: usize, const L: usize> Lights<N, L> for [[f32; N]; L] {
    #[inline(always)]
    fn lights(&self) -> &[[f32; N]; L] {
        self
    }

    #[inline(always)]
    fn flatten(pixels: &[Self]) -> &[f32] {
        pixels.as_flattened().as_flattened()
    }
}
