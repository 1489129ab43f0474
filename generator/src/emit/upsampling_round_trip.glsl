// @NAME@ (each local assigned apart from its declaration; the 3 x N matrix flat, as some compilers read float[3][N] the other way round): the runtime's Upsampling::reflectance: @lower@_interpolate, then in a cell at the edge of what the set reaches the round-trip correction (RoundTrip), reading its data from @NAME@_CODES after the table: the edge cells' bits from word @E@, then as f32 bits the weights (3 x @N@), RGB to XYZ (3 x 3) and the rounding (3) from word @F@.
float @lower@_f(uint i) {
    return uintBitsToFloat(@NAME@_CODES[@F@u + i]);
}

// Cholesky solve of a symmetric positive definite 3 x 3 system; w = 0 where a pivot is not positive and finite.
vec4 @lower@_solve3(float m[3][3], float b[3]) {
    float l[3][3];
    for (uint i = 0u; i < 3u; i++) {
        for (uint k = 0u; k <= i; k++) {
            float s;
            s = m[i][k];
            for (uint q = 0u; q < k; q++) {
                s = s - l[i][q] * l[k][q];
            }
            if (i == k) {
                if (!(s > 0.0 && s <= 3.4028235e38)) {
                    return vec4(0.0);
                }
                l[i][i] = sqrt(s);
            } else {
                l[i][k] = s / l[k][k];
            }
        }
    }
    float y[3];
    for (uint i = 0u; i < 3u; i++) {
        float s;
        s = b[i];
        for (uint q = 0u; q < i; q++) {
            s = s - l[i][q] * y[q];
        }
        y[i] = s / l[i][i];
    }
    float x[3];
    for (uint ii = 0u; ii < 3u; ii++) {
        uint i;
        i = 2u - ii;
        float s;
        s = y[i];
        for (uint q = i + 1u; q < 3u; q++) {
            s = s - l[q][i] * x[q];
        }
        x[i] = s / l[i][i];
    }
    return vec4(x[0], x[1], x[2], 1.0);
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
    float a[3 * @N@];
    float size;
    size = 0.0;
    for (uint rr = 0u; rr < 3u; rr++) {
        for (uint i = 0u; i < @N@u; i++) {
            float av;
            av = j[rr][0] * @lower@_f(i) + j[rr][1] * @lower@_f(@N@u + i) + j[rr][2] * @lower@_f(2u * @N@u + i);
            a[rr * @N@u + i] = av;
            size = size + av * av;
        }
    }
    float scale;
    scale = sqrt(@NF@ / size);
    if (!(scale > 0.0 && scale <= 3.4028235e38)) {
        return r;
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
    float t[3];
    for (uint c = 0u; c < 3u; c++) {
        t[c] = scale * (j[c][0] * e[0] + j[c][1] * e[1] + j[c][2] * e[2]);
    }
    for (uint rr = 0u; rr < 3u; rr++) {
        for (uint i = 0u; i < @N@u; i++) {
            a[rr * @N@u + i] = a[rr * @N@u + i] * scale;
        }
    }
    // The active-set method on the box: z = x - r, held[i] 0 (free), -1 (at 0) or 1 (at 1).
    float z[@N@];
    int held[@N@];
    for (uint i = 0u; i < @N@u; i++) {
        z[i] = 0.0;
        held[i] = 0;
    }
    for (uint it = 0u; it < @STEPS@u; it++) {
        float b[3];
        b = t;
        uint freed[3];
        freed = uint[3](0u, 0u, 0u);
        uint n_free;
        n_free = 0u;
        for (uint i = 0u; i < @N@u; i++) {
            if (held[i] != 0) {
                for (uint c = 0u; c < 3u; c++) {
                    b[c] = b[c] - a[c * @N@u + i] * z[i];
                }
            } else {
                if (n_free < 3u) {
                    freed[n_free] = i;
                }
                n_free = n_free + 1u;
            }
        }
        float goal[@N@];
        for (uint i = 0u; i < @N@u; i++) {
            goal[i] = 0.0;
        }
        float y[3];
        if (n_free >= 3u) {
            float m[3][3];
            m = float[3][3](float[3](0.0, 0.0, 0.0), float[3](0.0, 0.0, 0.0), float[3](0.0, 0.0, 0.0));
            for (uint i = 0u; i < @N@u; i++) {
                if (held[i] == 0) {
                    for (uint c = 0u; c < 3u; c++) {
                        for (uint k = 0u; k < 3u; k++) {
                            m[c][k] = m[c][k] + a[c * @N@u + i] * a[k * @N@u + i];
                        }
                    }
                }
            }
            for (uint c = 0u; c < 3u; c++) {
                m[c][c] = m[c][c] + @IMU@;
            }
            vec4 sol;
            sol = @lower@_solve3(m, b);
            if (sol.w == 0.0) {
                return r;
            }
            y = float[3](sol.x, sol.y, sol.z);
            for (uint i = 0u; i < @N@u; i++) {
                if (held[i] == 0) {
                    goal[i] = a[0 * @N@u + i] * y[0] + a[1 * @N@u + i] * y[1] + a[2 * @N@u + i] * y[2];
                }
            }
        } else {
            float m[3][3];
            m = float[3][3](float[3](0.0, 0.0, 0.0), float[3](0.0, 0.0, 0.0), float[3](0.0, 0.0, 0.0));
            float rhs[3];
            rhs = float[3](0.0, 0.0, 0.0);
            for (uint pp = 0u; pp < 3u; pp++) {
                if (pp >= n_free) {
                    m[pp][pp] = 1.0;
                } else {
                    uint ip;
                    ip = freed[pp];
                    rhs[pp] = a[0 * @N@u + ip] * b[0] + a[1 * @N@u + ip] * b[1] + a[2 * @N@u + ip] * b[2];
                    for (uint q = 0u; q < n_free; q++) {
                        uint iq;
                        iq = freed[q];
                        m[pp][q] = a[0 * @N@u + ip] * a[0 * @N@u + iq] + a[1 * @N@u + ip] * a[1 * @N@u + iq] + a[2 * @N@u + ip] * a[2 * @N@u + iq];
                    }
                    m[pp][pp] = m[pp][pp] + @IMU@;
                }
            }
            vec4 sol;
            sol = @lower@_solve3(m, rhs);
            if (sol.w == 0.0) {
                return r;
            }
            float zf[3];
            zf = float[3](sol.x, sol.y, sol.z);
            float res[3];
            res = b;
            for (uint pp = 0u; pp < n_free; pp++) {
                uint ip;
                ip = freed[pp];
                goal[ip] = zf[pp];
                for (uint c = 0u; c < 3u; c++) {
                    res[c] = res[c] - a[c * @N@u + ip] * zf[pp];
                }
            }
            y = float[3](@MU@ * res[0], @MU@ * res[1], @MU@ * res[2]);
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
        if (blocking >= 0) {
            uint bi;
            bi = uint(blocking);
            held[bi] = side;
            if (side < 0) {
                z[bi] = -r[bi];
            } else {
                z[bi] = 1.0 - r[bi];
            }
            continue;
        }
        float worst;
        worst = @FREE@;
        int release;
        release = -1;
        for (uint i = 0u; i < @N@u; i++) {
            if (held[i] == 0) {
                continue;
            }
            float gi;
            gi = z[i] - (a[0 * @N@u + i] * y[0] + a[1 * @N@u + i] * y[1] + a[2 * @N@u + i] * y[2]);
            float pull;
            pull = gi;
            if (held[i] < 0) {
                pull = -gi;
            }
            if (pull > worst) {
                worst = pull;
                release = int(i);
            }
        }
        if (release < 0) {
            break;
        }
        held[uint(release)] = 0;
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
