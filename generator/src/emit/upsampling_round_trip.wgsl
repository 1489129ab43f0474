// @NAME@: the runtime's Upsampling::reflectance: @lower@_interpolate, then in a cell at the edge of what the set reaches the round-trip correction (RoundTrip), reading its data from @NAME@_CODES after the table: the edge cells' bits from word @E@, then as f32 bits the weights (3 x @N@), RGB to XYZ (3 x 3) and the rounding (3) from word @F@.
fn @lower@_f(i: u32) -> f32 {
    return bitcast<f32>(@NAME@_CODES[@F@u + i]);
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
    var size = 0.0;
    for (var rr = 0u; rr < 3u; rr = rr + 1u) {
        for (var i = 0u; i < @N@u; i = i + 1u) {
            let av = j[rr][0] * @lower@_f(i) + j[rr][1] * @lower@_f(@N@u + i) + j[rr][2] * @lower@_f(2u * @N@u + i);
            size = size + av * av;
        }
    }
    let scale = sqrt(@NF@ / size);
    if (!(scale > 0.0 && scale <= 3.4028235e38)) {
        return r;
    }
    // The scaled differential s J, and each node's column of A = s J W.
    var sj: array<array<f32, 3>, 3>;
    for (var rr = 0u; rr < 3u; rr = rr + 1u) {
        for (var c = 0u; c < 3u; c = c + 1u) {
            sj[rr][c] = j[rr][c] * scale;
        }
    }
    var a: array<array<f32, @N@>, 3>;
    for (var rr = 0u; rr < 3u; rr = rr + 1u) {
        for (var i = 0u; i < @N@u; i = i + 1u) {
            a[rr][i] = sj[rr][0] * @lower@_f(i) + sj[rr][1] * @lower@_f(@N@u + i) + sj[rr][2] * @lower@_f(2u * @N@u + i);
        }
    }
    var e: array<f32, 3>;
    for (var k = 0u; k < 3u; k = k + 1u) {
        var ev = p[k];
        for (var i = 0u; i < @N@u; i = i + 1u) {
            ev = ev - @lower@_f(k * @N@u + i) * r[i];
        }
        e[k] = ev;
    }
    // The active-set method on the box: z = x - r, held[i] 0 (free), -1 (at 0) or 1 (at 1);
    // refused[i] 1 where a trial release moved i outward at once since z last moved.
    var z: array<f32, @N@>;
    var held: array<i32, @N@>;
    var refused: array<u32, @N@>;
    var trial = -1;
    for (var it = 0u; it < @STEPS@u; it = it + 1u) {
        var dv = e;
        var n_free = 0u;
        for (var i = 0u; i < @N@u; i = i + 1u) {
            if (held[i] != 0) {
                for (var c = 0u; c < 3u; c = c + 1u) {
                    dv[c] = dv[c] - @lower@_f(c * @N@u + i) * z[i];
                }
            } else {
                n_free = n_free + 1u;
            }
        }
        var t: array<f32, 3>;
        for (var c = 0u; c < 3u; c = c + 1u) {
            t[c] = sj[c][0] * dv[0] + sj[c][1] * dv[1] + sj[c][2] * dv[2];
        }
        // The free values' weights: an orthonormal basis q[0..m] of the channels' rows on the
        // free values, g[l][c] the coefficient of q[l] in channel c (Gram-Schmidt, largest
        // remaining row first, twice).
        var v: array<array<f32, @N@>, 3>;
        for (var c = 0u; c < 3u; c = c + 1u) {
            for (var i = 0u; i < @N@u; i = i + 1u) {
                if (held[i] == 0) {
                    v[c][i] = @lower@_f(c * @N@u + i);
                }
            }
        }
        var q: array<array<f32, @N@>, 3>;
        var gq: array<array<f32, 3>, 3>;
        var done = array<u32, 3>(0u, 0u, 0u);
        var m = 0u;
        let max_rank = min(n_free, 3u);
        while (m < max_rank) {
            var pick = -1;
            var largest = 0.0;
            for (var c = 0u; c < 3u; c = c + 1u) {
                if (done[c] != 0u) {
                    continue;
                }
                var n2 = 0.0;
                for (var i = 0u; i < @N@u; i = i + 1u) {
                    n2 = n2 + v[c][i] * v[c][i];
                }
                if (!(n2 <= 3.4028235e38)) {
                    return r;
                }
                if (n2 > largest) {
                    largest = n2;
                    pick = i32(c);
                }
            }
            if (pick < 0) {
                break;
            }
            let c = u32(pick);
            done[c] = 1u;
            for (var sweep = 0u; sweep < 2u; sweep = sweep + 1u) {
                for (var k = 0u; k < m; k = k + 1u) {
                    var dt = 0.0;
                    for (var i = 0u; i < @N@u; i = i + 1u) {
                        dt = dt + q[k][i] * v[c][i];
                    }
                    gq[k][c] = gq[k][c] + dt;
                    for (var i = 0u; i < @N@u; i = i + 1u) {
                        v[c][i] = v[c][i] - dt * q[k][i];
                    }
                }
            }
            var n2 = 0.0;
            for (var i = 0u; i < @N@u; i = i + 1u) {
                n2 = n2 + v[c][i] * v[c][i];
            }
            if (!(n2 > 0.0)) {
                break;
            }
            let norm = sqrt(n2);
            for (var i = 0u; i < @N@u; i = i + 1u) {
                q[m][i] = v[c][i] / norm;
            }
            gq[m][c] = norm;
            for (var c2 = 0u; c2 < 3u; c2 = c2 + 1u) {
                if (done[c2] != 0u) {
                    continue;
                }
                for (var sweep = 0u; sweep < 2u; sweep = sweep + 1u) {
                    var dt = 0.0;
                    for (var i = 0u; i < @N@u; i = i + 1u) {
                        dt = dt + q[m][i] * v[c2][i];
                    }
                    gq[m][c2] = gq[m][c2] + dt;
                    for (var i = 0u; i < @N@u; i = i + 1u) {
                        v[c2][i] = v[c2][i] - dt * q[m][i];
                    }
                }
            }
            m = m + 1u;
        }
        // C = s J G: the metric's change per unit of each basis vector.
        var cm: array<array<f32, 3>, 3>;
        for (var c = 0u; c < 3u; c = c + 1u) {
            for (var l = 0u; l < m; l = l + 1u) {
                cm[c][l] = sj[c][0] * gq[l][0] + sj[c][1] * gq[l][1] + sj[c][2] * gq[l][2];
            }
        }
        // u minimising |u|^2 + MU |C u - t|^2: [C; I / sqrt(MU)] = Q R by Gram-Schmidt twice.
        var qb: array<array<f32, 6>, 3>;
        var rb: array<array<f32, 3>, 3>;
        for (var l = 0u; l < m; l = l + 1u) {
            var w6 = array<f32, 6>(cm[0][l], cm[1][l], cm[2][l], 0.0, 0.0, 0.0);
            w6[3u + l] = @ISQMU@;
            for (var sweep = 0u; sweep < 2u; sweep = sweep + 1u) {
                for (var k = 0u; k < l; k = k + 1u) {
                    var dt = 0.0;
                    for (var i = 0u; i < 6u; i = i + 1u) {
                        dt = dt + qb[k][i] * w6[i];
                    }
                    rb[k][l] = rb[k][l] + dt;
                    for (var i = 0u; i < 6u; i = i + 1u) {
                        w6[i] = w6[i] - dt * qb[k][i];
                    }
                }
            }
            var n2 = 0.0;
            for (var i = 0u; i < 6u; i = i + 1u) {
                n2 = n2 + w6[i] * w6[i];
            }
            let norm = sqrt(n2);
            if (!(norm > 0.0 && norm <= 3.4028235e38)) {
                return r;
            }
            rb[l][l] = norm;
            for (var i = 0u; i < 6u; i = i + 1u) {
                qb[l][i] = w6[i] / norm;
            }
        }
        var u: array<f32, 3>;
        for (var ll = 0u; ll < m; ll = ll + 1u) {
            let l = m - 1u - ll;
            var s = qb[l][0] * t[0] + qb[l][1] * t[1] + qb[l][2] * t[2];
            for (var k = l + 1u; k < m; k = k + 1u) {
                s = s - rb[l][k] * u[k];
            }
            u[l] = s / rb[l][l];
        }
        var goal: array<f32, @N@>;
        for (var l = 0u; l < m; l = l + 1u) {
            for (var i = 0u; i < @N@u; i = i + 1u) {
                goal[i] = goal[i] + u[l] * q[l][i];
            }
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
        if (stepv > 0.0) {
            for (var i = 0u; i < @N@u; i = i + 1u) {
                refused[i] = 0u;
            }
        }
        if (blocking >= 0) {
            let bi = u32(blocking);
            held[bi] = side;
            z[bi] = select(1.0 - r[bi], -r[bi], side < 0);
            if (stepv == 0.0 && trial == blocking) {
                refused[bi] = 1u;
            }
            trial = -1;
            continue;
        }
        // The multiplier y = MU (t - C u): Q_C R_C^-T u in C's range (C = Q_C R_C by
        // Gram-Schmidt twice), plus MU times the target's part outside it.
        var qc: array<array<f32, 3>, 3>;
        var rc: array<array<f32, 3>, 3>;
        for (var l = 0u; l < m; l = l + 1u) {
            var w3 = array<f32, 3>(cm[0][l], cm[1][l], cm[2][l]);
            for (var sweep = 0u; sweep < 2u; sweep = sweep + 1u) {
                for (var k = 0u; k < l; k = k + 1u) {
                    let dt = qc[k][0] * w3[0] + qc[k][1] * w3[1] + qc[k][2] * w3[2];
                    rc[k][l] = rc[k][l] + dt;
                    for (var i = 0u; i < 3u; i = i + 1u) {
                        w3[i] = w3[i] - dt * qc[k][i];
                    }
                }
            }
            let norm = sqrt(w3[0] * w3[0] + w3[1] * w3[1] + w3[2] * w3[2]);
            if (!(norm > 0.0 && norm <= 3.4028235e38)) {
                return r;
            }
            rc[l][l] = norm;
            for (var i = 0u; i < 3u; i = i + 1u) {
                qc[l][i] = w3[i] / norm;
            }
        }
        var sv: array<f32, 3>;
        for (var l = 0u; l < m; l = l + 1u) {
            var acc = u[l];
            for (var k = 0u; k < l; k = k + 1u) {
                acc = acc - rc[k][l] * sv[k];
            }
            sv[l] = acc / rc[l][l];
        }
        var y: array<f32, 3>;
        var outside = t;
        for (var l = 0u; l < m; l = l + 1u) {
            let along = qc[l][0] * t[0] + qc[l][1] * t[1] + qc[l][2] * t[2];
            for (var i = 0u; i < 3u; i = i + 1u) {
                y[i] = y[i] + sv[l] * qc[l][i];
                outside[i] = outside[i] - along * qc[l][i];
            }
        }
        if (m < 3u) {
            for (var i = 0u; i < 3u; i = i + 1u) {
                y[i] = y[i] + @MU@ * outside[i];
            }
        }
        // Release the held value whose multiplier pulls outward most, or one within
        // RELEASE_TRIAL of its terms' size on trial; or stop.
        var worst = -3.4028235e38;
        var release = -1;
        for (var i = 0u; i < @N@u; i = i + 1u) {
            if (held[i] == 0 || refused[i] != 0u) {
                continue;
            }
            let a0 = a[0][i] * y[0];
            let a1 = a[1][i] * y[1];
            let a2 = a[2][i] * y[2];
            let gi = z[i] - (a0 + a1 + a2);
            let pull = select(gi, -gi, held[i] < 0);
            let sz = abs(z[i]) + abs(a0) + abs(a1) + abs(a2);
            if (pull > -@TRIAL@ * sz && pull > worst) {
                worst = pull;
                release = i32(i);
            }
        }
        if (release < 0) {
            break;
        }
        held[u32(release)] = 0;
        trial = release;
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
