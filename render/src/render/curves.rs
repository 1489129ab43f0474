//! The curves of error against render time: each method's points, where a curve has
//! flattened, one curve's error at another's time, where one passes below another for good, and
//! where one is not below another.
//!
//! Time is on a log scale and so is error: between two points a curve is read by interpolation
//! in log-log, as it is drawn.

/// One level of a curve: a method's image at `spp` paths a pixel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Point {
    /// Samples (paths) per pixel.
    pub spp: usize,
    /// Wall-clock seconds to render it, its frames' conversions included.
    pub seconds: f64,
    /// Mean ΔE00 over the pixels that see the scene.
    pub mean: f64,
    /// Their 95th percentile.
    pub p95: f64,
}

/// A curve has flattened when its mean ΔE00 fell by less than this share over the last
/// doubling of its paths: a log-log slope shallower than log₂(1.05) ≈ 0.07, against the 0.5 of an
/// error that is all noise. With an error made of a bias b and independent noise,
/// `e² = b² + σ²/spp`, and r = σ²/(b²·spp) at the level before the last, a fall of 5 % is
/// `(1 + r)/(1 + r/2) = 1.05²`, r = 0.228: when the curve stops its last point is within 6 % of
/// b (`e²/b² = 1 + r/2 = 1.114`), and the noise is a third of the error's square.
pub const FLAT: f64 = 0.05;

/// Whether `points` has flattened at its last point ([`FLAT`]).
pub fn flattened(points: &[Point]) -> bool {
    match points {
        [.., a, b] => a.mean < (1.0 + FLAT) * b.mean,
        _ => false,
    }
}

/// The median of `v` (the mean of the two middle values for an even count); NaN if empty.
pub fn median(v: &[f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let m = s.len() / 2;
    if s.len() % 2 == 1 {
        s[m]
    } else {
        0.5 * (s[m - 1] + s[m])
    }
}

/// The curve's mean ΔE00 at `seconds`, interpolated in log-log between its points; `None`
/// before its first point or after its last.
pub fn at_time(points: &[Point], seconds: f64) -> Option<f64> {
    let first = points.first()?;
    let last = points.last()?;
    if seconds < first.seconds || seconds > last.seconds {
        return None;
    }
    for w in points.windows(2) {
        let (a, b) = (w[0], w[1]);
        if a.seconds <= seconds && seconds <= b.seconds {
            if b.seconds <= a.seconds || a.seconds <= 0.0 {
                return Some(b.mean);
            }
            let f = (seconds.ln() - a.seconds.ln()) / (b.seconds.ln() - a.seconds.ln());
            return Some((a.mean.ln() + f * (b.mean.ln() - a.mean.ln())).exp());
        }
    }
    Some(last.mean)
}

/// [`at_time`], with the curve held at its last value after its last point (a curve stopped
/// where it flattened).
pub fn at_time_held(points: &[Point], seconds: f64) -> Option<f64> {
    match points.last() {
        Some(last) if seconds > last.seconds => Some(last.mean),
        _ => at_time(points, seconds),
    }
}

/// Where `a` passes below `b` for good: the first point of `a` from which on each of its points
/// is below `b` at the same time ([`at_time_held`]: `b` held at its last value after it
/// stopped). `None` if `a`'s last point is not below, or `a` never meets `b`'s times.
pub fn passes_below(a: &[Point], b: &[Point]) -> Option<usize> {
    let below = |p: &Point| at_time_held(b, p.seconds).map(|e| p.mean < e);
    let mut first = None;
    for (k, p) in a.iter().enumerate() {
        match below(p) {
            Some(true) => {
                first.get_or_insert(k);
            }
            Some(false) => first = None,
            None => {}
        }
    }
    first
}

/// `a` and `b` at every point of either curve where both have an image (`a` held at its last
/// value after it stopped, [`at_time_held`]), as (seconds, `a`'s mean, `b`'s mean), in time
/// order.
pub fn side_by_side(a: &[Point], b: &[Point]) -> Vec<(f64, f64, f64)> {
    let mut times: Vec<f64> = a.iter().chain(b).map(|p| p.seconds).collect();
    times.sort_by(f64::total_cmp);
    times.dedup();
    times
        .into_iter()
        .filter_map(|t| Some((t, at_time_held(a, t)?, at_time(b, t)?)))
        .collect()
}
