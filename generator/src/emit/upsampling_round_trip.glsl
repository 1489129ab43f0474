// @NAME@ (each local assigned apart from its declaration; the 3 x N matrix flat, as some compilers read float[3][N] the other way round): the runtime's Upsampling::reflectance: @lower@_interpolate, then in a cell at the edge of what the set reaches the round-trip correction (RoundTrip), reading its data from @NAME@_CODES after the table: the edge cells' bits from word @E@, then as f32 bits the weights (3 x @N@), RGB to XYZ (3 x 3) and the rounding (3) from word @F@.
float @lower@_f(uint i) {
    return uintBitsToFloat(@NAME@_CODES[@F@u + i]);
}

float[@N@] @lower@_round_trip(vec3 pv, uint cell, float r_in[@N@]) {
    float r[@N@];
    r = r_in;
    if (((@NAME@_CODES[@E@u + (cell >> 5u)] >> (cell & 31u)) & 1u) == 0u) {
        return r;
    }
    float p[3];
    p = float[3](pv.x, pv.y, pv.z);
    float gate;
    gate = 0.0;
    for (uint c = 0u; c < 3u; c++) {
        float ec;
        ec = p[c];
        for (uint i = 0u; i < @N@u; i++) {
            ec = ec - @lower@_f(c * @N@u + i) * r[i];
        }
        gate = max(gate, abs(ec) / @lower@_f(@ROUND@u + c));
    }
    if (!(gate > @KEEP@)) {
        return r;
    }
    float phase;
    phase = min((gate - @KEEP@) / (@FULL@ - @KEEP@), 1.0);
    // CIELAB's differential at p.
    float g[3];
    for (uint c = 0u; c < 3u; c++) {
        float m0;
        m0 = @lower@_f(@XYZ@u + 3u * c);
        float m1;
        m1 = @lower@_f(@XYZ@u + 3u * c + 1u);
        float m2;
        m2 = @lower@_f(@XYZ@u + 3u * c + 2u);
        float white;
        white = m0 + m1 + m2;
        float tc;
        tc = (m0 * p[0] + m1 * p[1] + m2 * p[2]) / white;
        float slope;
        slope = @LIN@;
        if (tc > @D3@) {
            // The runtime's f32 cube root: an estimate from the bits, three Newton steps.
            float q;
            q = uintBitsToFloat(floatBitsToUint(tc) / 3u + 709958130u);
            for (uint k = 0u; k < 3u; k++) {
                q = (2.0 * q + tc / (q * q)) * @THIRD@;
            }
            slope = 1.0 / (3.0 * q * q);
        }
        g[c] = slope / white;
    }
    float d[3][3] = float[3][3](
        float[3](0.0, 116.0 * g[1], 0.0),
        float[3](500.0 * g[0], -500.0 * g[1], 0.0),
        float[3](0.0, 200.0 * g[1], -200.0 * g[2])
    );
    float j[3][3];
    for (uint rr = 0u; rr < 3u; rr++) {
        for (uint c = 0u; c < 3u; c++) {
            j[rr][c] = d[rr][0] * @lower@_f(@XYZ@u + c) + d[rr][1] * @lower@_f(@XYZ@u + 3u + c) + d[rr][2] * @lower@_f(@XYZ@u + 6u + c);
        }
    }
    float size;
    size = 0.0;
    for (uint rr = 0u; rr < 3u; rr++) {
        for (uint i = 0u; i < @N@u; i++) {
            float av;
            av = j[rr][0] * @lower@_f(i) + j[rr][1] * @lower@_f(@N@u + i) + j[rr][2] * @lower@_f(2u * @N@u + i);
            size = size + av * av;
        }
    }
    float scale;
    scale = sqrt(@NF@ / size);
    if (!(scale > 0.0 && scale <= 3.4028235e38)) {
        return r;
    }
    // The scaled differential s J, and each node's column of A = s J W.
    float sj[3][3];
    for (uint rr = 0u; rr < 3u; rr++) {
        for (uint c = 0u; c < 3u; c++) {
            sj[rr][c] = j[rr][c] * scale;
        }
    }
    float a[3 * @N@];
    for (uint rr = 0u; rr < 3u; rr++) {
        for (uint i = 0u; i < @N@u; i++) {
            a[rr * @N@u + i] = sj[rr][0] * @lower@_f(i) + sj[rr][1] * @lower@_f(@N@u + i) + sj[rr][2] * @lower@_f(2u * @N@u + i);
        }
    }
    float e[3];
    for (uint k = 0u; k < 3u; k++) {
        float ev;
        ev = p[k];
        for (uint i = 0u; i < @N@u; i++) {
            ev = ev - @lower@_f(k * @N@u + i) * r[i];
        }
        e[k] = ev;
    }
    // The active-set method on the box: z = x - r, held[i] 0 (free), -1 (at 0) or 1 (at 1);
    // refused[i] 1 where a trial release moved i outward at once since z last moved.
    float z[@N@];
    int held[@N@];
    uint refused[@N@];
    for (uint i = 0u; i < @N@u; i++) {
        z[i] = 0.0;
        held[i] = 0;
        refused[i] = 0u;
    }
    int trial;
    trial = -1;
    for (uint it = 0u; it < @STEPS@u; it++) {
        float dv[3];
        dv = e;
        uint n_free;
        n_free = 0u;
        for (uint i = 0u; i < @N@u; i++) {
            if (held[i] != 0) {
                for (uint c = 0u; c < 3u; c++) {
                    dv[c] = dv[c] - @lower@_f(c * @N@u + i) * z[i];
                }
            } else {
                n_free = n_free + 1u;
            }
        }
        float t[3];
        for (uint c = 0u; c < 3u; c++) {
            t[c] = sj[c][0] * dv[0] + sj[c][1] * dv[1] + sj[c][2] * dv[2];
        }
        // The free values' weights: an orthonormal basis q[0..m] of the channels' rows on the
        // free values, gq[l][c] the coefficient of q[l] in channel c (Gram-Schmidt, largest
        // remaining row first, twice).
        float v[3 * @N@];
        float q[3 * @N@];
        for (uint c = 0u; c < 3u; c++) {
            for (uint i = 0u; i < @N@u; i++) {
                q[c * @N@u + i] = 0.0;
                if (held[i] == 0) {
                    v[c * @N@u + i] = @lower@_f(c * @N@u + i);
                } else {
                    v[c * @N@u + i] = 0.0;
                }
            }
        }
        float gq[3][3];
        gq = float[3][3](float[3](0.0, 0.0, 0.0), float[3](0.0, 0.0, 0.0), float[3](0.0, 0.0, 0.0));
        uint done[3];
        done = uint[3](0u, 0u, 0u);
        uint m;
        m = 0u;
        uint max_rank;
        max_rank = min(n_free, 3u);
        while (m < max_rank) {
            int pick;
            pick = -1;
            float largest;
            largest = 0.0;
            for (uint c = 0u; c < 3u; c++) {
                if (done[c] != 0u) {
                    continue;
                }
                float n2;
                n2 = 0.0;
                for (uint i = 0u; i < @N@u; i++) {
                    n2 = n2 + v[c * @N@u + i] * v[c * @N@u + i];
                }
                if (!(n2 <= 3.4028235e38)) {
                    return r;
                }
                if (n2 > largest) {
                    largest = n2;
                    pick = int(c);
                }
            }
            if (pick < 0) {
                break;
            }
            uint c;
            c = uint(pick);
            done[c] = 1u;
            for (uint sweep = 0u; sweep < 2u; sweep++) {
                for (uint k = 0u; k < m; k++) {
                    float dot_;
                    dot_ = 0.0;
                    for (uint i = 0u; i < @N@u; i++) {
                        dot_ = dot_ + q[k * @N@u + i] * v[c * @N@u + i];
                    }
                    gq[k][c] = gq[k][c] + dot_;
                    for (uint i = 0u; i < @N@u; i++) {
                        v[c * @N@u + i] = v[c * @N@u + i] - dot_ * q[k * @N@u + i];
                    }
                }
            }
            float n2;
            n2 = 0.0;
            for (uint i = 0u; i < @N@u; i++) {
                n2 = n2 + v[c * @N@u + i] * v[c * @N@u + i];
            }
            if (!(n2 > 0.0)) {
                break;
            }
            float norm;
            norm = sqrt(n2);
            for (uint i = 0u; i < @N@u; i++) {
                q[m * @N@u + i] = v[c * @N@u + i] / norm;
            }
            gq[m][c] = norm;
            for (uint c2 = 0u; c2 < 3u; c2++) {
                if (done[c2] != 0u) {
                    continue;
                }
                for (uint sweep = 0u; sweep < 2u; sweep++) {
                    float dot_;
                    dot_ = 0.0;
                    for (uint i = 0u; i < @N@u; i++) {
                        dot_ = dot_ + q[m * @N@u + i] * v[c2 * @N@u + i];
                    }
                    gq[m][c2] = gq[m][c2] + dot_;
                    for (uint i = 0u; i < @N@u; i++) {
                        v[c2 * @N@u + i] = v[c2 * @N@u + i] - dot_ * q[m * @N@u + i];
                    }
                }
            }
            m = m + 1u;
        }
        // C = s J G: the metric's change per unit of each basis vector.
        float cm[3][3];
        cm = float[3][3](float[3](0.0, 0.0, 0.0), float[3](0.0, 0.0, 0.0), float[3](0.0, 0.0, 0.0));
        for (uint c = 0u; c < 3u; c++) {
            for (uint l = 0u; l < m; l++) {
                cm[c][l] = sj[c][0] * gq[l][0] + sj[c][1] * gq[l][1] + sj[c][2] * gq[l][2];
            }
        }
        // u minimising |u|^2 + MU |C u - t|^2: [C; I / sqrt(MU)] = Q R by Gram-Schmidt twice.
        float qb[18];
        float rb[3][3];
        rb = float[3][3](float[3](0.0, 0.0, 0.0), float[3](0.0, 0.0, 0.0), float[3](0.0, 0.0, 0.0));
        for (uint l = 0u; l < m; l++) {
            float w6[6];
            w6 = float[6](cm[0][l], cm[1][l], cm[2][l], 0.0, 0.0, 0.0);
            w6[3u + l] = @ISQMU@;
            for (uint sweep = 0u; sweep < 2u; sweep++) {
                for (uint k = 0u; k < l; k++) {
                    float dot_;
                    dot_ = 0.0;
                    for (uint i = 0u; i < 6u; i++) {
                        dot_ = dot_ + qb[k * 6u + i] * w6[i];
                    }
                    rb[k][l] = rb[k][l] + dot_;
                    for (uint i = 0u; i < 6u; i++) {
                        w6[i] = w6[i] - dot_ * qb[k * 6u + i];
                    }
                }
            }
            float n2;
            n2 = 0.0;
            for (uint i = 0u; i < 6u; i++) {
                n2 = n2 + w6[i] * w6[i];
            }
            float norm;
            norm = sqrt(n2);
            if (!(norm > 0.0 && norm <= 3.4028235e38)) {
                return r;
            }
            rb[l][l] = norm;
            for (uint i = 0u; i < 6u; i++) {
                qb[l * 6u + i] = w6[i] / norm;
            }
        }
        float u[3];
        u = float[3](0.0, 0.0, 0.0);
        for (uint ll = 0u; ll < m; ll++) {
            uint l;
            l = m - 1u - ll;
            float s;
            s = qb[l * 6u] * t[0] + qb[l * 6u + 1u] * t[1] + qb[l * 6u + 2u] * t[2];
            for (uint k = l + 1u; k < m; k++) {
                s = s - rb[l][k] * u[k];
            }
            u[l] = s / rb[l][l];
        }
        float goal[@N@];
        for (uint i = 0u; i < @N@u; i++) {
            goal[i] = 0.0;
        }
        for (uint l = 0u; l < m; l++) {
            for (uint i = 0u; i < @N@u; i++) {
                goal[i] = goal[i] + u[l] * q[l * @N@u + i];
            }
        }
        float stepv;
        stepv = 1.0;
        int blocking;
        blocking = -1;
        int side;
        side = 0;
        for (uint i = 0u; i < @N@u; i++) {
            if (held[i] != 0) {
                continue;
            }
            float ti;
            ti = goal[i];
            float lo;
            lo = -r[i];
            float hi;
            hi = 1.0 - r[i];
            float ratio;
            ratio = 2.0;
            int sd;
            sd = 0;
            if (ti < lo) {
                ratio = (z[i] - lo) / (z[i] - ti);
                sd = -1;
            } else if (ti > hi) {
                ratio = (hi - z[i]) / (ti - z[i]);
                sd = 1;
            }
            if (sd != 0) {
                ratio = clamp(ratio, 0.0, 1.0);
                if (ratio < stepv || (blocking < 0 && ratio <= stepv)) {
                    stepv = ratio;
                    blocking = int(i);
                    side = sd;
                }
            }
        }
        for (uint i = 0u; i < @N@u; i++) {
            if (held[i] == 0) {
                z[i] = z[i] + stepv * (goal[i] - z[i]);
            }
        }
        if (stepv > 0.0) {
            for (uint i = 0u; i < @N@u; i++) {
                refused[i] = 0u;
            }
        }
        if (blocking >= 0) {
            uint bi;
            bi = uint(blocking);
            held[bi] = side;
            if (side < 0) {
                z[bi] = -r[bi];
            } else {
                z[bi] = 1.0 - r[bi];
            }
            if (stepv == 0.0 && trial == blocking) {
                refused[bi] = 1u;
            }
            trial = -1;
            continue;
        }
        // The multiplier y = MU (t - C u): Q_C R_C^-T u in C's range (C = Q_C R_C by
        // Gram-Schmidt twice), plus MU times the target's part outside it.
        float qc[3][3];
        qc = float[3][3](float[3](0.0, 0.0, 0.0), float[3](0.0, 0.0, 0.0), float[3](0.0, 0.0, 0.0));
        float rc[3][3];
        rc = float[3][3](float[3](0.0, 0.0, 0.0), float[3](0.0, 0.0, 0.0), float[3](0.0, 0.0, 0.0));
        for (uint l = 0u; l < m; l++) {
            float w3[3];
            w3 = float[3](cm[0][l], cm[1][l], cm[2][l]);
            for (uint sweep = 0u; sweep < 2u; sweep++) {
                for (uint k = 0u; k < l; k++) {
                    float dot_;
                    dot_ = qc[k][0] * w3[0] + qc[k][1] * w3[1] + qc[k][2] * w3[2];
                    rc[k][l] = rc[k][l] + dot_;
                    for (uint i = 0u; i < 3u; i++) {
                        w3[i] = w3[i] - dot_ * qc[k][i];
                    }
                }
            }
            float norm;
            norm = sqrt(w3[0] * w3[0] + w3[1] * w3[1] + w3[2] * w3[2]);
            if (!(norm > 0.0 && norm <= 3.4028235e38)) {
                return r;
            }
            rc[l][l] = norm;
            for (uint i = 0u; i < 3u; i++) {
                qc[l][i] = w3[i] / norm;
            }
        }
        float sv[3];
        sv = float[3](0.0, 0.0, 0.0);
        for (uint l = 0u; l < m; l++) {
            float acc;
            acc = u[l];
            for (uint k = 0u; k < l; k++) {
                acc = acc - rc[k][l] * sv[k];
            }
            sv[l] = acc / rc[l][l];
        }
        float y[3];
        y = float[3](0.0, 0.0, 0.0);
        float outside[3];
        outside = t;
        for (uint l = 0u; l < m; l++) {
            float along;
            along = qc[l][0] * t[0] + qc[l][1] * t[1] + qc[l][2] * t[2];
            for (uint i = 0u; i < 3u; i++) {
                y[i] = y[i] + sv[l] * qc[l][i];
                outside[i] = outside[i] - along * qc[l][i];
            }
        }
        if (m < 3u) {
            for (uint i = 0u; i < 3u; i++) {
                y[i] = y[i] + @MU@ * outside[i];
            }
        }
        // Release the held value whose multiplier pulls outward most, or one within
        // RELEASE_TRIAL of its terms' size on trial; or stop.
        float worst;
        worst = -3.4028235e38;
        int release;
        release = -1;
        for (uint i = 0u; i < @N@u; i++) {
            if (held[i] == 0 || refused[i] != 0u) {
                continue;
            }
            float a0;
            a0 = a[i] * y[0];
            float a1;
            a1 = a[@N@u + i] * y[1];
            float a2;
            a2 = a[2u * @N@u + i] * y[2];
            float gi;
            gi = z[i] - (a0 + a1 + a2);
            float pull;
            pull = gi;
            if (held[i] < 0) {
                pull = -gi;
            }
            float sz;
            sz = abs(z[i]) + abs(a0) + abs(a1) + abs(a2);
            if (pull > -@TRIAL@ * sz && pull > worst) {
                worst = pull;
                release = int(i);
            }
        }
        if (release < 0) {
            break;
        }
        held[uint(release)] = 0;
        trial = release;
    }
    for (uint i = 0u; i < @N@u; i++) {
        float x;
        x = clamp(r[i] + z[i], 0.0, 1.0);
        r[i] = clamp(r[i] + phase * (x - r[i]), 0.0, 1.0);
    }
    return r;
}

float[@N@] @lower@_reflectance(vec3 rgb) {
    vec3 p;
    p = @CLAMP@;
    uvec3 cell;
    cell = min(uvec3(p * @CELLS@), uvec3(@G2@u));
    return @lower@_round_trip(p, (cell.x * @G1@u + cell.y) * @G1@u + cell.z, @lower@_interpolate(rgb));
}
