//! The round trip between grid points: where interpolation leaves a colour short of what the
//! set's weights give back, a small box-constrained least-squares step moves the node values to
//! the nearest ones (Euclidean) that encode to the colour, or, where no node values in [0, 1]
//! reach it, to the nearest colour they reach in CIELAB linearised at the requested colour.

/// The set's encoding under the upsampling's reference light, and what the runtime needs to
/// restore the round trip where the table's interpolation alone misses it.
///
/// Tetrahedral interpolation round-trips exactly (up to the table's 16-bit rounding) inside a
/// cell whose eight corners the set reaches; in a cell at the edge of what the set reaches
/// ([`edge_cells`](Self::edge_cells)), [`Upsampling::reflectance`](crate::Upsampling::reflectance)
/// checks the residual `rgb − weights · r` and, where it exceeds the rounding, corrects `r`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoundTrip<const N: usize> {
    /// `rgb = weights · r`: the set's linear RGB of node reflectances under the reference light,
    /// white-balanced (each row sums to 1).
    pub weights: [[f32; N]; 3],
    /// The display's linear RGB to CIE XYZ: the metric (CIELAB, the display's white as the
    /// reference white) in which an unreachable colour's nearest reachable colour is found.
    pub rgb_to_xyz: [[f32; 3]; 3],
    /// One bit per cell of the grid, index `(r · (grid − 1) + g) · (grid − 1) + b`, bit `i % 32`
    /// of word `i / 32`: set where a corner of the cell is a colour node values in [0, 1] do
    /// not reach. A cell past the slice's end counts as set.
    pub edge_cells: &'static [u32],
    /// Per channel, the largest residual the table's rounding alone can leave: half a code
    /// times the sum of the row's absolute weights.
    pub(crate) rounding: [f32; 3],
}

/// Below this many times [`RoundTrip::rounding`] the residual is the table's rounding and the
/// values are kept; from there to [`FULL`] the correction is phased in, so that the function
/// stays continuous where it starts.
const KEEP: f32 = 1.5;
/// From this many times [`RoundTrip::rounding`] on, the correction is applied in full.
const FULL: f32 = 3.0;
/// The weight of the colour's residual against the change of the node values, once the colour
/// differential is scaled to unit size per node: large enough that the residual left where the
/// colour is reachable is far below f32's resolution of it, small enough that the 3 × 3 system
/// stays positive definite when fewer than three node values are free.
const MU: f32 = 1.0e6;
/// A fixed node value's multiplier must pull outward by more than this (in the scaled units,
/// where node values are of order 1) before it is freed: f32 noise never frees one.
const FREE_BELOW: f32 = 1.0e-6;

impl<const N: usize> RoundTrip<N> {
    /// A round trip from the set's white-balanced weights, the display's RGB → XYZ and the
    /// edge cells' bits. A weight that is not finite makes the correction a no-op (its
    /// residuals never pass the gate).
    pub const fn new(
        weights: [[f32; N]; 3],
        rgb_to_xyz: [[f32; 3]; 3],
        edge_cells: &'static [u32],
    ) -> Self {
        let mut rounding = [0.0f32; 3];
        let mut c = 0;
        while c < 3 {
            let mut sum = 0.0f32;
            let mut i = 0;
            while i < N {
                sum += weights[c][i].abs();
                i += 1;
            }
            // Half a code of 65535, and a floor so that a zero row divides by something.
            let r = sum * (0.5 / 65535.0);
            rounding[c] = if r > f32::MIN_POSITIVE {
                r
            } else {
                f32::MIN_POSITIVE
            };
            c += 1;
        }
        RoundTrip {
            weights,
            rgb_to_xyz,
            edge_cells,
            rounding,
        }
    }

    /// Whether the cell `cell` (index as [`edge_cells`](Self::edge_cells)) is at the edge.
    #[inline]
    pub(crate) fn is_edge(&self, cell: usize) -> bool {
        match self.edge_cells.get(cell / 32) {
            Some(w) => (w >> (cell % 32)) & 1 == 1,
            None => true,
        }
    }

    /// Corrects `r` (node values in [0, 1], interpolated at `p`, each channel of `p` in
    /// [0, 1]) toward the node values nearest `r` that encode to `p`; see the module docs.
    pub(crate) fn correct(&self, p: [f32; 3], r: &mut [f32; N]) {
        let w = &self.weights;
        let mut gate = 0.0f32;
        for c in 0..3 {
            let mut e = p[c];
            for i in 0..N {
                e -= w[c][i] * r[i];
            }
            gate = gate.max(e.abs() / self.rounding[c]);
        }
        // NaN (a weight that is not finite) is not greater and keeps the values.
        if gate.partial_cmp(&KEEP) != Some(core::cmp::Ordering::Greater) {
            return;
        }
        let phase = ((gate - KEEP) / (FULL - KEEP)).min(1.0);
        let Some(x) = self.nearest(p, r) else {
            return;
        };
        for i in 0..N {
            r[i] = (r[i] + phase * (x[i] - r[i])).clamp(0.0, 1.0);
        }
    }

    /// The node values x in [0, 1] minimising `|x − r|² + MU · |s J (weights · x − p)|²`: the
    /// colour residual in CIELAB linearised at p (J, its differential; s scales the columns of
    /// `A = s J · weights` to unit size on average) weighted by [`MU`] against the change of
    /// the node values. A primal active-set method on the box, at most `3 N + 3`
    /// steps, each a 3 × 3 solve. `None` if the metric is degenerate (no finite scale).
    fn nearest(&self, p: [f32; 3], r: &[f32; N]) -> Option<[f32; N]> {
        let j = lab_jacobian(&self.rgb_to_xyz, p);
        let w = &self.weights;
        let mut a = [[0.0f32; N]; 3];
        let mut size = 0.0f32;
        for (row, jr) in a.iter_mut().zip(&j) {
            for (i, v) in row.iter_mut().enumerate() {
                *v = jr[0] * w[0][i] + jr[1] * w[1][i] + jr[2] * w[2][i];
                size += *v * *v;
            }
        }
        let scale = libm::sqrtf(N as f32 / size);
        if !(scale.is_finite() && scale > 0.0) {
            return None;
        }
        // The colour's residual at r, in the scaled metric: the target of A (x − r).
        let mut e = p;
        for (ek, wk) in e.iter_mut().zip(w) {
            for (wi, ri) in wk.iter().zip(r) {
                *ek -= wi * ri;
            }
        }
        let t: [f32; 3] =
            core::array::from_fn(|c| scale * (j[c][0] * e[0] + j[c][1] * e[1] + j[c][2] * e[2]));
        for row in a.iter_mut() {
            for v in row.iter_mut() {
                *v *= scale;
            }
        }
        // x = r + z; z_i free or held at the bound it reached (−r_i or 1 − r_i).
        let mut z = [0.0f32; N];
        // 0: free; −1: held at 0; 1: held at 1.
        let mut held = [0i8; N];
        for _ in 0..3 * N + 3 {
            // The free values' optimum with the held ones fixed: minimise
            // |z_F|² / MU + |A_F z_F − b|², b = t − A_H z_H. With three or more free values,
            // through the 3 × 3 system z_F = A_Fᵀ y, (I / MU + A_F A_Fᵀ) y = b (A_F has full
            // row rank); with fewer, through their own normal equations
            // (I / MU + A_Fᵀ A_F) z_F = A_Fᵀ b and y = MU (b − A_F z_F) (A_F has full column
            // rank): each the well-conditioned side in f32.
            let mut b = t;
            let mut free = [0usize; 3];
            let mut n_free = 0;
            for i in 0..N {
                if held[i] != 0 {
                    for (c, bc) in b.iter_mut().enumerate() {
                        *bc -= a[c][i] * z[i];
                    }
                } else {
                    if n_free < 3 {
                        free[n_free] = i;
                    }
                    n_free += 1;
                }
            }
            let mut target = [0.0f32; N];
            let y = if n_free >= 3 {
                let mut m = [[0.0f32; 3]; 3];
                for i in 0..N {
                    if held[i] == 0 {
                        for (c, row) in m.iter_mut().enumerate() {
                            for (k, v) in row.iter_mut().enumerate() {
                                *v += a[c][i] * a[k][i];
                            }
                        }
                    }
                }
                for (c, row) in m.iter_mut().enumerate() {
                    row[c] += 1.0 / MU;
                }
                let y = solve_spd3(&m, b)?;
                for i in 0..N {
                    if held[i] == 0 {
                        target[i] = a[0][i] * y[0] + a[1][i] * y[1] + a[2][i] * y[2];
                    }
                }
                y
            } else {
                // Unused rows and columns of the system are the identity's.
                let mut m = [[0.0f32; 3]; 3];
                let mut rhs = [0.0f32; 3];
                for p in 0..3 {
                    if p >= n_free {
                        m[p][p] = 1.0;
                        continue;
                    }
                    let ip = free[p];
                    rhs[p] = a[0][ip] * b[0] + a[1][ip] * b[1] + a[2][ip] * b[2];
                    for q in 0..n_free {
                        let iq = free[q];
                        m[p][q] = a[0][ip] * a[0][iq] + a[1][ip] * a[1][iq] + a[2][ip] * a[2][iq];
                    }
                    m[p][p] += 1.0 / MU;
                }
                let zf = solve_spd3(&m, rhs)?;
                let mut res = b;
                for p in 0..n_free {
                    let ip = free[p];
                    target[ip] = zf[p];
                    for (c, rc) in res.iter_mut().enumerate() {
                        *rc -= a[c][ip] * zf[p];
                    }
                }
                res.map(|v| MU * v)
            };
            // Step from z toward the optimum; stop at the first bound it crosses.
            let mut step = 1.0f32;
            let mut blocking = None;
            for i in 0..N {
                if held[i] != 0 {
                    continue;
                }
                let ti = target[i];
                let (lo, hi) = (-r[i], 1.0 - r[i]);
                let limit = if ti < lo {
                    Some(((z[i] - lo) / (z[i] - ti), -1))
                } else if ti > hi {
                    Some(((hi - z[i]) / (ti - z[i]), 1))
                } else {
                    None
                };
                if let Some((s, side)) = limit {
                    let s = s.clamp(0.0, 1.0);
                    if s < step || (blocking.is_none() && s <= step) {
                        step = s;
                        blocking = Some((i, side));
                    }
                }
            }
            for i in 0..N {
                if held[i] == 0 {
                    z[i] += step * (target[i] - z[i]);
                }
            }
            if let Some((i, side)) = blocking {
                held[i] = side;
                z[i] = if side < 0 { -r[i] } else { 1.0 - r[i] };
                continue;
            }
            // At the free values' optimum: free the held value whose multiplier pulls outward
            // most, or stop. Half the gradient at a held value: z_i − a_iᵀ y.
            let mut worst = FREE_BELOW;
            let mut release = None;
            for i in 0..N {
                if held[i] == 0 {
                    continue;
                }
                let g = z[i] - (a[0][i] * y[0] + a[1][i] * y[1] + a[2][i] * y[2]);
                // Held at 0 it may rise if the gradient is negative; at 1, fall if positive.
                let pull = if held[i] < 0 { -g } else { g };
                if pull > worst {
                    worst = pull;
                    release = Some(i);
                }
            }
            match release {
                Some(i) => held[i] = 0,
                None => break,
            }
        }
        Some(core::array::from_fn(|i| (r[i] + z[i]).clamp(0.0, 1.0)))
    }
}

/// CIELAB's differential with respect to linear RGB at `p` (rows L*, a*, b*), the display's
/// white, `rgb_to_xyz · (1, 1, 1)`, as the reference white.
fn lab_jacobian(m: &[[f32; 3]; 3], p: [f32; 3]) -> [[f32; 3]; 3] {
    // CIELAB's f has slope 1 / (3 t^(2/3)) above (6/29)³ and 1 / (3 (6/29)²) below.
    const D3: f32 = (6.0 / 29.0) * (6.0 / 29.0) * (6.0 / 29.0);
    const LINEAR: f32 = 1.0 / (3.0 * (6.0 / 29.0) * (6.0 / 29.0));
    let mut g = [0.0f32; 3];
    for c in 0..3 {
        let white = m[c][0] + m[c][1] + m[c][2];
        let t = (m[c][0] * p[0] + m[c][1] * p[1] + m[c][2] * p[2]) / white;
        let slope = if t > D3 {
            let q = cbrt(t);
            1.0 / (3.0 * q * q)
        } else {
            LINEAR
        };
        g[c] = slope / white;
    }
    let d = [
        [0.0, 116.0 * g[1], 0.0],
        [500.0 * g[0], -500.0 * g[1], 0.0],
        [0.0, 200.0 * g[1], -200.0 * g[2]],
    ];
    core::array::from_fn(|r| {
        core::array::from_fn(|c| d[r][0] * m[0][c] + d[r][1] * m[1][c] + d[r][2] * m[2][c])
    })
}

/// The cube root of a positive, finite, normal `t`, in f32 alone (libm's `cbrtf` computes in
/// f64, which a microcontroller without a double-precision unit emulates): an estimate from the
/// exponent's bits (musl's constant), then three Newton steps `y ← (2 y + t / y²) / 3`, each
/// cubing the relative error's order, from a few per cent to f32's rounding.
fn cbrt(t: f32) -> f32 {
    let mut y = f32::from_bits(t.to_bits() / 3 + 709_958_130);
    for _ in 0..3 {
        y = (2.0 * y + t / (y * y)) * (1.0 / 3.0);
    }
    y
}

/// Solves `m y = b` for a symmetric positive definite 3 × 3 `m` by Cholesky; `None` where a
/// pivot is not positive and finite.
// The triangular loops index two factors at once.
#[allow(clippy::needless_range_loop)]
fn solve_spd3(m: &[[f32; 3]; 3], b: [f32; 3]) -> Option<[f32; 3]> {
    let mut l = [[0.0f32; 3]; 3];
    for i in 0..3 {
        for k in 0..=i {
            let mut s = m[i][k];
            for q in 0..k {
                s -= l[i][q] * l[k][q];
            }
            if i == k {
                if !(s > 0.0 && s.is_finite()) {
                    return None;
                }
                l[i][i] = libm::sqrtf(s);
            } else {
                l[i][k] = s / l[k][k];
            }
        }
    }
    let mut y = [0.0f32; 3];
    for i in 0..3 {
        let mut s = b[i];
        for q in 0..i {
            s -= l[i][q] * y[q];
        }
        y[i] = s / l[i][i];
    }
    let mut x = [0.0f32; 3];
    for i in (0..3).rev() {
        let mut s = y[i];
        for q in i + 1..3 {
            s -= l[q][i] * x[q];
        }
        x[i] = s / l[i][i];
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::cbrt;

    #[test]
    fn cube_root_to_f32_rounding() {
        // Over the range the metric uses, (6/29)³ to a little above 1, and beyond.
        let mut t = 0.008f32;
        while t < 4.0 {
            let want = f64::from(t).cbrt();
            let got = f64::from(cbrt(t));
            // Three Newton steps leave f32 rounding: a few units of 2⁻²⁴ relative.
            assert!(
                ((got - want) / want).abs() < 4.0 * f64::from(f32::EPSILON),
                "{t}: {got} vs {want}"
            );
            t *= 1.001;
        }
    }
}
