// @NAME@: the runtime's Upsampling::reflectance: @lower@_interpolate, then in a cell at the edge of what the set reaches the round-trip correction (RoundTrip), reading its data from @NAME@_CODES after the table: the edge cells' bits from word @E@, then as f32 bits the weights (3 x @N@), RGB to XYZ (3 x 3) and the rounding (3) from word @F@.
fn @lower@_f(i: u32) -> f32 {
    return bitcast<f32>(@NAME@_CODES[@F@u + i]);
}

// Cholesky solve of a symmetric positive definite 3 x 3 system; w = 0 where a pivot is not positive and finite.
fn @lower@_solve3(m: array<array<f32, 3>, 3>, b: array<f32, 3>) -> vec4<f32> {
    var l: array<array<f32, 3>, 3>;
    for (var i = 0u; i < 3u; i = i + 1u) {
        for (var k = 0u; k <= i; k = k + 1u) {
            var s = m[i][k];
            for (var q = 0u; q < k; q = q + 1u) {
                s = s - l[i][q] * l[k][q];
            }
            if (i == k) {
                if (!(s > 0.0 && s <= 3.4028235e38)) {
                    return vec4<f32>(0.0, 0.0, 0.0, 0.0);
                }
                l[i][i] = sqrt(s);
            } else {
                l[i][k] = s / l[k][k];
            }
        }
    }
    var y: array<f32, 3>;
    for (var i = 0u; i < 3u; i = i + 1u) {
        var s = b[i];
        for (var q = 0u; q < i; q = q + 1u) {
            s = s - l[i][q] * y[q];
        }
        y[i] = s / l[i][i];
    }
    var x: array<f32, 3>;
    for (var ii = 0u; ii < 3u; ii = ii + 1u) {
        let i = 2u - ii;
        var s = y[i];
        for (var q = i + 1u; q < 3u; q = q + 1u) {
            s = s - l[q][i] * x[q];
        }
        x[i] = s / l[i][i];
    }
    return vec4<f32>(x[0], x[1], x[2], 1.0);
}

fn @lower@_round_trip(pv: vec3<f32>, cell: u32, r_in: array<f32, @N@>) -> array<f32, @N@> {
    var r = r_in;
    if (((@NAME@_CODES[@E@u + (cell >> 5u)] >> (cell & 31u)) & 1u) == 0u) {
        return r;
    }
    var p = array<f32, 3>(pv.x, pv.y, pv.z);
    var gate = 0.0;
    for (var c = 0u; c < 3u; c = c + 1u) {
        var ec = p[c];
        for (var i = 0u; i < @N@u; i = i + 1u) {
            ec = ec - @lower@_f(c * @N@u + i) * r[i];
        }
        gate = max(gate, abs(ec) / @lower@_f(@ROUND@u + c));
    }
    if (!(gate > @KEEP@)) {
        return r;
    }
    let phase = min((gate - @KEEP@) / (@FULL@ - @KEEP@), 1.0);
    // CIELAB's differential at p.
    var g: array<f32, 3>;
    for (var c = 0u; c < 3u; c = c + 1u) {
        let m0 = @lower@_f(@XYZ@u + 3u * c);
        let m1 = @lower@_f(@XYZ@u + 3u * c + 1u);
        let m2 = @lower@_f(@XYZ@u + 3u * c + 2u);
        let white = m0 + m1 + m2;
        let tc = (m0 * p[0] + m1 * p[1] + m2 * p[2]) / white;
        var slope = @LIN@;
        if (tc > @D3@) {
            // The runtime's f32 cube root: an estimate from the bits, three Newton steps.
            var q = bitcast<f32>(bitcast<u32>(tc) / 3u + 709958130u);
            for (var k = 0u; k < 3u; k = k + 1u) {
                q = (2.0 * q + tc / (q * q)) * @THIRD@;
            }
            slope = 1.0 / (3.0 * q * q);
        }
        g[c] = slope / white;
    }
    var d = array<array<f32, 3>, 3>(
        array<f32, 3>(0.0, 116.0 * g[1], 0.0),
        array<f32, 3>(500.0 * g[0], -500.0 * g[1], 0.0),
        array<f32, 3>(0.0, 200.0 * g[1], -200.0 * g[2]),
    );
    var j: array<array<f32, 3>, 3>;
    for (var rr = 0u; rr < 3u; rr = rr + 1u) {
        for (var c = 0u; c < 3u; c = c + 1u) {
            j[rr][c] = d[rr][0] * @lower@_f(@XYZ@u + c) + d[rr][1] * @lower@_f(@XYZ@u + 3u + c) + d[rr][2] * @lower@_f(@XYZ@u + 6u + c);
        }
    }
    var a: array<array<f32, @N@>, 3>;
    var size = 0.0;
    for (var rr = 0u; rr < 3u; rr = rr + 1u) {
        for (var i = 0u; i < @N@u; i = i + 1u) {
            let av = j[rr][0] * @lower@_f(i) + j[rr][1] * @lower@_f(@N@u + i) + j[rr][2] * @lower@_f(2u * @N@u + i);
            a[rr][i] = av;
            size = size + av * av;
        }
    }
    let scale = sqrt(@NF@ / size);
    if (!(scale > 0.0 && scale <= 3.4028235e38)) {
        return r;
    }
    var e: array<f32, 3>;
    for (var k = 0u; k < 3u; k = k + 1u) {
        var ev = p[k];
        for (var i = 0u; i < @N@u; i = i + 1u) {
            ev = ev - @lower@_f(k * @N@u + i) * r[i];
        }
        e[k] = ev;
    }
    var t: array<f32, 3>;
    for (var c = 0u; c < 3u; c = c + 1u) {
        t[c] = scale * (j[c][0] * e[0] + j[c][1] * e[1] + j[c][2] * e[2]);
    }
    for (var rr = 0u; rr < 3u; rr = rr + 1u) {
        for (var i = 0u; i < @N@u; i = i + 1u) {
            a[rr][i] = a[rr][i] * scale;
        }
    }
    // The active-set method on the box: z = x - r, held[i] 0 (free), -1 (at 0) or 1 (at 1).
    var z: array<f32, @N@>;
    var held: array<i32, @N@>;
    for (var it = 0u; it < @STEPS@u; it = it + 1u) {
        var b = t;
        var freed = array<u32, 3>(0u, 0u, 0u);
        var n_free = 0u;
        for (var i = 0u; i < @N@u; i = i + 1u) {
            if (held[i] != 0) {
                for (var c = 0u; c < 3u; c = c + 1u) {
                    b[c] = b[c] - a[c][i] * z[i];
                }
            } else {
                if (n_free < 3u) {
                    freed[n_free] = i;
                }
                n_free = n_free + 1u;
            }
        }
        var goal: array<f32, @N@>;
        var y: array<f32, 3>;
        if (n_free >= 3u) {
            var m: array<array<f32, 3>, 3>;
            for (var i = 0u; i < @N@u; i = i + 1u) {
                if (held[i] == 0) {
                    for (var c = 0u; c < 3u; c = c + 1u) {
                        for (var k = 0u; k < 3u; k = k + 1u) {
                            m[c][k] = m[c][k] + a[c][i] * a[k][i];
                        }
                    }
                }
            }
            for (var c = 0u; c < 3u; c = c + 1u) {
                m[c][c] = m[c][c] + @IMU@;
            }
            let sol = @lower@_solve3(m, b);
            if (sol.w == 0.0) {
                return r;
            }
            y = array<f32, 3>(sol.x, sol.y, sol.z);
            for (var i = 0u; i < @N@u; i = i + 1u) {
                if (held[i] == 0) {
                    goal[i] = a[0][i] * y[0] + a[1][i] * y[1] + a[2][i] * y[2];
                }
            }
        } else {
            var m: array<array<f32, 3>, 3>;
            var rhs: array<f32, 3>;
            for (var pp = 0u; pp < 3u; pp = pp + 1u) {
                if (pp >= n_free) {
                    m[pp][pp] = 1.0;
                    continue;
                }
                let ip = freed[pp];
                rhs[pp] = a[0][ip] * b[0] + a[1][ip] * b[1] + a[2][ip] * b[2];
                for (var q = 0u; q < n_free; q = q + 1u) {
                    let iq = freed[q];
                    m[pp][q] = a[0][ip] * a[0][iq] + a[1][ip] * a[1][iq] + a[2][ip] * a[2][iq];
                }
                m[pp][pp] = m[pp][pp] + @IMU@;
            }
            let sol = @lower@_solve3(m, rhs);
            if (sol.w == 0.0) {
                return r;
            }
            let zf = array<f32, 3>(sol.x, sol.y, sol.z);
            var res = b;
            for (var pp = 0u; pp < n_free; pp = pp + 1u) {
                let ip = freed[pp];
                goal[ip] = zf[pp];
                for (var c = 0u; c < 3u; c = c + 1u) {
                    res[c] = res[c] - a[c][ip] * zf[pp];
                }
            }
            y = array<f32, 3>(@MU@ * res[0], @MU@ * res[1], @MU@ * res[2]);
        }
        var stepv = 1.0;
        var blocking = -1;
        var side = 0;
        for (var i = 0u; i < @N@u; i = i + 1u) {
            if (held[i] != 0) {
                continue;
            }
            let ti = goal[i];
            let lo = -r[i];
            let hi = 1.0 - r[i];
            var ratio = 2.0;
            var sd = 0;
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
                    blocking = i32(i);
                    side = sd;
                }
            }
        }
        for (var i = 0u; i < @N@u; i = i + 1u) {
            if (held[i] == 0) {
                z[i] = z[i] + stepv * (goal[i] - z[i]);
            }
        }
        if (blocking >= 0) {
            let bi = u32(blocking);
            held[bi] = side;
            z[bi] = select(1.0 - r[bi], -r[bi], side < 0);
            continue;
        }
        var worst = @FREE@;
        var release = -1;
        for (var i = 0u; i < @N@u; i = i + 1u) {
            if (held[i] == 0) {
                continue;
            }
            let gi = z[i] - (a[0][i] * y[0] + a[1][i] * y[1] + a[2][i] * y[2]);
            let pull = select(gi, -gi, held[i] < 0);
            if (pull > worst) {
                worst = pull;
                release = i32(i);
            }
        }
        if (release < 0) {
            break;
        }
        held[u32(release)] = 0;
    }
    for (var i = 0u; i < @N@u; i = i + 1u) {
        let x = clamp(r[i] + z[i], 0.0, 1.0);
        r[i] = clamp(r[i] + phase * (x - r[i]), 0.0, 1.0);
    }
    return r;
}

fn @lower@_reflectance(rgb: vec3<f32>) -> array<f32, @N@> {
    let p = @CLAMP@;
    let cell = min(vec3<u32>(p * @CELLS@), vec3<u32>(@G2@u));
    return @lower@_round_trip(p, (cell.x * @G1@u + cell.y) * @G1@u + cell.z, @lower@_interpolate(rgb));
}
