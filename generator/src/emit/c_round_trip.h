/* RoundTrip (Upsampling::reflectance on edge cells): the runtime's upsample/round_trip.rs in C,
 * the same f32 operations in the same order. n values (at most SQ_UPSAMPLING_MAX_LEN), the
 * weights w as 3 rows of n. */

/* f32::abs. */
static inline float sq_abs(float x) {
    return sq_f32_from_bits(sq_f32_bits(x) & 0x7fffffffu);
}

/* f32::clamp(x, 0, 1): NaN stays NaN. */
static inline float sq_clamp01_keep_nan(float x) {
    return x < 0.0f ? 0.0f : (x > 1.0f ? 1.0f : x);
}

/* Whether the cell is an edge cell (a cell past the bit set's end is). */
static inline int sq_round_trip_is_edge(const uint32_t *edge_cells, size_t words, size_t cell) {
    if (cell / 32u >= words) {
        return 1;
    }
    return (int)((edge_cells[cell / 32u] >> (cell % 32u)) & 1u);
}

/* The cube root to f32 rounding: a bit-level guess and three Newton steps. */
static inline float sq_round_trip_cbrt(float t) {
    SQ_FP_EXACT
    float y = sq_f32_from_bits(sq_f32_bits(t) / 3u + 709958130u);
    int k;
    for (k = 0; k < 3; k++) {
        y = (2.0f * y + t / (y * y)) * (1.0f / 3.0f);
    }
    return y;
}

/* CIELAB's differential at the linear RGB p (white: RGB 1, 1, 1), through rgb_to_xyz. */
static inline void sq_round_trip_lab_jacobian(const float m[3][3], const float p[3], float out[3][3]) {
    SQ_FP_EXACT
    const float d3 = (6.0f / 29.0f) * (6.0f / 29.0f) * (6.0f / 29.0f);
    const float linear = 1.0f / (3.0f * (6.0f / 29.0f) * (6.0f / 29.0f));
    float g[3], d[3][3];
    int c, r;
    for (c = 0; c < 3; c++) {
        float white = m[c][0] + m[c][1] + m[c][2];
        float t = (m[c][0] * p[0] + m[c][1] * p[1] + m[c][2] * p[2]) / white;
        float slope;
        if (t > d3) {
            float q = sq_round_trip_cbrt(t);
            slope = 1.0f / (3.0f * q * q);
        } else {
            slope = linear;
        }
        g[c] = slope / white;
    }
    d[0][0] = 0.0f;
    d[0][1] = 116.0f * g[1];
    d[0][2] = 0.0f;
    d[1][0] = 500.0f * g[0];
    d[1][1] = -500.0f * g[1];
    d[1][2] = 0.0f;
    d[2][0] = 0.0f;
    d[2][1] = 200.0f * g[1];
    d[2][2] = -200.0f * g[2];
    for (r = 0; r < 3; r++) {
        for (c = 0; c < 3; c++) {
            out[r][c] = d[r][0] * m[0][c] + d[r][1] * m[1][c] + d[r][2] * m[2][c];
        }
    }
}

/* The free values' weights factored (Gram-Schmidt, the largest remaining row first, each
 * projection twice): q[0..m] orthonormal, g[l][c] the coefficient of q[l] in row c. Returns m,
 * or -1 on a weight that is not finite. */
static inline int sq_round_trip_factor(size_t n, const float *w, const signed char *held, int max_rank, float q[3][SQ_UPSAMPLING_MAX_LEN], float g[3][3]) {
    SQ_FP_EXACT
    float v[3][SQ_UPSAMPLING_MAX_LEN];
    int done[3] = { 0, 0, 0 };
    int m = 0, c, c2, k, pass;
    size_t i;
    for (c = 0; c < 3; c++) {
        for (i = 0; i < n; i++) {
            v[c][i] = held[i] == 0 ? w[c * n + i] : 0.0f;
            q[c][i] = 0.0f;
        }
        g[c][0] = g[c][1] = g[c][2] = 0.0f;
    }
    while (m < max_rank) {
        int pick = -1;
        float largest = 0.0f, n2, norm;
        for (c = 0; c < 3; c++) {
            if (done[c]) {
                continue;
            }
            n2 = 0.0f;
            for (i = 0; i < n; i++) {
                n2 += v[c][i] * v[c][i];
            }
            if (sq_is_nan(n2) || sq_is_infinite(n2)) {
                return -1;
            }
            if (n2 > largest) {
                largest = n2;
                pick = c;
            }
        }
        if (pick < 0) {
            break;
        }
        c = pick;
        done[c] = 1;
        for (pass = 0; pass < 2; pass++) {
            for (k = 0; k < m; k++) {
                float dot = 0.0f;
                for (i = 0; i < n; i++) {
                    dot += q[k][i] * v[c][i];
                }
                g[k][c] += dot;
                for (i = 0; i < n; i++) {
                    v[c][i] -= dot * q[k][i];
                }
            }
        }
        n2 = 0.0f;
        for (i = 0; i < n; i++) {
            n2 += v[c][i] * v[c][i];
        }
        if (sq_is_nan(n2) || n2 <= 0.0f) {
            break;
        }
        norm = sqrtf(n2);
        for (i = 0; i < n; i++) {
            q[m][i] = v[c][i] / norm;
        }
        g[m][c] = norm;
        for (c2 = 0; c2 < 3; c2++) {
            if (done[c2]) {
                continue;
            }
            for (pass = 0; pass < 2; pass++) {
                float dot = 0.0f;
                for (i = 0; i < n; i++) {
                    dot += q[m][i] * v[c2][i];
                }
                g[m][c2] += dot;
                for (i = 0; i < n; i++) {
                    v[c2][i] -= dot * q[m][i];
                }
            }
        }
        m++;
    }
    return m;
}

/* min |C u - t|^2 + |u|^2 / MU over u (m unknowns), by the QR factors of C stacked on the
 * regularisation. 0 where a column's norm is not finite and positive. */
static inline int sq_round_trip_least_squares(float cm[3][3], const float t[3], int m, float inv_sqrt_mu, float u[3]) {
    SQ_FP_EXACT
    float qb[3][6], rb[3][3];
    int l, k, i, pass;
    for (l = 0; l < 3; l++) {
        for (i = 0; i < 6; i++) {
            qb[l][i] = 0.0f;
        }
        rb[l][0] = rb[l][1] = rb[l][2] = 0.0f;
        u[l] = 0.0f;
    }
    for (l = 0; l < m; l++) {
        float v[6] = { 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f }, n2 = 0.0f, norm;
        for (i = 0; i < 3; i++) {
            v[i] = cm[i][l];
        }
        v[3 + l] = inv_sqrt_mu;
        for (pass = 0; pass < 2; pass++) {
            for (k = 0; k < l; k++) {
                float dot = 0.0f;
                for (i = 0; i < 6; i++) {
                    dot += qb[k][i] * v[i];
                }
                rb[k][l] += dot;
                for (i = 0; i < 6; i++) {
                    v[i] -= dot * qb[k][i];
                }
            }
        }
        for (i = 0; i < 6; i++) {
            n2 += v[i] * v[i];
        }
        norm = sqrtf(n2);
        if (!(norm > 0.0f) || sq_is_infinite(norm)) {
            return 0;
        }
        rb[l][l] = norm;
        for (i = 0; i < 6; i++) {
            qb[l][i] = v[i] / norm;
        }
    }
    for (l = m - 1; l >= 0; l--) {
        float s = qb[l][0] * t[0] + qb[l][1] * t[1] + qb[l][2] * t[2];
        for (k = l + 1; k < m; k++) {
            s -= rb[l][k] * u[k];
        }
        u[l] = s / rb[l][l];
    }
    return 1;
}

/* The multiplier y = MU (t - C u) of the colour constraint, from the QR factors of C. 0 where a
 * column's norm is not finite and positive. */
static inline int sq_round_trip_multiplier(float cm[3][3], const float t[3], const float u[3], int m, float y[3]) {
    SQ_FP_EXACT
    float qc[3][3], rc[3][3], s[3] = { 0.0f, 0.0f, 0.0f }, outside[3];
    int l, k, i, pass;
    for (l = 0; l < 3; l++) {
        qc[l][0] = qc[l][1] = qc[l][2] = 0.0f;
        rc[l][0] = rc[l][1] = rc[l][2] = 0.0f;
    }
    for (l = 0; l < m; l++) {
        float v[3], norm;
        v[0] = cm[0][l];
        v[1] = cm[1][l];
        v[2] = cm[2][l];
        for (pass = 0; pass < 2; pass++) {
            for (k = 0; k < l; k++) {
                float dot = qc[k][0] * v[0] + qc[k][1] * v[1] + qc[k][2] * v[2];
                rc[k][l] += dot;
                for (i = 0; i < 3; i++) {
                    v[i] -= dot * qc[k][i];
                }
            }
        }
        norm = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (!(norm > 0.0f) || sq_is_infinite(norm)) {
            return 0;
        }
        rc[l][l] = norm;
        for (i = 0; i < 3; i++) {
            qc[l][i] = v[i] / norm;
        }
    }
    for (l = 0; l < m; l++) {
        float acc = u[l];
        for (k = 0; k < l; k++) {
            acc -= rc[k][l] * s[k];
        }
        s[l] = acc / rc[l][l];
    }
    y[0] = y[1] = y[2] = 0.0f;
    outside[0] = t[0];
    outside[1] = t[1];
    outside[2] = t[2];
    for (l = 0; l < m; l++) {
        float along = qc[l][0] * t[0] + qc[l][1] * t[1] + qc[l][2] * t[2];
        for (i = 0; i < 3; i++) {
            y[i] += s[l] * qc[l][i];
            outside[i] -= along * qc[l][i];
        }
    }
    if (m < 3) {
        for (i = 0; i < 3; i++) {
            y[i] += 1.0e6f * outside[i];
        }
    }
    return 1;
}

/* The nearest node values in [0, 1] (in CIELAB linearised at p) that give the colour p back, from
 * r: an active-set search. 0 (x untouched) where the metric or a factor is degenerate. */
static inline int sq_round_trip_nearest(size_t n, const float *w, const float m3[3][3], const float p[3], const float *r, float *x) {
    SQ_FP_EXACT
    float j[3][3], sj[3][3], e[3], size = 0.0f, scale, inv_sqrt_mu;
    float z[SQ_UPSAMPLING_MAX_LEN], target[SQ_UPSAMPLING_MAX_LEN];
    signed char held[SQ_UPSAMPLING_MAX_LEN], refused[SQ_UPSAMPLING_MAX_LEN];
    long trial = -1;
    size_t i, it;
    int c, k, l;
    sq_round_trip_lab_jacobian(m3, p, j);
    for (c = 0; c < 3; c++) {
        for (i = 0; i < n; i++) {
            float v = j[c][0] * w[i] + j[c][1] * w[n + i] + j[c][2] * w[2 * n + i];
            size += v * v;
        }
    }
    scale = sqrtf((float)n / size);
    if (!(scale > 0.0f) || sq_is_infinite(scale)) {
        return 0;
    }
    for (c = 0; c < 3; c++) {
        for (k = 0; k < 3; k++) {
            sj[c][k] = j[c][k] * scale;
        }
    }
    for (k = 0; k < 3; k++) {
        e[k] = p[k];
        for (i = 0; i < n; i++) {
            e[k] -= w[k * n + i] * r[i];
        }
    }
    for (i = 0; i < n; i++) {
        z[i] = 0.0f;
        held[i] = 0;
        refused[i] = 0;
    }
    inv_sqrt_mu = sqrtf(1.0f / 1.0e6f);
    for (it = 0; it < 3 * n + 3; it++) {
        float d[3], t[3], q[3][SQ_UPSAMPLING_MAX_LEN], g[3][3], cm[3][3], u[3], y[3];
        float step = 1.0f, worst = -FLT_MAX;
        size_t n_free = 0;
        long blocking = -1, release = -1;
        int blocking_side = 0, m;
        d[0] = e[0];
        d[1] = e[1];
        d[2] = e[2];
        for (i = 0; i < n; i++) {
            if (held[i] != 0) {
                for (c = 0; c < 3; c++) {
                    d[c] -= w[c * n + i] * z[i];
                }
            } else {
                n_free++;
            }
        }
        for (c = 0; c < 3; c++) {
            t[c] = sj[c][0] * d[0] + sj[c][1] * d[1] + sj[c][2] * d[2];
        }
        m = sq_round_trip_factor(n, w, held, n_free < 3 ? (int)n_free : 3, q, g);
        if (m < 0) {
            return 0;
        }
        for (c = 0; c < 3; c++) {
            for (l = 0; l < 3; l++) {
                cm[c][l] = l < m ? sj[c][0] * g[l][0] + sj[c][1] * g[l][1] + sj[c][2] * g[l][2] : 0.0f;
            }
        }
        if (!sq_round_trip_least_squares(cm, t, m, inv_sqrt_mu, u)) {
            return 0;
        }
        for (i = 0; i < n; i++) {
            target[i] = 0.0f;
        }
        for (l = 0; l < m; l++) {
            for (i = 0; i < n; i++) {
                target[i] += u[l] * q[l][i];
            }
        }
        for (i = 0; i < n; i++) {
            float ti, lo, hi, s;
            int side;
            if (held[i] != 0) {
                continue;
            }
            ti = target[i];
            lo = -r[i];
            hi = 1.0f - r[i];
            if (ti < lo) {
                s = (z[i] - lo) / (z[i] - ti);
                side = -1;
            } else if (ti > hi) {
                s = (hi - z[i]) / (ti - z[i]);
                side = 1;
            } else {
                continue;
            }
            s = sq_clamp01_keep_nan(s);
            if (s < step || (blocking < 0 && s <= step)) {
                step = s;
                blocking = (long)i;
                blocking_side = side;
            }
        }
        for (i = 0; i < n; i++) {
            if (held[i] == 0) {
                z[i] += step * (target[i] - z[i]);
            }
        }
        if (step > 0.0f) {
            for (i = 0; i < n; i++) {
                refused[i] = 0;
            }
        }
        if (blocking >= 0) {
            held[blocking] = (signed char)blocking_side;
            z[blocking] = blocking_side < 0 ? -r[blocking] : 1.0f - r[blocking];
            if (step == 0.0f && trial == blocking) {
                refused[blocking] = 1;
            }
            trial = -1;
            continue;
        }
        if (!sq_round_trip_multiplier(cm, t, u, m, y)) {
            return 0;
        }
        for (i = 0; i < n; i++) {
            float a[3], ay, gi, pull, size_i;
            if (held[i] == 0 || refused[i]) {
                continue;
            }
            for (c = 0; c < 3; c++) {
                a[c] = sj[c][0] * w[i] + sj[c][1] * w[n + i] + sj[c][2] * w[2 * n + i];
            }
            ay = a[0] * y[0] + a[1] * y[1] + a[2] * y[2];
            gi = z[i] - ay;
            pull = held[i] < 0 ? -gi : gi;
            size_i = sq_abs(z[i]) + sq_abs(a[0] * y[0]) + sq_abs(a[1] * y[1]) + sq_abs(a[2] * y[2]);
            if (pull > -(1.0f / 1024.0f) * size_i && pull > worst) {
                worst = pull;
                release = (long)i;
            }
        }
        if (release < 0) {
            break;
        }
        held[release] = 0;
        trial = release;
    }
    for (i = 0; i < n; i++) {
        x[i] = sq_clamp01_keep_nan(r[i] + z[i]);
    }
    return 1;
}

/* RoundTrip::correct: where the interpolated values r miss the colour p by more than 1.5 times
 * the rounding, move them toward the nearest values that give it back (all the way from 3 times). */
static inline void sq_round_trip_correct(size_t n, const float *w, const float m3[3][3], const float rounding[3], const float p[3], float *r) {
    SQ_FP_EXACT
    float gate = 0.0f, phase, x[SQ_UPSAMPLING_MAX_LEN];
    size_t i;
    int c;
    for (c = 0; c < 3; c++) {
        float e = p[c], v;
        for (i = 0; i < n; i++) {
            e -= w[c * n + i] * r[i];
        }
        v = sq_abs(e) / rounding[c];
        gate = v > gate ? v : gate;
    }
    if (!(gate > 1.5f)) {
        return;
    }
    phase = (gate - 1.5f) / (3.0f - 1.5f);
    phase = phase < 1.0f ? phase : 1.0f;
    if (!sq_round_trip_nearest(n, w, m3, p, r, x)) {
        return;
    }
    for (i = 0; i < n; i++) {
        r[i] = sq_clamp01_keep_nan(r[i] + phase * (x[i] - r[i]));
    }
}

