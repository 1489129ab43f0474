//! Correlated colour temperature (CCT) and Duv from XYZ, in f32, on a Planckian locus table
//! baked for the scene's observer.
//!
//! The method: the chromaticity in CIE 1960 (u, v); a binary search over the table's nodes for
//! the segment that holds the foot of the perpendicular from that point onto the locus (where
//! the slope (p − L)·L′ changes sign); Newton's method on that segment's cubic Hermite
//! interpolant (the nodes' points, tangents and chord) for the foot itself; the distance to it,
//! signed. The table is dense enough that interpolating it moves the foot less than the f32
//! rounding of (u, v) does, so the result is the exact CCT of the locus to about 10⁻⁴ mired, on
//! the locus and off it alike, where the usual methods (McCamy's cubic, Robertson's isotherms,
//! Ohno's triangular and parabolic solutions) trade accuracy for a smaller table.

#![forbid(unsafe_code)]

/// A correlated colour temperature and the chromaticity's distance from the Planckian locus.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Cct {
    /// The temperature of the nearest blackbody in CIE 1960 (u, v), kelvin.
    pub kelvin: f32,
    /// The signed distance from the locus in CIE 1960 (u, v): positive above it (toward green),
    /// negative below (toward magenta), as CIE 015 and ANSI C78.377 define Duv.
    pub duv: f32,
}

/// The largest |Duv| for which [`PlanckianLocus::cct`] gives a temperature: 0.05, the limit
/// CIE 015 sets on the concept. Farther from the locus a correlated colour temperature means
/// nothing, and the function returns `None`.
pub const MAX_DUV: f32 = 0.05;

/// The stated accuracy of [`PlanckianLocus::cct`]'s temperature, in mired (μ = 10⁶ / T), against
/// the standard definition: for every XYZ whose CCT the table covers (1000-100 000 K for the
/// baked tables) with |Duv| ≤ [`MAX_DUV`], the result's μ is within `CCT_MAX_ERROR_MIRED` of the
/// exact CCT's, the nearest point of the Planckian locus as CIE 015 defines it (Planck's law with
/// c₂ = 1.4388 × 10⁻² m·K against the CIE 1931 2° functions, 1 nm over 360-830 nm) found in f64
/// for the same f32 XYZ. `tests/cct.rs` measures at most 4.1 × 10⁻⁴ (a dense sweep, and 200 000
/// random points once), and checks the locus itself against Planck's law summed there from the
/// data file (blackbodies from 1000 to 100 000 K: at most 1.8 × 10⁻⁴ mired from their
/// temperature) and against colour-science's CCT of the CIE illuminants (at most
/// 1.1 × 10⁻⁴ mired). In kelvin, ΔT ≤ T² · 10⁻⁶ · `CCT_MAX_ERROR_MIRED`: 0.0005 K at 1000 K,
/// 0.02 K at 6500 K, 0.2 K at 20 000 K. Reciprocal temperature is the natural unit: the locus
/// moves about as far in (u, v) per mired at every temperature, so the f32 rounding of (u, v),
/// a few 10⁻⁸, is about the same error in mired everywhere. With another observer the bound is
/// against that observer's locus over the same range (clipped to its table: 390-830 nm for the
/// CIE 2015 observers).
pub const CCT_MAX_ERROR_MIRED: f32 = 5e-4;

/// The stated accuracy of [`PlanckianLocus::cct`]'s Duv, absolute, against the same standard
/// locus and over the same inputs as [`CCT_MAX_ERROR_MIRED`]. `tests/cct.rs` measures at most
/// 6.9 × 10⁻⁸ against the f64 reference, 5 × 10⁻⁸ on blackbodies (whose Duv is 0) and
/// 3.2 × 10⁻⁸ against colour-science on the CIE illuminants.
pub const DUV_MAX_ERROR: f32 = 1e-7;

/// The Planckian locus as a table of points and tangents in CIE 1960 (u, v), by reciprocal
/// temperature: what [`cct`](Self::cct) interpolates. The build bakes one for the scene's
/// observer when the scene asks for it (`[extras] cct = true`; the default scene does):
/// [`tables::PLANCKIAN_LOCUS`](crate::tables).
///
/// The locus is the one CIE 015 defines: Planck's law (c₂ = 1.4388 × 10⁻² m·K) against the
/// scene's observer at 1 nm over 360-830 nm, whatever range the scene integrates its colours
/// over (380-770 nm by default): CCT and Duv are then those other instruments and software
/// give. Where the observer's table is shorter, its own table clipped to 360-830 nm (the CIE
/// 2015 tables start at 390 nm: 390-830 nm). CCT is defined with CIE 1931 2°, the default
/// observer; with another observer these are its own temperatures, consistent with the XYZ its
/// sets give. A set's XYZ is that of the scene's range, so a light's CCT from a set is that of
/// its XYZ over that range: for D65 0.85 K below its CCT over 360-830 nm
/// (docs/colour-temperature-and-calibration.md).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PlanckianLocus<const K: usize> {
    // Private: the baked table is made by `new`, which checks them; users read them through the
    // accessors of the same names.
    mired: [f32; K],
    uv: [[f32; 2]; K],
    tangent: [[f32; 2]; K],
    chord: [[f32; 2]; K],
    /// The unit tangent at each node in 1.14 fixed point (16 384 is 1): the binary search over
    /// the nodes runs in integers, where an f32 operation is a library call of a hundred
    /// instructions.
    unit_tangent_q14: [[i16; 2]; K],
    /// `L · T̂` at each node, the point in 16 fractional bits times the unit tangent above (30
    /// fractional bits): a point P (16 fractional bits) lies on the hot side of the node's
    /// isotemperature line where `P · T̂ − L · T̂ ≥ 0`.
    along_q30: [i32; K],
}

/// Half a unit in the last place of an f32 in [0.5, 1), and so the most the f32 rounding of a
/// point's coordinate below 1 (CIE 1960 u and v are) moves it: what [`PlanckianLocus::new`]
/// allows for in `L · T̂`.
const POINT_ROUNDING: f64 = 1.0 / 33_554_432.0;

/// The chord's allowance per unit of (1 + |chord|) in [`PlanckianLocus::new`]: half a unit in
/// the last place of each of the two points (2⁻²⁵ each, for coordinates below 1) and of the
/// chord (2⁻²⁴ · |chord| at most), all three rounded to f32 separately from their f64 values.
const CHORD_ROUNDING: f64 = 1.0 / 16_777_216.0;

/// How far the squared length of a unit tangent in 1.14 fixed point, `q = 16 384 · T̂ + e`, may be
/// from 16 384²: each component of `e` is at most ½, so `|q|² − 16 384² = 2 · 16 384 · (T̂ · e) +
/// |e|²` with `|T̂ · e| ≤ (|T̂_u| + |T̂_v|) / 2 ≤ √2 / 2` and `|e|² ≤ ½`: within
/// 16 384 · √2 + ½ = 23 170.98.
const UNIT_LENGTH_ROUNDING: i64 = 23_171;

/// The cross product of a unit tangent in 1.14 fixed point with the f32 tangent, per unit of
/// |t_u| + |t_v|, that the components' rounding (½ each) and the tangent's own f32 rounding
/// (16 384 · 2⁻²⁴ = 2⁻¹⁰ relative) allow, with 2⁻¹⁰ more for the f64 arithmetic: ½ + 2⁻⁹.
const DIRECTION_ROUNDING: f64 = 0.5 + 1.0 / 512.0;

/// Whether the f32 chord `c` is the difference `d` of the f32 points (in f64, exact), to within
/// their rounding ([`CHORD_ROUNDING`]).
const fn chord_near(c: f32, d: f64) -> bool {
    let c = c as f64;
    c.is_finite() && (c - d).abs() <= CHORD_ROUNDING * (1.0 + c.abs())
}

/// At most how many Newton steps refine the foot of the perpendicular on a segment, from where
/// the linear interpolation of the slope between its ends vanishes. Newton's method converges
/// quadratically: two steps reach f32 rounding on every point `tests/cct.rs` tries (a dense
/// sweep, and 200 000 random points once; 2000 in each run), and a third changes none of its
/// largest errors by more than a tenth.
const NEWTON_STEPS: usize = 2;

/// A Newton step smaller than this (in t, the segment's parameter) ends the refinement: the
/// next step would be about its square (times the segment's curvature term, of order 1), below
/// 10⁻⁷ of a segment of at most 16 mired, 2 × 10⁻⁶ mired. Most points near the locus stop
/// after one step.
const NEWTON_DONE: f32 = 3e-4;

/// CIE 1960 (u, v) from XYZ: u = 4X / (X + 15Y + 3Z), v = 6Y / (X + 15Y + 3Z), in f32.
///
/// `None` where a component is NaN or infinite, or the denominator is not positive (all zero,
/// or negative components that outweigh the rest). Huge components (up to `f32::MAX`) and tiny
/// ones (subnormals) are scaled by a power of two first, which changes nothing in (u, v) but
/// keeps the denominator from overflowing or losing precision. Negative components are used as
/// they are. Never panics.
pub fn uv_from_xyz(xyz: [f32; 3]) -> Option<[f32; 2]> {
    // The largest biased exponent among the three, from the bits (no float comparison, which is
    // a library call on FPU-less cores): 255 is NaN or infinity.
    let exponent = |v: f32| (v.to_bits() >> 23) & 0xff;
    let e = exponent(xyz[0]).max(exponent(xyz[1])).max(exponent(xyz[2]));
    if e == 0xff {
        return None;
    }
    // 2⁻⁶⁴ above 2¹⁰⁰ (the sum of 19 such values stays finite), 2⁶⁴ below 2⁻⁶⁰ (subnormals
    // become normal): exact scalings of all three.
    let scale = if e > 127 + 100 {
        f32::from_bits((127 - 64) << 23)
    } else if e < 127 - 60 {
        f32::from_bits((127 + 64) << 23)
    } else {
        1.0
    };
    let [x, y, z] = xyz.map(|c| c * scale);
    let d = x + 15.0 * y + 3.0 * z;
    if d <= 0.0 || d.is_nan() {
        return None;
    }
    Some([4.0 * x / d, 6.0 * y / d])
}

impl<const K: usize> PlanckianLocus<K> {
    /// A table of your own, or the one the build bakes (`tables::PLANCKIAN_LOCUS` is made by
    /// this): each node's reciprocal temperature, point, tangent and chord
    /// ([`mired`](Self::mired), [`uv`](Self::uv), [`tangent`](Self::tangent),
    /// [`chord`](Self::chord)), and the fixed-point forms the binary search reads: the unit
    /// tangent in 1.14 fixed point (16 384 is 1) and `L · T̂` with the point in 16 fractional
    /// bits times that tangent (30 fractional bits), both computed from the point and tangent
    /// before their rounding to f32 and rounded to nearest.
    ///
    /// Checked, never a panic, usable in consts:
    /// [`Error::InvalidLocus`](crate::Error::InvalidLocus) at the first node where
    ///
    /// - the reciprocal temperature is not finite and positive, or not above the one before;
    /// - a coordinate of the point is not in 0 ≤ u, v < 1, or the tangent is not finite or is
    ///   zero;
    /// - the chord is not the difference of this node's point and the next one's (`[0, 0]` at
    ///   the last node) to within the f32 rounding of the three (half a unit in the last place
    ///   of each, 2⁻²⁴ · (1 + |chord|) in all for points below 1);
    /// - the unit tangent's length squared is not 16 384² to within its components' rounding
    ///   (± ½ each: 16 384 · √2 + ½, so 23 171), it points away from the tangent, or its
    ///   direction is not the tangent's to within that rounding and the tangent's own (the
    ///   cross product within (½ + 2⁻⁹) · (|t_u| + |t_v|));
    /// - `L · T̂` is not the f32 point times the unit tangent, times 2¹⁶, to within its own
    ///   rounding and the point's (½ + (|T̂_u| + |T̂_v|) · 2¹⁶ · 2⁻²⁵ for points below 1).
    ///
    /// It computes in f64 (exactly, for these products of f32 and 15-bit integers): once per
    /// table, never per pixel.
    pub const fn new(
        mired: [f32; K],
        uv: [[f32; 2]; K],
        tangent: [[f32; 2]; K],
        chord: [[f32; 2]; K],
        unit_tangent_q14: [[i16; 2]; K],
        along_q30: [i32; K],
    ) -> Result<PlanckianLocus<K>, crate::Error> {
        let mut i = 0;
        while i < K {
            let refused = Err(crate::Error::InvalidLocus { node: i });
            let m = mired[i];
            if !(m.is_finite() && m > 0.0) || (i > 0 && m <= mired[i - 1]) {
                return refused;
            }
            let [u, v] = uv[i];
            if !(u >= 0.0 && u < 1.0 && v >= 0.0 && v < 1.0) {
                return refused;
            }
            let [tu, tv] = tangent[i];
            if !(tu.is_finite() && tv.is_finite()) || (tu == 0.0 && tv == 0.0) {
                return refused;
            }
            let [cu, cv] = chord[i];
            if i + 1 < K {
                let [nu, nv] = uv[i + 1];
                let du = nu as f64 - u as f64;
                let dv = nv as f64 - v as f64;
                if !(chord_near(cu, du) && chord_near(cv, dv)) {
                    return refused;
                }
            } else if !(cu == 0.0 && cv == 0.0) {
                return refused;
            }
            let [a, b] = unit_tangent_q14[i];
            let (a, b) = (a as i64, b as i64);
            let length = a * a + b * b - (1 << 28);
            if length > UNIT_LENGTH_ROUNDING || length < -UNIT_LENGTH_ROUNDING {
                return refused;
            }
            let (af, bf, tu, tv) = (a as f64, b as f64, tu as f64, tv as f64);
            let along_tangent = af * tu + bf * tv;
            let across = af * tv - bf * tu;
            if !(along_tangent > 0.0 && across.abs() <= DIRECTION_ROUNDING * (tu.abs() + tv.abs()))
            {
                return refused;
            }
            let exact = 65_536.0 * (u as f64 * af + v as f64 * bf);
            let bound = 0.5 + (af.abs() + bf.abs()) * 65_536.0 * POINT_ROUNDING;
            if (along_q30[i] as f64 - exact).abs() > bound {
                return refused;
            }
            i += 1;
        }
        Ok(PlanckianLocus {
            mired,
            uv,
            tangent,
            chord,
            unit_tangent_q14,
            along_q30,
        })
    }

    /// The nodes' reciprocal temperatures μ = 10⁶ / T in mired, ascending (T descending).
    ///
    /// The node accessors return references: a table holds a hundred nodes or more (111 in the
    /// baked ones), which a copy per call would move through the stack.
    pub const fn mired(&self) -> &[f32; K] {
        &self.mired
    }

    /// CIE 1960 (u, v) of the blackbody at each node.
    pub const fn uv(&self) -> &[[f32; 2]; K] {
        &self.uv
    }

    /// d(u, v)/dμ at each node, per mired.
    pub const fn tangent(&self) -> &[[f32; 2]; K] {
        &self.tangent
    }

    /// `uv[i + 1] − uv[i]`, computed before rounding (the difference of the rounded points
    /// would lose the direction of short segments), and `[0, 0]` at the last node. With the
    /// points and the tangents it gives each segment's cubic Hermite interpolant, the curve
    /// [`cct`](Self::cct) measures against: for t in 0..=1 and `h = mired[i + 1] − mired[i]`,
    /// `uv[i] + h·tangent[i]·(t − 2t² + t³) + chord[i]·(3t² − 2t³) + h·tangent[i + 1]·(t³ − t²)`.
    pub const fn chord(&self) -> &[[f32; 2]; K] {
        &self.chord
    }

    /// The temperatures the table covers, lowest first: `[10⁶ / mired[K − 1], 10⁶ / mired[0]]`
    /// (1000 K and 100 000 K for the baked tables).
    pub fn kelvin_range(&self) -> [f32; 2] {
        match (self.mired.first(), self.mired.last()) {
            (Some(&hi), Some(&lo)) => [1e6 / lo, 1e6 / hi],
            _ => [f32::NAN; 2],
        }
    }

    /// The CCT and Duv of `xyz` (any scale: only the chromaticity counts), from
    /// [`uv_from_xyz`] and [`cct_from_uv`](Self::cct_from_uv).
    ///
    /// `None` where (u, v) is not defined (a NaN or infinite component, a denominator
    /// X + 15Y + 3Z that is not positive), where the nearest point of the locus lies beyond the
    /// table's ends ([`kelvin_range`](Self::kelvin_range)), and where |Duv| > [`MAX_DUV`]. Never
    /// panics, uses no f64.
    ///
    /// # Accuracy
    /// Within [`CCT_MAX_ERROR_MIRED`] (in μ = 10⁶ / T) and [`DUV_MAX_ERROR`] of the exact CCT and Duv of
    /// the same (f32) XYZ on CIE 015's locus, for every XYZ whose exact CCT is in the table's range with
    /// |Duv| ≤ [`MAX_DUV`]. Within that bound of the table's ends or of |Duv| = 0.05, the
    /// answer may be `None` or a value just beyond them.
    ///
    /// ```
    /// use spectral_quadrature::tables::PLANCKIAN_LOCUS;
    /// // Illuminant A (2856 K on the CIE 1931 locus): X, Y, Z = 109.85, 100, 35.58.
    /// let a = PLANCKIAN_LOCUS.cct([109.85, 100.0, 35.58]).unwrap();
    /// assert!((a.kelvin - 2856.0).abs() < 2.0 && a.duv.abs() < 1e-4);
    /// // Far from the locus (a saturated green) there is no colour temperature.
    /// assert_eq!(PLANCKIAN_LOCUS.cct([0.3, 0.6, 0.1]), None);
    /// ```
    #[inline]
    pub fn cct(&self, xyz: [f32; 3]) -> Option<Cct> {
        self.cct_from_uv(uv_from_xyz(xyz)?)
    }

    /// The CCT and Duv of a chromaticity in CIE 1960 (u, v). `None` for a NaN or infinite
    /// coordinate, where the nearest point of the locus lies beyond the table's ends, and where
    /// |Duv| > [`MAX_DUV`]; accuracy as [`cct`](Self::cct). Never panics.
    pub fn cct_from_uv(&self, uv: [f32; 2]) -> Option<Cct> {
        if K < 2 {
            return None;
        }
        // The point in 16 fractional bits; outside u < 0.6, v < 0.5 (NaN among it) nothing is
        // within MAX_DUV of any locus (the CIE 1931 locus spans u 0.18-0.45, v 0.26-0.36), and
        // inside it the products below stay within i32.
        let (pu, pv) = (q16(uv[0])?, q16(uv[1])?);
        if pu >= 39_322 || pv >= 32_768 {
            return None;
        }
        // The side of node i's isotemperature line, in integers: the sign of (P − L_i) · T̂_i.
        let side = |i: usize| {
            let [a, b] = self.unit_tangent_q14[i];
            pu * i32::from(a) + pv * i32::from(b) - self.along_q30[i]
        };
        // The segment whose ends the point lies between (the slope falls through zero where the
        // distance is least), or an end segment when it lies beyond the table; the integer
        // sides are exact to about 2 × 10⁻⁵ in (u, v), so the foot may lie a little outside
        // the segment found, which the Newton steps below allow for.
        let (mut lo, mut hi) = (0, K - 1);
        if side(0) < 0 {
            hi = 1;
        } else if side(K - 1) >= 0 {
            lo = K - 2;
        }
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            if side(mid) >= 0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let slope = |i: usize| {
            (uv[0] - self.uv[i][0]) * self.tangent[i][0]
                + (uv[1] - self.uv[i][1]) * self.tangent[i][1]
        };
        let (s_lo, s_hi) = (slope(lo), slope(hi));
        // The segment's cubic in t ∈ [0, 1], relative to its first node:
        // L(t) − L(0) = c1 t + c2 t² + c3 t³, from the end points and the tangents times h.
        let h = self.mired[hi] - self.mired[lo];
        let a = self.uv[lo];
        let q = [uv[0] - a[0], uv[1] - a[1]];
        let c = |k: usize| {
            let d = self.chord[lo][k];
            let (ma, mb) = (h * self.tangent[lo][k], h * self.tangent[hi][k]);
            [ma, 3.0 * d - 2.0 * ma - mb, ma + mb - 2.0 * d]
        };
        let [cu, cv] = [c(0), c(1)];
        // Start where the slope's linear interpolation vanishes.
        let mut t = extended(s_lo / (s_lo - s_hi));
        // Newton's method on f(t) = r(t)·L′(t), r = q − (L(t) − L(0)): the foot of the
        // perpendicular. Each step leaves r moved to the new t to first order (r − Δt L′),
        // which is what the distance needs: the neglected Δt² L″ / 2 is below f32 rounding
        // once Δt is below NEWTON_DONE.
        let mut r = [0.0f32; 2];
        let mut d1 = [0.0f32; 2];
        for _ in 0..NEWTON_STEPS {
            let at = |c: [f32; 3]| ((c[2] * t + c[1]) * t + c[0]) * t;
            r = [q[0] - at(cu), q[1] - at(cv)];
            let slope = |c: [f32; 3]| (3.0 * c[2] * t + 2.0 * c[1]) * t + c[0];
            d1 = [slope(cu), slope(cv)];
            let d2 = [6.0 * cu[2] * t + 2.0 * cu[1], 6.0 * cv[2] * t + 2.0 * cv[1]];
            let f = r[0] * d1[0] + r[1] * d1[1];
            let df = r[0] * d2[0] + r[1] * d2[1] - (d1[0] * d1[0] + d1[1] * d1[1]);
            let next = extended(t - f / df);
            let dt = next - t;
            r = [r[0] - dt * d1[0], r[1] - dt * d1[1]];
            t = next;
            if dt.abs() < NEWTON_DONE {
                break;
            }
        }
        // The distance, with the sign of the side: the tangent turned anticlockwise points up.
        let distance = libm::sqrtf(r[0] * r[0] + r[1] * r[1]);
        let duv = if r[1] * d1[0] - r[0] * d1[1] < 0.0 {
            -distance
        } else {
            distance
        };
        // Beyond the table's ends (and NaN: a point no segment holds), nothing.
        let beyond = (lo == 0 && t < 0.0) || (hi == K - 1 && t > 1.0);
        if beyond || duv.is_nan() || duv.abs() > MAX_DUV {
            return None;
        }
        Some(Cct {
            kelvin: 1e6 / (self.mired[lo] + t * h),
            duv,
        })
    }
}

/// `x` clamped to the segment and a tenth beyond either end (where a foot the integer search
/// placed in the neighbouring segment may lie; the cubic extends smoothly there), and a NaN
/// (0 / 0) to 0: `f32::max` returns the number where `f32::clamp` would return the NaN.
#[allow(clippy::manual_clamp)]
fn extended(x: f32) -> f32 {
    x.max(-0.1).min(1.1)
}

/// `x` in 16 fractional bits, rounded, for 0 ≤ x < 1 (−0.0 too); `None` for negative numbers,
/// 1 and more, infinities and NaN. From the bits, with integer operations only.
fn q16(x: f32) -> Option<i32> {
    let bits = x.to_bits();
    if bits == 0x8000_0000 {
        return Some(0);
    }
    // The sign bit set, or a biased exponent of 127 or more (x ≥ 1, ∞, NaN).
    let exponent = bits >> 23;
    if exponent >= 127 {
        return None;
    }
    // x = m · 2^(e − 150) with the implicit bit (e > 0), so x · 2¹⁶ = m / 2^(134 − e).
    let mantissa = (bits & 0x007f_ffff) | if exponent > 0 { 0x0080_0000 } else { 0 };
    let shift = 134 - exponent;
    if shift > 24 {
        return Some(0);
    }
    Some(((mantissa + (1 << (shift - 1))) >> shift) as i32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tables::PLANCKIAN_LOCUS;

    /// The baked table's parts, as `PlanckianLocus::new` takes them.
    #[allow(clippy::type_complexity)]
    fn parts<const K: usize>(
        l: &PlanckianLocus<K>,
    ) -> (
        [f32; K],
        [[f32; 2]; K],
        [[f32; 2]; K],
        [[f32; 2]; K],
        [[i16; 2]; K],
        [i32; K],
    ) {
        (
            l.mired,
            l.uv,
            l.tangent,
            l.chord,
            l.unit_tangent_q14,
            l.along_q30,
        )
    }

    /// `new` gives the baked table back (the build made it with `new`), and refuses each kind of
    /// node a table cannot hold, naming the node.
    #[test]
    fn new_checks_every_node() {
        let (m, uv, t, c, q, a) = parts(&PLANCKIAN_LOCUS);
        assert_eq!(PlanckianLocus::new(m, uv, t, c, q, a), Ok(PLANCKIAN_LOCUS));
        let refused = |node| Err(crate::Error::InvalidLocus { node });
        let k = 40;
        let mut bad = m;
        bad[k] = f32::NAN;
        assert_eq!(PlanckianLocus::new(bad, uv, t, c, q, a), refused(k));
        bad[k] = m[k - 1];
        assert_eq!(PlanckianLocus::new(bad, uv, t, c, q, a), refused(k));
        // A point outside 0..1 (at node 0: elsewhere the chord before it fails first).
        let mut bad = uv;
        bad[0][1] = 1.0;
        assert_eq!(PlanckianLocus::new(m, bad, t, c, q, a), refused(0));
        bad[0][1] = -0.1;
        assert_eq!(PlanckianLocus::new(m, bad, t, c, q, a), refused(0));
        let mut bad = t;
        bad[k] = [0.0, 0.0];
        assert_eq!(PlanckianLocus::new(m, uv, bad, c, q, a), refused(k));
        // The chord of another segment, and a last chord that is not zero.
        let mut bad = c;
        bad[k] = c[k + 1];
        assert_eq!(PlanckianLocus::new(m, uv, t, bad, q, a), refused(k));
        let mut bad = c;
        bad[110] = c[109];
        assert_eq!(PlanckianLocus::new(m, uv, t, bad, q, a), refused(110));
        // A unit tangent 24 units of 16 384 too long (beyond the components' rounding), one
        // turned by 2 units (1.2e-4 rad, beyond it too), and one reversed.
        let [qu, qv] = q[k];
        let scale = |x: i16, f: f64| (f64::from(x) * f).round() as i16;
        let longer = 1.0 + 24.0 / 16_384.0;
        let mut bad = q;
        bad[k] = [scale(qu, longer), scale(qv, longer)];
        assert_eq!(PlanckianLocus::new(m, uv, t, c, bad, a), refused(k));
        let mut bad = q;
        bad[k] = if qu.abs() > qv.abs() {
            [qu, qv + 2]
        } else {
            [qu + 2, qv]
        };
        assert_eq!(PlanckianLocus::new(m, uv, t, c, bad, a), refused(k));
        let mut bad = q;
        bad[k] = [-qu, -qv];
        assert_eq!(PlanckianLocus::new(m, uv, t, c, bad, a), refused(k));
        // `L · T̂` 64 units of 2⁻³⁰ off (the bound here is about 45).
        let mut bad = a;
        bad[k] += 64;
        assert_eq!(PlanckianLocus::new(m, uv, t, c, q, bad), refused(k));
    }

    /// How much of each of `new`'s roundings the baked table uses: every node within its
    /// bounds, and each bound not looser than a few times what the table needs (so that a node
    /// a few units off fails, as `new_checks_every_node` shows).
    #[test]
    fn the_baked_table_uses_the_bounds_new_allows() {
        let l = &PLANCKIAN_LOCUS;
        let (mut length, mut direction, mut along, mut chord) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for i in 0..l.mired.len() {
            let [a, b] = l.unit_tangent_q14[i].map(f64::from);
            let [tu, tv] = l.tangent[i].map(f64::from);
            let [u, v] = l.uv[i].map(f64::from);
            length =
                length.max((a * a + b * b - 268_435_456.0).abs() / UNIT_LENGTH_ROUNDING as f64);
            direction = direction
                .max((a * tv - b * tu).abs() / (DIRECTION_ROUNDING * (tu.abs() + tv.abs())));
            let bound = 0.5 + (a.abs() + b.abs()) * 65_536.0 * POINT_ROUNDING;
            along =
                along.max((f64::from(l.along_q30[i]) - 65_536.0 * (u * a + v * b)).abs() / bound);
            if let Some(next) = l.uv.get(i + 1) {
                for (k, &end) in next.iter().enumerate() {
                    let c = f64::from(l.chord[i][k]);
                    let d = f64::from(end) - f64::from(l.uv[i][k]);
                    chord = chord.max((c - d).abs() / (CHORD_ROUNDING * (1.0 + c.abs())));
                }
            }
        }
        for (what, used) in [
            ("length", length),
            ("direction", direction),
            ("along", along),
            ("chord", chord),
        ] {
            assert!(used <= 1.0, "{what}: {used}");
            assert!(used > 0.05, "{what}: {used} of the bound");
        }
    }

    /// Empty and one-node tables answer None. Only the crate can build a table (its fields are
    /// the baked table's), so the test is here.
    #[test]
    fn empty_and_one_node_tables_answer_none() {
        let empty = PlanckianLocus::<0> {
            mired: [],
            uv: [],
            tangent: [],
            chord: [],
            unit_tangent_q14: [],
            along_q30: [],
        };
        assert_eq!(empty.cct([1.0, 1.0, 1.0]), None);
        assert!(empty.kelvin_range()[0].is_nan());
        let one = PlanckianLocus::<1> {
            mired: [PLANCKIAN_LOCUS.mired[5]],
            uv: [PLANCKIAN_LOCUS.uv[5]],
            tangent: [PLANCKIAN_LOCUS.tangent[5]],
            chord: [[0.0; 2]],
            unit_tangent_q14: [PLANCKIAN_LOCUS.unit_tangent_q14[5]],
            along_q30: [PLANCKIAN_LOCUS.along_q30[5]],
        };
        // The node's own point, on the locus (XYZ with Y = 1 from its (u, v)): the whole table
        // answers, the one-node table does not.
        let [u, v] = PLANCKIAN_LOCUS.uv[5];
        let xyz = [1.5 * u / v, 1.0, (4.0 - u - 10.0 * v) / (2.0 * v)];
        assert!(PLANCKIAN_LOCUS.cct(xyz).is_some());
        assert_eq!(one.cct(xyz), None);
        assert_eq!(one.cct_from_uv([u, v]), None);
    }
}
