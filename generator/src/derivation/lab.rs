//! CIELAB and colour differences (ΔE*ab 1976 and CIEDE2000), in f64, for measuring the error
//! of a wavelength set.
//!
//! The same code as the runtime's `lab` module, with the transcendental functions from libm as
//! there, so both give the same bits (the runtime's `tests/delta_e.rs` checks it). It is a copy
//! because this crate cannot depend on the runtime, whose build script depends on this crate.

/// CIELAB `[L*, a*, b*]` of `xyz` relative to the reference `white` (both in the same units).
///
/// Never panics. NaN in either argument gives NaN; a white with a zero or negative component
/// gives ±Inf or NaN; negative XYZ use the linear branch of the CIE function (so L* may be
/// negative).
pub fn lab_from_xyz(xyz: [f64; 3], white: [f64; 3]) -> [f64; 3] {
    let f = |t: f64| {
        const DELTA: f64 = 6.0 / 29.0;
        if t > DELTA * DELTA * DELTA {
            libm::cbrt(t)
        } else {
            t / (3.0 * DELTA * DELTA) + 4.0 / 29.0
        }
    };
    let fx = f(xyz[0] / white[0]);
    let fy = f(xyz[1] / white[1]);
    let fz = f(xyz[2] / white[2]);
    [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
}

/// ΔE*ab (CIE 1976): the Euclidean distance in CIELAB. NaN in → NaN out; never panics.
pub fn delta_e76(lab1: [f64; 3], lab2: [f64; 3]) -> f64 {
    let d = [lab1[0] - lab2[0], lab1[1] - lab2[1], lab1[2] - lab2[2]];
    libm::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
}

/// ΔE00 (CIEDE2000) with k_L = k_C = k_H = 1, following Sharma, Wu and Dalal (2005), whose 34
/// test pairs it reproduces to their printed 4 decimals. NaN in → NaN out; never panics.
pub fn delta_e2000(lab1: [f64; 3], lab2: [f64; 3]) -> f64 {
    use core::f64::consts::PI;
    let deg = |r: f64| r * 180.0 / PI;
    let rad = |d: f64| d * PI / 180.0;
    let [l1, a1, b1] = lab1;
    let [l2, a2, b2] = lab2;
    let c1 = libm::hypot(a1, b1);
    let c2 = libm::hypot(a2, b2);
    let c_bar = 0.5 * (c1 + c2);
    let c_bar7 = libm::pow(c_bar, 7.0);
    let g = 0.5 * (1.0 - libm::sqrt(c_bar7 / (c_bar7 + 6_103_515_625.0))); // 25^7
    let a1p = (1.0 + g) * a1;
    let a2p = (1.0 + g) * a2;
    let c1p = libm::hypot(a1p, b1);
    let c2p = libm::hypot(a2p, b2);
    let hue = |b: f64, ap: f64| {
        if b == 0.0 && ap == 0.0 {
            0.0
        } else {
            let h = deg(libm::atan2(b, ap));
            if h < 0.0 {
                h + 360.0
            } else {
                h
            }
        }
    };
    let h1p = hue(b1, a1p);
    let h2p = hue(b2, a2p);
    let dl = l2 - l1;
    let dc = c2p - c1p;
    let chroma_zero = c1p * c2p == 0.0;
    let dh = if chroma_zero {
        0.0
    } else {
        let d = h2p - h1p;
        if d > 180.0 {
            d - 360.0
        } else if d < -180.0 {
            d + 360.0
        } else {
            d
        }
    };
    let dh_big = 2.0 * libm::sqrt(c1p * c2p) * libm::sin(rad(dh) / 2.0);
    let l_bar = 0.5 * (l1 + l2);
    let c_bar_p = 0.5 * (c1p + c2p);
    let h_bar = if chroma_zero {
        h1p + h2p
    } else if (h1p - h2p).abs() <= 180.0 {
        0.5 * (h1p + h2p)
    } else if h1p + h2p < 360.0 {
        0.5 * (h1p + h2p + 360.0)
    } else {
        0.5 * (h1p + h2p - 360.0)
    };
    let t = 1.0 - 0.17 * libm::cos(rad(h_bar - 30.0))
        + 0.24 * libm::cos(rad(2.0 * h_bar))
        + 0.32 * libm::cos(rad(3.0 * h_bar + 6.0))
        - 0.20 * libm::cos(rad(4.0 * h_bar - 63.0));
    let d_theta = 30.0 * libm::exp(-libm::pow((h_bar - 275.0) / 25.0, 2.0));
    let c_bar_p7 = libm::pow(c_bar_p, 7.0);
    let r_c = 2.0 * libm::sqrt(c_bar_p7 / (c_bar_p7 + 6_103_515_625.0));
    let l50 = (l_bar - 50.0) * (l_bar - 50.0);
    let s_l = 1.0 + 0.015 * l50 / libm::sqrt(20.0 + l50);
    let s_c = 1.0 + 0.045 * c_bar_p;
    let s_h = 1.0 + 0.015 * c_bar_p * t;
    let r_t = -libm::sin(rad(2.0 * d_theta)) * r_c;
    let (x, y, z) = (dl / s_l, dc / s_c, dh_big / s_h);
    libm::sqrt(x * x + y * y + z * z + r_t * y * z)
}
