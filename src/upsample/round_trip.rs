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
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RoundTrip<const N: usize> {
    // Set by `new` alone (the baked tables call it too); `pub(super)`: the upsampling reads them.
    pub(super) weights: [[f32; N]; 3],
    pub(super) rgb_to_xyz: [[f32; 3]; 3],
    pub(super) edge_cells: &'static [u32],
    /// Per channel, the largest residual the table's rounding alone can leave: half a code
    /// times the sum of the row's absolute weights.
    pub(super) rounding: [f32; 3],
}

/// Below this many times [`RoundTrip::rounding`] the residual is the table's rounding and the
/// values are kept; from there to [`FULL`] the correction is phased in, so that the function
/// stays continuous where it starts.
const KEEP: f32 = 1.5;
/// From this many times [`RoundTrip::rounding`] on, the correction is applied in full.
const FULL: f32 = 3.0;
/// The weight of the colour's residual against the change of the node values, once the colour
/// differential is scaled to unit size per node: large enough that the residual left where the
/// colour is reachable is far below f32's resolution of it, small enough that the stacked
/// least-squares problem `[C; I / √MU]` keeps a condition number near `√MU` that f32 resolves.
const MU: f32 = 1.0e6;

/// A held value whose multiplier pulls inward by less than this fraction of the multiplier's
/// terms is released on trial (see `nearest`): well above what the conditioning of the free
/// values' colours leaves of f32's rounding in the multiplier.
const RELEASE_TRIAL: f32 = 1.0 / 1024.0;

impl<const N: usize> RoundTrip<N> {
    /// `rgb = weights · r`: the set's linear RGB of node reflectances under the reference light,
    /// white-balanced (each row sums to 1).
    pub const fn weights(&self) -> [[f32; N]; 3] {
        self.weights
    }

    /// The display's linear RGB to CIE XYZ: the metric (CIELAB, the display's white as the
    /// reference white) in which an unreachable colour's nearest reachable colour is found.
    pub const fn rgb_to_xyz(&self) -> [[f32; 3]; 3] {
        self.rgb_to_xyz
    }

    /// One bit per cell of the grid, index `(r · (grid − 1) + g) · (grid − 1) + b`, bit `i % 32`
    /// of word `i / 32`: set where a corner of the cell is a colour node values in [0, 1] do
    /// not reach. A cell past the slice's end counts as set.
    pub const fn edge_cells(&self) -> &'static [u32] {
        self.edge_cells
    }

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
    /// the node values. A primal active-set method on the box, at most `3 N + 3` steps.
    /// `None` if the metric is degenerate (no finite scale) or a factor is.
    ///
    /// Each step's solve keeps apart what depends on the colour and what does not. The free
    /// values' weights `W_F` are factored first, `W_Fᵀ = Q R` (Gram-Schmidt with pivoting,
    /// twice): the same arithmetic for every colour, so where a set's weights are nearly
    /// dependent (nodes a nanometre apart, weights nearly proportional) the small pivot is the
    /// same number for every input instead of f32 noise that changes from one input to the
    /// next. The step is `z_F = Q u`, u the least-squares solution of
    /// `[C; I / √MU] u ≈ [t; 0]` with `C = s J R`-ish (`C = s J G`, G the weights' columns in
    /// Q's basis), by Gram-Schmidt twice on its columns: columnwise stable, so C's small
    /// column (a small pivot of R times J) keeps its relative accuracy. The held values'
    /// multipliers come from u through C's own factor (no cancellation), plus `MU` times the
    /// part of the target outside C's range where fewer than three directions are free.
    fn nearest(&self, p: [f32; 3], r: &[f32; N]) -> Option<[f32; N]> {
        let j = lab_jacobian(&self.rgb_to_xyz, p);
        let w = &self.weights;
        let mut size = 0.0f32;
        for jr in &j {
            for ((w0, w1), w2) in w[0].iter().zip(&w[1]).zip(&w[2]) {
                let v = jr[0] * w0 + jr[1] * w1 + jr[2] * w2;
                size += v * v;
            }
        }
        let scale = libm::sqrtf(N as f32 / size);
        if !(scale.is_finite() && scale > 0.0) {
            return None;
        }
        // The scaled differential s J, and each node's column of A = s J W.
        let sj: [[f32; 3]; 3] = core::array::from_fn(|c| j[c].map(|v| v * scale));
        let col = |i: usize| -> [f32; 3] {
            core::array::from_fn(|c| sj[c][0] * w[0][i] + sj[c][1] * w[1][i] + sj[c][2] * w[2][i])
        };
        // The colour's residual at r, in linear RGB.
        let mut e = p;
        for (ek, wk) in e.iter_mut().zip(w) {
            for (wi, ri) in wk.iter().zip(r) {
                *ek -= wi * ri;
            }
        }
        // x = r + z; z_i free or held at the bound it reached (−r_i or 1 − r_i).
        let mut z = [0.0f32; N];
        // 0: free; −1: held at 0; 1: held at 1.
        let mut held = [0i8; N];
        // Held values whose trial release moved them outward at once, since z last moved.
        let mut refused = [false; N];
        // The value released on the last step, on trial.
        let mut trial = None;
        let inv_sqrt_mu = libm::sqrtf(1.0 / MU);
        for _ in 0..3 * N + 3 {
            // The RGB the free values must supply: d = e − W_H z_H; in the metric, t = s J d.
            let mut d = e;
            let mut n_free = 0;
            for i in 0..N {
                if held[i] != 0 {
                    for (c, dc) in d.iter_mut().enumerate() {
                        *dc -= w[c][i] * z[i];
                    }
                } else {
                    n_free += 1;
                }
            }
            let t: [f32; 3] =
                core::array::from_fn(|c| sj[c][0] * d[0] + sj[c][1] * d[1] + sj[c][2] * d[2]);
            // W_Fᵀ = Q R: the free values' weights (one column per RGB channel) in an
            // orthonormal basis q_0..q_{m−1} of the free values, g[l][c] the coefficient of
            // q_l in channel c.
            let (q, g, m) = factor_weights(w, &held, n_free.min(3))?;
            // C = s J Gᵀ: the metric's change per unit of each basis vector.
            let cm: [[f32; 3]; 3] = core::array::from_fn(|c| {
                core::array::from_fn(|l| {
                    if l < m {
                        sj[c][0] * g[l][0] + sj[c][1] * g[l][1] + sj[c][2] * g[l][2]
                    } else {
                        0.0
                    }
                })
            });
            let u = regularised_least_squares(&cm, t, m, inv_sqrt_mu)?;
            let mut target = [0.0f32; N];
            for (l, ql) in q.iter().enumerate().take(m) {
                for i in 0..N {
                    target[i] += u[l] * ql[i];
                }
            }
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
            if step > 0.0 {
                refused = [false; N];
            }
            if let Some((i, side)) = blocking {
                held[i] = side;
                z[i] = if side < 0 { -r[i] } else { 1.0 - r[i] };
                if step == 0.0 && trial == Some(i) {
                    refused[i] = true;
                }
                trial = None;
                continue;
            }
            // At the free values' optimum: release the held value whose multiplier pulls
            // outward most, or stop. Half the gradient at a held value: z_i − a_iᵀ y,
            // y = MU (t − C u). Where the free values' colours are nearly dependent, y carries
            // their conditioning times f32's rounding, and a pull near zero may have either
            // sign; so a value whose pull is within RELEASE_TRIAL of its terms' size is
            // released too, on trial: the next step's solve, accurate where the multiplier is
            // not, moves it inward (kept free) or at once outward (held again, and not tried
            // again until z moves).
            let y = multiplier(&cm, t, &u, m)?;
            let mut worst = f32::MIN;
            let mut release = None;
            for i in 0..N {
                if held[i] == 0 || refused[i] {
                    continue;
                }
                let a = col(i);
                let ay = a[0] * y[0] + a[1] * y[1] + a[2] * y[2];
                let g = z[i] - ay;
                // Held at 0 it may rise if the gradient is negative; at 1, fall if positive.
                let pull = if held[i] < 0 { -g } else { g };
                let size =
                    z[i].abs() + (a[0] * y[0]).abs() + (a[1] * y[1]).abs() + (a[2] * y[2]).abs();
                if pull > -RELEASE_TRIAL * size && pull > worst {
                    worst = pull;
                    release = Some(i);
                }
            }
            match release {
                Some(i) => {
                    held[i] = 0;
                    trial = Some(i);
                }
                None => break,
            }
        }
        Some(core::array::from_fn(|i| (r[i] + z[i]).clamp(0.0, 1.0)))
    }
}

/// The basis `q`, the coefficients `g` and the rank `m` of [`factor_weights`].
type WeightsFactor<const N: usize> = ([[f32; N]; 3], [[f32; 3]; 3], usize);

/// The free values' weights factored: an orthonormal basis `q[0..m]` of the span of the three
/// channels' rows of `w` restricted to the free values (held entries zero), and `g[l][c]`, the
/// coefficient of `q[l]` in channel c's row. Gram-Schmidt, the largest remaining row first,
/// each projection done twice; at most `max_rank` vectors, fewer where a remaining row is zero.
/// It reads only the weights and which values are free, so its rounding is the same for every
/// colour. `None` on a weight that is not finite.
// The factor's loops index rows and the basis at once.
#[allow(clippy::needless_range_loop)]
fn factor_weights<const N: usize>(
    w: &[[f32; N]; 3],
    held: &[i8; N],
    max_rank: usize,
) -> Option<WeightsFactor<N>> {
    let mut v = [[0.0f32; N]; 3];
    for c in 0..3 {
        for i in 0..N {
            if held[i] == 0 {
                v[c][i] = w[c][i];
            }
        }
    }
    let mut q = [[0.0f32; N]; 3];
    let mut g = [[0.0f32; 3]; 3];
    let mut done = [false; 3];
    let mut m = 0;
    while m < max_rank {
        // The largest remaining row (the lowest channel on a tie).
        let mut pick = None;
        let mut largest = 0.0f32;
        for c in 0..3 {
            if done[c] {
                continue;
            }
            let n2: f32 = v[c].iter().map(|x| x * x).sum();
            if !n2.is_finite() {
                return None;
            }
            if n2 > largest {
                largest = n2;
                pick = Some(c);
            }
        }
        let Some(c) = pick else { break };
        done[c] = true;
        // Orthogonal to every earlier basis vector again: the updates below leave a remainder
        // along them of f32 rounding times the row's size, which a small remainder (nearly
        // dependent rows) would otherwise turn into a basis vector far from orthogonal.
        for _ in 0..2 {
            for k in 0..m {
                let mut dot = 0.0f32;
                for i in 0..N {
                    dot += q[k][i] * v[c][i];
                }
                g[k][c] += dot;
                for i in 0..N {
                    v[c][i] -= dot * q[k][i];
                }
            }
        }
        let n2: f32 = v[c].iter().map(|x| x * x).sum();
        if n2.is_nan() || n2 <= 0.0 {
            break;
        }
        let norm = libm::sqrtf(n2);
        for i in 0..N {
            q[m][i] = v[c][i] / norm;
        }
        g[m][c] = norm;
        for c2 in 0..3 {
            if done[c2] {
                continue;
            }
            for _ in 0..2 {
                let mut dot = 0.0f32;
                for i in 0..N {
                    dot += q[m][i] * v[c2][i];
                }
                g[m][c2] += dot;
                for i in 0..N {
                    v[c2][i] -= dot * q[m][i];
                }
            }
        }
        m += 1;
    }
    Some((q, g, m))
}

/// The u (first `m` entries) minimising `|u|² + MU · |C u − t|²` over C's first `m` columns:
/// the least-squares solution of `[C; I / √MU] u ≈ [t; 0]`, by Gram-Schmidt twice on the
/// stacked columns and back substitution. `None` where a pivot is not positive and finite.
#[allow(clippy::needless_range_loop)]
fn regularised_least_squares(
    cm: &[[f32; 3]; 3],
    t: [f32; 3],
    m: usize,
    inv_sqrt_mu: f32,
) -> Option<[f32; 3]> {
    // Column l of the stacked matrix: rows 0..3 from C, row 3 + l the regularisation.
    let mut qb = [[0.0f32; 6]; 3];
    let mut rb = [[0.0f32; 3]; 3];
    for l in 0..m {
        let mut v = [0.0f32; 6];
        for c in 0..3 {
            v[c] = cm[c][l];
        }
        v[3 + l] = inv_sqrt_mu;
        for _ in 0..2 {
            for k in 0..l {
                let mut dot = 0.0f32;
                for i in 0..6 {
                    dot += qb[k][i] * v[i];
                }
                rb[k][l] += dot;
                for i in 0..6 {
                    v[i] -= dot * qb[k][i];
                }
            }
        }
        let norm = libm::sqrtf(v.iter().map(|x| x * x).sum());
        if !(norm > 0.0 && norm.is_finite()) {
            return None;
        }
        rb[l][l] = norm;
        for i in 0..6 {
            qb[l][i] = v[i] / norm;
        }
    }
    let mut u = [0.0f32; 3];
    for l in (0..m).rev() {
        let mut s = qb[l][0] * t[0] + qb[l][1] * t[1] + qb[l][2] * t[2];
        for k in l + 1..m {
            s -= rb[l][k] * u[k];
        }
        u[l] = s / rb[l][l];
    }
    Some(u)
}

/// The multiplier `y = MU (t − C u)` of the colour term at the free values' optimum u, without
/// the cancellation of that difference: its part in C's range is `Q_C R_C⁻ᵀ u` (from the
/// optimality condition `Cᵀ y = u`, `C = Q_C R_C` by Gram-Schmidt twice), and only the part
/// outside C's range (fewer than three directions free) is `MU` times the target's.
#[allow(clippy::needless_range_loop)]
fn multiplier(cm: &[[f32; 3]; 3], t: [f32; 3], u: &[f32; 3], m: usize) -> Option<[f32; 3]> {
    let mut qc = [[0.0f32; 3]; 3];
    let mut rc = [[0.0f32; 3]; 3];
    for l in 0..m {
        let mut v = [cm[0][l], cm[1][l], cm[2][l]];
        for _ in 0..2 {
            for k in 0..l {
                let dot = qc[k][0] * v[0] + qc[k][1] * v[1] + qc[k][2] * v[2];
                rc[k][l] += dot;
                for i in 0..3 {
                    v[i] -= dot * qc[k][i];
                }
            }
        }
        let norm = libm::sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if !(norm > 0.0 && norm.is_finite()) {
            return None;
        }
        rc[l][l] = norm;
        for i in 0..3 {
            qc[l][i] = v[i] / norm;
        }
    }
    // R_Cᵀ s = u, forward.
    let mut s = [0.0f32; 3];
    for l in 0..m {
        let mut acc = u[l];
        for k in 0..l {
            acc -= rc[k][l] * s[k];
        }
        s[l] = acc / rc[l][l];
    }
    let mut y = [0.0f32; 3];
    let mut outside = t;
    for l in 0..m {
        let along = qc[l][0] * t[0] + qc[l][1] * t[1] + qc[l][2] * t[2];
        for i in 0..3 {
            y[i] += s[l] * qc[l][i];
            outside[i] -= along * qc[l][i];
        }
    }
    if m < 3 {
        for i in 0..3 {
            y[i] += MU * outside[i];
        }
    }
    Some(y)
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
