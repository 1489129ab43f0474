//! The Planckian locus in CIE 1960 (u, v) with the derivation's observer, on which the
//! correlated colour temperature (CCT) and Duv are defined, and the table of locus points the
//! runtime's `PlanckianLocus::cct` interpolates.
//!
//! The locus is Planck's law integrated against the observer's x̄ȳz̄ at 1 nm over CIE 015's
//! range, 360-830 nm, whatever range the derivation integrates colours over (380-770 nm by
//! default): CCT and Duv have a standard definition, and a user compares them with other
//! instruments and software. Where the observer's table starts later or ends sooner (the CIE
//! 2015 tables start at 390 nm), its own table clipped to 360-830 nm (`standard_range_nm`).
//! The second radiation constant is CIE 015's (c₂ = 1.4388 × 10⁻² m·K). The locus is
//! parametrised by the reciprocal temperature in mired, μ = 10⁶ / T, in which it is smooth up to
//! T = ∞ (μ = 0).
//!
//! The CCT of a chromaticity is the temperature of the nearest point of the locus in (u, v), and
//! Duv its distance, positive above the locus (toward green) and negative below (toward
//! magenta), as CIE 015 and ANSI C78.377 define them. The runtime's tests find that point in f64
//! on this locus ([`PlanckianLocus::uv_and_tangent`]) by scanning it and solving for the foot of
//! the perpendicular (the zero of the distance's derivative) by false position: the reference
//! the runtime is tested against (`tests/cct.rs`).

use std::vec::Vec;

use super::observer::Observer;
use crate::base::error::Error;

/// Planck's second radiation constant as CIE 015 gives it, in nm·K (1.4388 × 10⁻² m·K).
pub(crate) const C2_NM_K: f64 = 1.4388e7;

/// CIE 015's range of integration for colorimetry, nm: the Planckian locus's (and so CCT's and
/// Duv's) whatever the derivation's range.
pub(crate) const CIE_015_RANGE_NM: [f64; 2] = [360.0, 830.0];

/// The range the standard locus of `observer` is integrated over: [`CIE_015_RANGE_NM`] clipped
/// to the observer's table (390-830 nm for the CIE 2015 observers, whose tables start at
/// 390 nm; 360-830 nm for CIE 1931 2° and CIE 1964 10°).
pub(crate) fn standard_range_nm(observer: &Observer) -> [f64; 2] {
    let [lo, hi] = CIE_015_RANGE_NM;
    let first = observer.wavelengths.first().copied().unwrap_or(lo);
    let last = observer.wavelengths.last().copied().unwrap_or(hi);
    [lo.max(first), hi.min(last)]
}

/// The locus table's ends in mired: 10 (100 000 K) to 1000 (1000 K).
pub(crate) const TABLE_MIRED: [f64; 2] = [10.0, 1000.0];

/// How far (in u, v) the cubic Hermite interpolation between two table nodes may stray from the
/// locus: about the rounding of u and v to f32 (half a unit in the last place of 0.2-0.4 is
/// 0.7-1.5 × 10⁻⁸), so that the table's interpolation adds no more error to Duv than its storage
/// in f32 does.
pub(crate) const TABLE_TOLERANCE_UV: f64 = 5e-9;

/// How far (in mired) the interpolation may move the foot of the perpendicular from a point up
/// to 0.05 from the locus (the largest |Duv| with a CCT): its error in position plus 0.05 times
/// its error in direction (radians), over the locus's speed |dL/dμ|. Off the locus the
/// direction matters: a tangent off by ε rad moves the foot by 0.05 ε. The bound is what the
/// f32 rounding of (u, v) alone moves the foot where the locus is slowest (3 × 10⁻⁸ over
/// 2.3 × 10⁻⁴ per mired, at 1000 K): a tighter one doubles the table and changes the runtime's
/// largest error by a tenth (`tests/cct.rs` prints it).
pub(crate) const TABLE_TOLERANCE_MIRED: f64 = 1e-4;

/// The largest |Duv| the table is made for.
const TABLE_MAX_DUV: f64 = 0.05;

/// One node of the locus table: the point and its tangent at μ mired.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct LocusNode {
    /// μ = 10⁶ / T, mired.
    pub mired: f64,
    /// CIE 1960 (u, v) of the blackbody at μ.
    pub uv: [f64; 2],
    /// d(u, v)/dμ at μ, per mired.
    pub tangent: [f64; 2],
}

impl LocusNode {
    /// The node's unit tangent in 1.14 fixed point (16 384 is 1) and `L · T̂` with (u, v) in 16
    /// fractional bits times that tangent (so 30 fractional bits): what the runtime's binary
    /// search computes the slope's sign from in integers, `(P · T̂) − L · T̂` for a point P in
    /// 16 fractional bits.
    pub(crate) fn fixed_point(&self) -> ([i16; 2], i32) {
        let norm = self.tangent[0].hypot(self.tangent[1]);
        let unit = self.tangent.map(|t| (t / norm * 16_384.0).round() as i16);
        let along =
            self.uv[0] * 65_536.0 * f64::from(unit[0]) + self.uv[1] * 65_536.0 * f64::from(unit[1]);
        (unit, along.round() as i32)
    }
}

/// The Planckian locus of one observer over one range of wavelengths: the standard one
/// ([`PlanckianLocus::standard`], CIE 015's 360-830 nm) for CCT and Duv, which the runtime's
/// table bakes; another range only to measure what the range changes
/// ([`PlanckianLocus::new`]).
#[derive(Debug, Clone, PartialEq)]
pub struct PlanckianLocus {
    /// x̄ȳz̄ · dλ on the 1 nm grid.
    weights: [Vec<f64>; 3],
    /// λ⁻⁵ and c₂ / (10⁶ λ) at each wavelength: what every evaluation needs (the build script
    /// runs this at opt-level 0, where a call to `powi` costs).
    per_wavelength: Vec<[f64; 2]>,
}

impl PlanckianLocus {
    /// The standard locus of `observer`, the one CCT and Duv are defined on: Planck's law
    /// against its x̄ȳz̄ at 1 nm over `standard_range_nm` (CIE 015's 360-830 nm, clipped to the
    /// observer's table), whatever range the derivation integrates colours over. The runtime's
    /// `tables::PLANCKIAN_LOCUS` is this locus's table of nodes. Errors: the observer's
    /// table is not at 1 nm (or a divisor of it) on whole nm.
    pub fn standard(observer: &Observer) -> Result<PlanckianLocus, Error> {
        PlanckianLocus::new(observer, standard_range_nm(observer))
    }

    /// The locus with `observer` over `range_nm` at 1 nm: not CIE 015's unless the range is
    /// `standard_range_nm` ([`standard`](Self::standard)); another range serves to measure
    /// what the range changes. Errors: the range is not on the observer's 1 nm table.
    pub fn new(observer: &Observer, range_nm: [f64; 2]) -> Result<PlanckianLocus, Error> {
        let full = observer.full_integration(range_nm, 1.0)?;
        let per_wavelength = full
            .wavelengths_nm
            .iter()
            .map(|&nm| [nm.powi(-5), C2_NM_K * 1e-6 / nm])
            .collect();
        Ok(PlanckianLocus {
            weights: full.xyz_weights,
            per_wavelength,
        })
    }

    /// XYZ of the blackbody at μ mired (μ ≥ 0), up to a constant factor: each wavelength's
    /// radiance is μ λ⁻⁵ / (exp(c₂ μ / (10⁶ λ)) − 1), finite down to μ = 0 (T = ∞). Also its
    /// derivative with respect to μ.
    fn xyz_and_derivative(&self, mired: f64) -> ([f64; 3], [f64; 3]) {
        let (mut xyz, mut dxyz) = ([0.0; 3], [0.0; 3]);
        let [wx, wy, wz] = &self.weights;
        for (i, &[l5, a]) in self.per_wavelength.iter().enumerate() {
            // x = c₂ μ / (10⁶ λ); q = μ λ⁻⁵ / expm1(x) and dq/dμ = λ⁻⁵ (1 − x eˣ / expm1(x)) /
            // expm1(x), both with finite limits at x = 0: λ⁻⁵ / (c₂ / (10⁶ λ)) and −λ⁻⁵ / 2.
            let x = a * mired;
            let (q, dq) = if x < 1e-6 {
                (l5 / a, -0.5 * l5)
            } else {
                let em1 = x.exp_m1();
                (l5 * mired / em1, l5 * (1.0 - x * (em1 + 1.0) / em1) / em1)
            };
            let w = [wx[i], wy[i], wz[i]];
            for c in 0..3 {
                xyz[c] += w[c] * q;
                dxyz[c] += w[c] * dq;
            }
        }
        (xyz, dxyz)
    }

    /// CIE 1960 (u, v) of the blackbody at μ mired (μ ≥ 0), and its derivative d(u, v)/dμ.
    pub fn uv_and_tangent(&self, mired: f64) -> ([f64; 2], [f64; 2]) {
        let ([x, y, z], [dx, dy, dz]) = self.xyz_and_derivative(mired);
        let d = x + 15.0 * y + 3.0 * z;
        let dd = dx + 15.0 * dy + 3.0 * dz;
        let uv = [4.0 * x / d, 6.0 * y / d];
        let tangent = [
            4.0 * (dx * d - x * dd) / (d * d),
            6.0 * (dy * d - y * dd) / (d * d),
        ];
        (uv, tangent)
    }

    /// The nodes of the runtime's locus table over [`TABLE_MIRED`]: 16 segments equal in
    /// log μ, each halved until the cubic Hermite interpolation between its ends (points and
    /// tangents) stays within [`TABLE_TOLERANCE_UV`] of the locus and moves the foot of a
    /// perpendicular by at most `TABLE_TOLERANCE_MIRED`, at the quarters of the segment.
    pub(crate) fn table(&self) -> Vec<LocusNode> {
        let node = |mired: f64| {
            let (uv, tangent) = self.uv_and_tangent(mired);
            LocusNode { mired, uv, tangent }
        };
        let [lo, hi] = TABLE_MIRED;
        let mut nodes: Vec<LocusNode> = (0..=16)
            .map(|i| node(lo * (hi / lo).powf(i as f64 / 16.0)))
            .collect();
        let mut i = 0;
        while i + 1 < nodes.len() {
            let (a, b) = (nodes[i], nodes[i + 1]);
            // The quarters: to leading order a cubic Hermite's error in position goes as
            // t²(1 − t)², largest at the half, and in direction as t(1 − t)(1 − 2t), largest at
            // 0.21 and 0.79, where it is 1.03 times its value at the quarters.
            let too_far = [0.25, 0.5, 0.75].into_iter().any(|t| {
                let mired = a.mired + t * (b.mired - a.mired);
                let ([u, v], [tu, tv]) = self.uv_and_tangent(mired);
                let p = hermite(&a, &b, t);
                let [du, dv] = hermite_tangent(&a, &b, t);
                let position = (p[0] - u).hypot(p[1] - v);
                let speed = tu.hypot(tv);
                let direction = (du * tv - dv * tu).abs() / (du.hypot(dv) * speed);
                position > TABLE_TOLERANCE_UV
                    || (position + TABLE_MAX_DUV * direction) / speed > TABLE_TOLERANCE_MIRED
            });
            if too_far {
                nodes.insert(i + 1, node(0.5 * (a.mired + b.mired)));
            } else {
                i += 1;
            }
        }
        nodes
    }
}

/// The derivative d(u, v)/dμ of [`hermite`] at t.
pub(crate) fn hermite_tangent(a: &LocusNode, b: &LocusNode, t: f64) -> [f64; 2] {
    let h = b.mired - a.mired;
    let t2 = t * t;
    let (d00, d10, d01, d11) = (
        6.0 * t2 - 6.0 * t,
        3.0 * t2 - 4.0 * t + 1.0,
        -6.0 * t2 + 6.0 * t,
        3.0 * t2 - 2.0 * t,
    );
    [0, 1].map(|c| (d00 * a.uv[c] + d01 * b.uv[c]) / h + d10 * a.tangent[c] + d11 * b.tangent[c])
}

/// The cubic Hermite interpolant between two nodes at t in [0, 1] (t = 0 at `a`).
pub(crate) fn hermite(a: &LocusNode, b: &LocusNode, t: f64) -> [f64; 2] {
    let h = b.mired - a.mired;
    let (t2, t3) = (t * t, t * t * t);
    let (h00, h10, h01, h11) = (
        2.0 * t3 - 3.0 * t2 + 1.0,
        t3 - 2.0 * t2 + t,
        -2.0 * t3 + 3.0 * t2,
        t3 - t2,
    );
    [0, 1].map(|c| h00 * a.uv[c] + h10 * h * a.tangent[c] + h01 * b.uv[c] + h11 * h * b.tangent[c])
}
