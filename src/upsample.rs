//! RGB materials at a set's wavelengths: [`Upsampling`], a baked map from linear display RGB to
//! node reflectances, and its per-pixel and batch paths.

#![forbid(unsafe_code)]

use crate::model::bits::same_f32_bits;
use crate::model::error::{check_length, planar_pixels};
use crate::{Display, Error, FoldedSet, LengthOf, Samples};

mod round_trip;

pub use round_trip::RoundTrip;

/// The 16-bit code of a node value of 1 in an [`Upsampling`]'s table: value = code / 65535.
pub const UPSAMPLING_CODE_ONE: u16 = u16::MAX;

/// The reference light of an upsampling for a set for radiances, whose weights hold no light:
/// CIE illuminant D65, the white of the displays' RGB (the generator's
/// `RADIANCE_REFERENCE_LIGHT`; `tests/upsampling.rs` holds the two to the same name).
const RADIANCE_REFERENCE_LIGHT: &str = "D65";

/// Whether `x` can be a measured figure: finite and non-negative.
const fn is_figure(x: f32) -> bool {
    x.is_finite() && x >= 0.0
}

/// An upsampling baked for one folded set, and so for its display: linear RGB of that display,
/// white-balanced under the set's reference light, to the set's N node reflectances. The
/// upsampling holds its [`FoldedSet`] ([`set`](Self::set)), so the display whose RGB it takes,
/// the wavelengths of its node values and the reference light are the set's, by type: no
/// upsampling can be paired with another set's display or light.
///
/// Build time fits a least-squares map on measured reflectances, then moves each point of a
/// `grid`³ lattice of the RGB cube to the nearest node values in [0, 1] that the set encodes
/// back to that RGB (or, where node values in [0, 1] cannot reach it, to the nearest colour
/// they reach, in CIELAB). [`reflectance`](Self::reflectance) interpolates the lattice
/// tetrahedrally. What follows from that, each property asserted by `tests/upsampling.rs`:
///
/// - **Bounded**: every output is a convex combination of four table entries, so every node
///   value is in [0, 1], for any input.
/// - **White, black, greys**: RGB (1, 1, 1) gives 1 at every node, (0, 0, 0) gives 0, and a grey
///   (g, g, g) gives the same value at every node (a flat spectrum): the grey diagonal is an edge
///   of every tetrahedron it crosses, and the table holds greys exactly.
/// - **Round trip**: the set's weights under the reference light take the output back to the
///   input RGB wherever node values in [0, 1] reach it: inside a cell whose corners are all
///   reachable by the interpolation alone, up to the table's 16-bit rounding
///   ([`max_round_trip_delta_e00`](Self::max_round_trip_delta_e00)); in a cell at the edge of
///   what the set reaches by the [`RoundTrip`] correction. Where no node values in [0, 1] reach
///   the colour, the output gives the nearest colour they reach, in CIELAB linearised at the
///   requested colour.
/// - **Continuous**: no node value changes by more than
///   [`lipschitz`](Self::lipschitz)` · max(|Δr|, |Δg|, |Δb|)` between two inputs outside the
///   edge cells; the correction is continuous too, with the larger constants
///   `docs/upsampling.md` states per set (measured).
///
/// For a set with a light folded in, the RGB is the surface's colour under that light and the
/// node values feed the set directly. For a set for radiances, the RGB is the surface's colour
/// under D65 and the renderer multiplies the node values by its own light's samples.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Upsampling<const N: usize> {
    // Private: every upsampling, the baked ones too, is made by `new` (and `with_measured`).
    // The three figures are NaN where only `new` made it (not measured; their accessors say
    // `None`).
    /// The folded set whose node values it gives: for reflectances under a light, or for
    /// radiances (never a sensor's readings).
    set: FoldedSet<N>,
    lipschitz: f32,
    max_round_trip_delta_e00: f32,
    reachable_share: f32,
    /// Points per axis, at least 2.
    grid: usize,
    /// `grid³` entries, index `(r · grid + g) · grid + b`, codes of
    /// [`UPSAMPLING_CODE_ONE`]ths.
    table: &'static [[u16; N]],
    round_trip: Option<RoundTrip<N>>,
}

impl<const N: usize> Upsampling<N> {
    /// An upsampling of your own (the baked ones are in
    /// [`tables::upsampling`](crate::tables::upsampling)) for the folded set `set`, which gives
    /// it the display whose linear RGB it takes, the wavelengths of its node values and its
    /// reference light: a table of `grid³` entries (index `(r · grid + g) · grid + b`, node
    /// values in 65535ths) and, if the edge cells are to be corrected, a [`RoundTrip`]. Its
    /// measured figures ([`lipschitz`](Self::lipschitz),
    /// [`max_round_trip_delta_e00`](Self::max_round_trip_delta_e00),
    /// [`reachable_share`](Self::reachable_share)) are `None`: only the build measures them.
    ///
    /// Errors, never a panic, usable in consts: [`Error::UpsamplingReadings`] for a set for a
    /// sensor's readings ([`Samples::Readings`]: its samples are channel readings, not
    /// values at wavelengths); [`Error::UpsamplingTable`] unless `grid ≥ 2` and
    /// `table.len() == grid³`; [`Error::UpsamplingRoundTrip`] for a round trip whose
    /// [`rgb_to_xyz`](RoundTrip::rgb_to_xyz) is not the set's display's, bit for bit.
    ///
    /// ```
    /// use spectral_quadrature::tables::folded::KQ_C_4_SRGB;
    /// use spectral_quadrature::Upsampling;
    /// // A 2³ table: black at (0, 0, 0), white everywhere else.
    /// static TABLE: [[u16; 4]; 8] = {
    ///     let mut t = [[u16::MAX; 4]; 8];
    ///     t[0] = [0; 4];
    ///     t
    /// };
    /// let up = Upsampling::new(KQ_C_4_SRGB, 2, &TABLE, None).unwrap();
    /// assert_eq!(up.display().name(), "sRGB");
    /// assert_eq!(up.light(), "C");
    /// assert_eq!(up.reflectance([1.0; 3]), [1.0; 4]);
    /// ```
    pub const fn new(
        set: FoldedSet<N>,
        grid: usize,
        table: &'static [[u16; N]],
        round_trip: Option<RoundTrip<N>>,
    ) -> Result<Self, Error> {
        if let Samples::Readings { .. } = set.samples() {
            return Err(Error::UpsamplingReadings);
        }
        let refused = Err(Error::UpsamplingTable {
            grid,
            entries: table.len(),
        });
        let Some(sq) = grid.checked_mul(grid) else {
            return refused;
        };
        let Some(cube) = sq.checked_mul(grid) else {
            return refused;
        };
        if grid < 2 || table.len() != cube {
            return refused;
        }
        if let Some(rt) = &round_trip {
            let to_xyz = set.display_ref().rgb_to_xyz();
            let mut r = 0;
            while r < 3 {
                if !same_f32_bits(&rt.rgb_to_xyz[r], &to_xyz[r]) {
                    return Err(Error::UpsamplingRoundTrip);
                }
                r += 1;
            }
        }
        Ok(Upsampling {
            set,
            lipschitz: f32::NAN,
            max_round_trip_delta_e00: f32::NAN,
            reachable_share: f32::NAN,
            grid,
            table,
            round_trip,
        })
    }

    /// The same upsampling with the figures the build measured of it
    /// ([`lipschitz`](Self::lipschitz),
    /// [`max_round_trip_delta_e00`](Self::max_round_trip_delta_e00),
    /// [`reachable_share`](Self::reachable_share)), as the baked ones carry them. Checked, never
    /// a panic, usable in consts: [`Error::UpsamplingFigures`] unless each is finite and
    /// non-negative and the share at most 1.
    ///
    /// ```
    /// use spectral_quadrature::tables::upsampling::KQ_C_4_SRGB as BAKED;
    /// use spectral_quadrature::Upsampling;
    /// let made = Upsampling::new(BAKED.set(), BAKED.grid(), BAKED.table(), BAKED.round_trip()).unwrap();
    /// assert_eq!(made.lipschitz(), None);
    /// let [l, d, s] = [BAKED.lipschitz(), BAKED.max_round_trip_delta_e00(), BAKED.reachable_share()].map(Option::unwrap);
    /// assert_eq!(made.with_measured(l, d, s), Ok(BAKED));
    /// assert!(made.with_measured(l, d, 1.5).is_err());
    /// ```
    pub const fn with_measured(
        self,
        lipschitz: f32,
        max_round_trip_delta_e00: f32,
        reachable_share: f32,
    ) -> Result<Self, Error> {
        if !(is_figure(lipschitz)
            && is_figure(max_round_trip_delta_e00)
            && is_figure(reachable_share)
            && reachable_share <= 1.0)
        {
            return Err(Error::UpsamplingFigures);
        }
        Ok(Upsampling {
            lipschitz,
            max_round_trip_delta_e00,
            reachable_share,
            ..self
        })
    }

    /// The folded set whose node values it gives (`tables::folded::KQ_C_8_SRGB` for
    /// `tables::upsampling::KQ_C_8_SRGB`): its weights take the node values to linear RGB of
    /// [`display`](Self::display).
    pub const fn set(&self) -> FoldedSet<N> {
        self.set
    }

    /// The display whose linear RGB it takes: the set's.
    pub const fn display(&self) -> Display {
        self.set.display()
    }

    /// The reference light, under which the RGB is white-balanced: the set's folded light
    /// ([`Samples::Reflectance`]), or `"D65"` for a set for radiances.
    pub const fn light(&self) -> &'static str {
        match self.set.samples() {
            Samples::Reflectance { light } => light,
            _ => RADIANCE_REFERENCE_LIGHT,
        }
    }

    /// The set's wavelengths in nm: the order of the node values.
    pub const fn wavelengths_nm(&self) -> [f32; N] {
        self.set.wavelengths_nm()
    }

    /// A Lipschitz constant of [`interpolate`](Self::interpolate) (and of
    /// [`reflectance`](Self::reflectance) outside the edge cells) from the max norm of the RGB
    /// change to the largest change of a node value, computed from the table at build time;
    /// `None` for an upsampling made by [`new`](Self::new).
    pub const fn lipschitz(&self) -> Option<f32> {
        measured(self.lipschitz)
    }

    /// The largest CIEDE2000 difference between a reachable grid point and the colour the set
    /// gives its table entry (the table's 16-bit rounding); `None` for an upsampling made by
    /// [`new`](Self::new).
    pub const fn max_round_trip_delta_e00(&self) -> Option<f32> {
        measured(self.max_round_trip_delta_e00)
    }

    /// The share of the grid's points that node values in [0, 1] reach; `None` for an
    /// upsampling made by [`new`](Self::new).
    pub const fn reachable_share(&self) -> Option<f32> {
        measured(self.reachable_share)
    }

    /// The set's encoding, with which [`reflectance`](Self::reflectance) restores the round
    /// trip in the cells at the edge of what the set reaches; `None`: the interpolation alone.
    pub const fn round_trip(&self) -> Option<RoundTrip<N>> {
        self.round_trip
    }

    /// Points per axis of the table.
    pub const fn grid(&self) -> usize {
        self.grid
    }

    /// The table: `grid³` entries of N codes, node value = code / 65535.
    pub const fn table(&self) -> &'static [[u16; N]] {
        self.table
    }

    /// The words a shader reads: the codes in table order, two to a `u32`, the first of each
    /// pair in the low half (the last word padded with 0); then, with a [`RoundTrip`], its
    /// edge cells' words and, as f32 bits, its weights (row by row), RGB → XYZ (row by row)
    /// and per-channel rounding. Upload them to the storage buffer `<SET>_<DISPLAY>_CODES`
    /// that the shader functions `<set>_<display>_reflectance` and `_interpolate` read
    /// (`tables::upsampling::<SET>_<DISPLAY>_WGSL`, `_GLSL`).
    pub fn shader_words(&self) -> impl Iterator<Item = u32> + '_ {
        let codes = ShaderPairs(self.table.iter().flatten());
        let rt = self.round_trip.as_ref();
        let edge = rt.into_iter().flat_map(|rt| rt.edge_cells.iter().copied());
        let floats = rt.into_iter().flat_map(|rt| {
            rt.weights
                .iter()
                .flatten()
                .chain(rt.rgb_to_xyz.iter().flatten())
                .chain(rt.rounding.iter())
                .map(|v| v.to_bits())
        });
        codes.chain(edge).chain(floats)
    }

    /// The node reflectances of a linear, white-balanced RGB colour, each in [0, 1].
    ///
    /// Each channel is clamped to [0, 1] first: a negative or NaN channel counts as 0, one
    /// above 1 (or +∞) as 1, so any input gives node values in [0, 1] and nothing panics.
    /// (Reflectances do not exceed 1; scale HDR colours down before, and the result up after,
    /// if a renderer needs them.) Subnormal channels are used as they are.
    ///
    /// The table's interpolation ([`interpolate`](Self::interpolate)), then, in a cell at the
    /// edge of what the set reaches and only where the colour's residual exceeds the table's
    /// rounding, the [`RoundTrip`] correction: the node values move to the nearest (Euclidean)
    /// ones in [0, 1] that the set encodes back to the colour, or, where none do, to those
    /// that give the nearest colour they can reach in CIELAB linearised at the requested colour
    /// (the display's white as reference white).
    ///
    /// Cost: the interpolation, and one bit test; in an edge cell, 3·N multiply-adds for the
    /// residual, and where it is not the rounding, a small active-set solve (at most 3·N + 3
    /// steps, each a few Gram-Schmidt factorisations of at most three columns;
    /// `docs/upsampling.md` measures it). No f64, no allocation.
    #[inline]
    pub fn reflectance(&self, rgb: [f32; 3]) -> [f32; N] {
        let (mut r, p, cell) = self.interpolate_at(rgb);
        if let Some(rt) = &self.round_trip {
            if rt.is_edge(cell) {
                rt.correct(p, &mut r);
            }
        }
        r
    }

    /// The table's tetrahedral interpolation alone: [`reflectance`](Self::reflectance) without
    /// the correction in the edge cells. Bounded, white, black and greys as `reflectance`, with
    /// the Lipschitz constant [`lipschitz`](Self::lipschitz); round trip exact (up to the
    /// table's rounding) wherever the cell's corners are reachable.
    ///
    /// Cost: three clamps and a cell lookup, three compares to pick the tetrahedron, then four
    /// table entries weighted and summed: 4·N loads and multiply-adds.
    #[inline]
    pub fn interpolate(&self, rgb: [f32; 3]) -> [f32; N] {
        self.interpolate_at(rgb).0
    }

    /// The interpolation, the clamped colour and the index of its cell (as
    /// [`RoundTrip::edge_cells`]).
    #[inline]
    fn interpolate_at(&self, rgb: [f32; 3]) -> ([f32; N], [f32; 3], usize) {
        let g = self.grid;
        let cells = (g - 1) as f32;
        let mut cell = [0usize; 3];
        let mut frac = [0.0f32; 3];
        let mut p = [0.0f32; 3];
        for c in 0..3 {
            // NaN fails both comparisons and becomes 0.
            let v = if rgb[c] > 0.0 { rgb[c].min(1.0) } else { 0.0 };
            p[c] = v;
            let x = v * cells;
            // x ≥ 0, so the cast truncates to the cell below; x = cells is the last cell's top.
            let i = (x as usize).min(g - 2);
            cell[c] = i;
            frac[c] = x - i as f32;
        }
        let cell_index = (cell[0] * (g - 1) + cell[1]) * (g - 1) + cell[2];
        let strides = [g * g, g, 1];
        let [fr, fg, fb] = frac;
        // The Kuhn tetrahedron: the axes in decreasing order of the position in the cell.
        let (a, b, c) = if fr >= fg {
            if fg >= fb {
                (0, 1, 2)
            } else if fr >= fb {
                (0, 2, 1)
            } else {
                (2, 0, 1)
            }
        } else if fr >= fb {
            (1, 0, 2)
        } else if fg >= fb {
            (1, 2, 0)
        } else {
            (2, 1, 0)
        };
        let base = (cell[0] * g + cell[1]) * g + cell[2];
        let i1 = base + strides[a];
        let i2 = i1 + strides[b];
        let i3 = i2 + strides[c];
        let w0 = 1.0 - frac[a];
        let w1 = frac[a] - frac[b];
        let w2 = frac[b] - frac[c];
        let w3 = frac[c];
        // `new` and the baked tables hold grid³ entries, so the indices are in range; `get`
        // keeps the function free of panics whatever the compiler can prove.
        let (Some(v0), Some(v1), Some(v2), Some(v3)) = (
            self.table.get(base),
            self.table.get(i1),
            self.table.get(i2),
            self.table.get(i3),
        ) else {
            return ([0.0; N], p, cell_index);
        };
        let scale = 1.0 / UPSAMPLING_CODE_ONE as f32;
        let r = core::array::from_fn(|n| {
            let acc = w0 * f32::from(v0[n])
                + w1 * f32::from(v1[n])
                + w2 * f32::from(v2[n])
                + w3 * f32::from(v3[n]);
            (acc * scale).clamp(0.0, 1.0)
        });
        (r, p, cell_index)
    }

    /// [`reflectance`](Self::reflectance) for interleaved pixels: `out[p] = reflectance(rgb[p])`,
    /// the node values of pixel p as one `[f32; N]` (the layout a renderer that shades pixel by
    /// pixel reads). The same values as `reflectance` on each pixel, bit for bit: it calls it.
    ///
    /// Input handling as [`reflectance`](Self::reflectance): any input (NaN, ±Inf, negative,
    /// huge, subnormal) gives node values in [0, 1]; never panics, allocates nothing.
    ///
    /// Errors with [`Error::LengthMismatch`] (and writes nothing) unless
    /// `rgb.len() == out.len()`: [`LengthOf::Output`], `expected` `rgb.len()`, `got`
    /// `out.len()`.
    ///
    /// ```
    /// use spectral_quadrature::tables::upsampling::KQ_C_4_SRGB as UP;
    /// let rgb = [[0.8f32, 0.2, 0.1], [0.5, 0.5, 0.5]];
    /// let mut out = [[0.0f32; 4]; 2];
    /// UP.reflectance_batch(&rgb, &mut out).unwrap();
    /// assert_eq!(out[0], UP.reflectance(rgb[0]));
    /// ```
    pub fn reflectance_batch(&self, rgb: &[[f32; 3]], out: &mut [[f32; N]]) -> Result<(), Error> {
        check_length(LengthOf::Output, rgb.len(), out.len())?;
        for (o, p) in out.iter_mut().zip(rgb) {
            *o = self.reflectance(*p);
        }
        Ok(())
    }

    /// [`reflectance`](Self::reflectance) from RGB planes to node planes: `rgb[c][p]` is channel
    /// c (R, G, B) of pixel p, and `out[i][p]` receives pixel p's value at
    /// [`wavelengths_nm`](Self::wavelengths_nm)`[i]`: the planes
    /// [`FoldedSet::linear_rgb_planar`](crate::FoldedSet::linear_rgb_planar) and
    /// [`FoldedSet::encode_u8_planar`](crate::FoldedSet::encode_u8_planar) take (multiplied by
    /// the light's samples first, for a set for radiances). The same values as `reflectance` on
    /// each pixel, bit for bit.
    ///
    /// Input handling as [`reflectance`](Self::reflectance); never panics, allocates nothing.
    ///
    /// Errors with [`Error::LengthMismatch`] (and writes nothing) unless every plane of `rgb`
    /// and `out` has the length of `rgb[0]` (`expected`), at the first that differs:
    /// [`LengthOf::InputPlane`] for a plane of `rgb`, [`LengthOf::OutputPlane`] for one of
    /// `out`. With N = 0 there is nothing to write and only the RGB planes are checked.
    ///
    /// ```
    /// use spectral_quadrature::tables::upsampling::KQ_C_4_SRGB as UP;
    /// let (r, g, b) = ([0.8f32, 0.5], [0.2f32, 0.5], [0.1f32, 0.5]);
    /// let mut n = [[0.0f32; 2]; 4];
    /// let [n0, n1, n2, n3] = &mut n;
    /// UP.reflectance_planar([&r, &g, &b], [n0, n1, n2, n3]).unwrap();
    /// assert_eq!(n.map(|plane| plane[0]), UP.reflectance([0.8, 0.2, 0.1]));
    /// ```
    pub fn reflectance_planar(&self, rgb: [&[f32]; 3], out: [&mut [f32]; N]) -> Result<(), Error> {
        let mut lengths = [0; N];
        for (len, plane) in lengths.iter_mut().zip(&out) {
            *len = plane.len();
        }
        let pixels = planar_pixels(rgb.map(|c| c.len()), LengthOf::OutputPlane, &lengths)?;
        let mut out = out;
        for p in 0..pixels {
            let px = [rgb[0][p], rgb[1][p], rgb[2][p]];
            for (plane, v) in out.iter_mut().zip(self.reflectance(px)) {
                plane[p] = v;
            }
        }
        Ok(())
    }

    /// [`reflectance`](Self::reflectance) from interleaved RGB pixels (an RGB texture's layout)
    /// to node planes, `out[i][p]` as for [`reflectance_planar`](Self::reflectance_planar): an
    /// RGB texture feeds the planar encoders without a transpose of your own. The same values as
    /// `reflectance` on each pixel, bit for bit.
    ///
    /// Input handling as [`reflectance`](Self::reflectance); never panics, allocates nothing.
    ///
    /// Errors with [`Error::LengthMismatch`] (and writes nothing) unless every plane of `out`
    /// has `rgb.len()` values: [`LengthOf::OutputPlane`], `expected` `rgb.len()`, `got` the
    /// first length that differs.
    ///
    /// ```
    /// use spectral_quadrature::tables::upsampling::KQ_C_4_SRGB as UP;
    /// let rgb = [[0.8f32, 0.2, 0.1], [0.5, 0.5, 0.5]];
    /// let mut n = [[0.0f32; 2]; 4];
    /// let [n0, n1, n2, n3] = &mut n;
    /// UP.reflectance_interleaved_to_planar(&rgb, [n0, n1, n2, n3]).unwrap();
    /// assert_eq!(n.map(|plane| plane[1]), UP.reflectance(rgb[1]));
    /// ```
    pub fn reflectance_interleaved_to_planar(
        &self,
        rgb: &[[f32; 3]],
        out: [&mut [f32]; N],
    ) -> Result<(), Error> {
        let mut lengths = [0; N];
        for (len, plane) in lengths.iter_mut().zip(&out) {
            *len = plane.len();
        }
        planar_pixels([rgb.len()], LengthOf::OutputPlane, &lengths)?;
        let mut out = out;
        for (p, px) in rgb.iter().enumerate() {
            for (plane, v) in out.iter_mut().zip(self.reflectance(*px)) {
                plane[p] = v;
            }
        }
        Ok(())
    }
}

/// A build-time figure, `None` where it was not measured (NaN).
const fn measured(v: f32) -> Option<f32> {
    if v.is_nan() {
        None
    } else {
        Some(v)
    }
}

/// Pairs of codes as words, low half first; a lone last code is padded with 0.
struct ShaderPairs<I>(I);

impl<'a, I: Iterator<Item = &'a u16>> Iterator for ShaderPairs<I> {
    type Item = u32;
    fn next(&mut self) -> Option<u32> {
        let lo = u32::from(*self.0.next()?);
        let hi = self.0.next().map_or(0, |&v| u32::from(v));
        Some(lo | (hi << 16))
    }
}
