//! Random wavelengths per sample, the way spectral renderers choose them: the peers the crate's
//! fixed wavelength sets are measured against (report section 7, `docs/random-wavelengths.md`).
//!
//! A renderer that picks its wavelengths at random draws N of them for every sample, evaluates
//! the scene at those wavelengths, and adds `f(λ) / p(λ)` (the radiance times the
//! colour-matching functions, divided by the density the wavelengths were drawn with) to the
//! pixel. The estimate is unbiased, so its error is noise, which only more samples per pixel
//! remove. Three samplers are here:
//!
//! - [`Sampler::Visible`]: pbrt-v4's `SampleVisibleWavelengths` (Mitsuba 3 uses the same
//!   density), a sech² density centred at 538 nm on 360-830 nm; the i-th of N wavelengths is
//!   drawn at `u + i/N` (wrapped to [0, 1)), so one random number stratifies all N.
//! - [`Sampler::Hero`]: hero wavelength sampling (Wilkie et al. 2014): one wavelength uniform
//!   on the range and the others spaced evenly by range/N, wrapped into it.
//! - [`Sampler::Uniform`]: N independent uniform wavelengths, no stratification.
//!
//! The integrand is the report's reference integral ([`Cells`]): the 1 nm sum of x̄ȳz̄ times the
//! radiance is exactly the integral of a function that is constant over 1 nm cells centred on
//! the grid wavelengths, so the samplers' expected value is the reference's colour itself, not
//! a slightly different continuous integral. `tools/tests/random_wavelengths.rs` checks that
//! every sampler is unbiased and that every density integrates to 1 on its range.
//!
//! [`SensorRgb`] is the per-sample colour path a renderer runs in f32 (the wavelengths and their
//! densities, the colour-matching functions looked up at them, the division by the density and
//! the sum into the pixel): the report times it beside the fixed sets' 3×N product.

use rand::{Rng, RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use spectral_quadrature_spectra::EvalSet;

use crate::Error;

/// pbrt-v4's visible-wavelength sampling range, nm.
pub const VISIBLE_RANGE_NM: [f64; 2] = [360.0, 830.0];

// pbrt-v4 `util/spectrum.h`: `SampleVisibleWavelengths(u) = 538 - 138.888889 atanh(0.85691062 -
// 1.82750197 u)` and `VisibleWavelengthsPDF(λ) = 0.0039398042 / cosh²(0.0072 (λ - 538))`.
const VISIBLE_CENTRE_NM: f64 = 538.0;
const VISIBLE_SCALE_NM: f64 = 138.888889;
const VISIBLE_A: f64 = 0.85691062;
const VISIBLE_B: f64 = 1.82750197;
const VISIBLE_PDF_PEAK: f64 = 0.0039398042;
const VISIBLE_PDF_RATE: f64 = 0.0072;

/// How a renderer draws the wavelengths of one sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Sampler {
    /// pbrt-v4's visible-wavelength sampling: density `0.0039398042 / cosh²(0.0072 (λ - 538))`
    /// on [`VISIBLE_RANGE_NM`], the i-th of N wavelengths at `u + i/N` wrapped.
    Visible,
    /// Hero wavelength sampling: the first wavelength uniform on `range_nm`, the others spaced
    /// evenly by (range)/N after it, wrapped into the range.
    Hero {
        /// The range, nm.
        range_nm: [f64; 2],
    },
    /// N independent wavelengths, each uniform on `range_nm`.
    Uniform {
        /// The range, nm.
        range_nm: [f64; 2],
    },
}

impl Sampler {
    /// A short name for tables: `pbrt-v4 visible`, `hero`, `uniform`.
    pub fn name(&self) -> &'static str {
        match self {
            Sampler::Visible => "pbrt-v4 visible",
            Sampler::Hero { .. } => "hero",
            Sampler::Uniform { .. } => "uniform",
        }
    }

    /// The range the wavelengths fall in, nm: the density is zero outside it.
    pub fn range_nm(&self) -> [f64; 2] {
        match self {
            Sampler::Visible => VISIBLE_RANGE_NM,
            Sampler::Hero { range_nm } | Sampler::Uniform { range_nm } => *range_nm,
        }
    }

    /// The density of each wavelength of a sample (every one has the same marginal density),
    /// per nm; zero outside [`range_nm`](Self::range_nm), NaN for NaN.
    pub fn pdf(&self, nm: f64) -> f64 {
        let [lo, hi] = self.range_nm();
        if nm.is_nan() {
            return f64::NAN;
        }
        if !(lo..=hi).contains(&nm) {
            return 0.0;
        }
        match self {
            Sampler::Visible => {
                let c = (VISIBLE_PDF_RATE * (nm - VISIBLE_CENTRE_NM)).cosh();
                VISIBLE_PDF_PEAK / (c * c)
            }
            Sampler::Hero { .. } | Sampler::Uniform { .. } => 1.0 / (hi - lo),
        }
    }

    /// The wavelength at `u` in [0, 1] of the inverse cumulative distribution: a wavelength
    /// drawn with [`pdf`](Self::pdf) when `u` is uniform. Outside [0, 1] it extrapolates
    /// (uniform, hero) or gives NaN beyond pbrt-v4's `atanh` domain.
    pub fn wavelength(&self, u: f64) -> f64 {
        match self {
            Sampler::Visible => {
                VISIBLE_CENTRE_NM - VISIBLE_SCALE_NM * (VISIBLE_A - VISIBLE_B * u).atanh()
            }
            Sampler::Hero { range_nm } | Sampler::Uniform { range_nm } => {
                range_nm[0] + u * (range_nm[1] - range_nm[0])
            }
        }
    }

    /// Fills `out` with the wavelengths of one sample (N = `out.len()`), drawing from `rng`:
    /// one uniform number for [`Visible`](Self::Visible) and [`Hero`](Self::Hero) (the i-th
    /// wavelength at `u + i/N`, wrapped), N for [`Uniform`](Self::Uniform).
    pub fn wavelengths<R: Rng + ?Sized>(&self, rng: &mut R, out: &mut [f64]) {
        let n = out.len();
        match self {
            Sampler::Visible | Sampler::Hero { .. } => {
                let u: f64 = rng.random();
                for (i, l) in out.iter_mut().enumerate() {
                    *l = self.wavelength(stratum(u, i, n));
                }
            }
            Sampler::Uniform { .. } => {
                for l in out.iter_mut() {
                    *l = self.wavelength(rng.random());
                }
            }
        }
    }

    /// One sample's estimate of the integral of `f`: the mean over the sample's wavelengths
    /// (N = `scratch.len()`, at least 1) of `f(λ) / p(λ)`. Unbiased when the sampler's range
    /// covers [`Cells::span_nm`] (see [`covers`](Self::covers)).
    pub fn estimate<R: Rng + ?Sized>(
        &self,
        f: &Cells,
        rng: &mut R,
        scratch: &mut [f64],
    ) -> [f64; 3] {
        self.wavelengths(rng, scratch);
        let mut sum = [0.0; 3];
        for &l in scratch.iter() {
            let v = f.at(l);
            let p = self.pdf(l);
            // A drawn wavelength has a positive density; the guard keeps a rounding at the
            // range's end from dividing by zero (pbrt's `SafeDiv` does the same).
            if p > 0.0 {
                for (s, v) in sum.iter_mut().zip(v) {
                    *s += v / p;
                }
            }
        }
        sum.map(|s| s / scratch.len() as f64)
    }

    /// Whether every wavelength where `f` may be non-zero can be drawn (the condition for an
    /// unbiased estimate).
    pub fn covers(&self, f: &Cells) -> bool {
        let [lo, hi] = self.range_nm();
        let [a, b] = f.span_nm();
        lo <= a && b <= hi
    }

    /// [`wavelength`](Self::wavelength) in f32, as a renderer computes it (pbrt-v4's `Float`).
    pub fn wavelength_f32(&self, u: f32) -> f32 {
        match self {
            Sampler::Visible => {
                VISIBLE_CENTRE_NM as f32
                    - VISIBLE_SCALE_NM as f32 * (VISIBLE_A as f32 - VISIBLE_B as f32 * u).atanh()
            }
            Sampler::Hero { range_nm } | Sampler::Uniform { range_nm } => {
                let (lo, hi) = (range_nm[0] as f32, range_nm[1] as f32);
                lo + u * (hi - lo)
            }
        }
    }

    /// [`pdf`](Self::pdf) in f32.
    pub fn pdf_f32(&self, nm: f32) -> f32 {
        let [lo, hi] = self.range_nm().map(|v| v as f32);
        if nm.is_nan() {
            return f32::NAN;
        }
        if !(lo..=hi).contains(&nm) {
            return 0.0;
        }
        match self {
            Sampler::Visible => {
                let c = (VISIBLE_PDF_RATE as f32 * (nm - VISIBLE_CENTRE_NM as f32)).cosh();
                VISIBLE_PDF_PEAK as f32 / (c * c)
            }
            Sampler::Hero { .. } | Sampler::Uniform { .. } => 1.0 / (hi - lo),
        }
    }

    /// The wavelengths of one sample and their densities in f32, as a renderer draws them
    /// before tracing the sample: [`wavelengths`](Self::wavelengths) in f32.
    pub fn wavelengths_f32<const N: usize, R: Rng + ?Sized>(
        &self,
        rng: &mut R,
    ) -> ([f32; N], [f32; N]) {
        let mut l = [0.0f32; N];
        match self {
            Sampler::Visible | Sampler::Hero { .. } => {
                let u: f32 = rng.random();
                for (i, l) in l.iter_mut().enumerate() {
                    let mut v = u + i as f32 / N as f32;
                    if v >= 1.0 {
                        v -= 1.0;
                    }
                    *l = self.wavelength_f32(v);
                }
            }
            Sampler::Uniform { .. } => {
                for l in l.iter_mut() {
                    *l = self.wavelength_f32(rng.random());
                }
            }
        }
        (l, l.map(|v| self.pdf_f32(v)))
    }
}

/// A sampler prepared for one grid of [`Cells`]: [`Sampler::estimate`] from the same random
/// numbers, faster for [`Sampler::Visible`].
///
/// pbrt-v4's wavelength is `atanh` of the random number `u` and its density a `cosh` of the
/// wavelength: two library calls per wavelength, most of the time the report's random trials
/// took. A sample's contribution depends on its wavelength only through the cell the
/// wavelength falls in and the density there, and the wavelength rises with `u`. So the least
/// `u` that reaches each cell boundary is found once, by bisection over the f64 values with
/// [`Sampler::wavelength`] and the cells' own arithmetic, and a sample's cell is read from `u`
/// (a table of 4096 buckets, then a comparison or two): the cell the wavelength falls in. The
/// density is taken in `u`: `0.0039398042 (1 - x²)` with `x = 0.85691062 - 1.82750197 u`,
/// which is `cosh⁻²(0.0072 (λ - 538))` at `λ = 538 - 138.888889 atanh(x)` up to pbrt's
/// constants (`0.0072 × 138.888889 = 1 + 8·10⁻¹⁰`), so an estimate differs from
/// [`Sampler::estimate`]'s by a few parts in 10⁹ (`tools/tests/random_wavelengths.rs` measures
/// it). Hero and uniform sampling, whose wavelengths are a multiplication and an addition, take
/// [`Sampler::estimate`]'s path (read from the table they ran slower: section 7's trials took
/// 4.2 s instead of 3.4 s), and so do cells on another grid.
#[derive(Debug, Clone)]
pub struct Estimator {
    sampler: Sampler,
    /// The grid it was prepared for.
    grid: Grid,
    /// For [`Sampler::Visible`]: its cells in `u`.
    visible: Option<CellsInU>,
}

/// Where the wavelengths a sampler draws from `u` fall among a grid's cells.
#[derive(Debug, Clone)]
struct CellsInU {
    /// `thresholds[k]`: the least `u` in [0, 1] whose wavelength lies at or above cell k's
    /// lower edge (k = 0 ..= the number of cells; infinite where none does). The cell of `u` is
    /// the number of thresholds at or below it, less one (none: below the first cell; all:
    /// above the last).
    thresholds: Vec<f64>,
    /// `buckets[b]`: how many thresholds are at or below `b / BUCKETS`, where the count for a
    /// `u` in bucket b starts.
    buckets: Vec<u32>,
    /// The `u` where the density becomes positive and the `u` where it ends: `pdf` is zero for
    /// wavelengths outside the sampler's range, and so is the sample's contribution.
    density_from: f64,
    density_to: f64,
}

impl Estimator {
    /// `sampler` prepared for cells on the grid of `cells` (their values are not kept).
    pub fn new(sampler: Sampler, cells: &Cells) -> Estimator {
        let visible = matches!(sampler, Sampler::Visible).then(|| CellsInU::new(sampler, cells));
        Estimator {
            sampler,
            grid: cells.grid(),
            visible,
        }
    }

    /// The sampler.
    pub fn sampler(&self) -> Sampler {
        self.sampler
    }

    /// One sample's estimate of the integral of `f`, as [`Sampler::estimate`] (N =
    /// `scratch.len()`, at least 1), drawing the same random numbers from `rng`.
    pub fn estimate<R: Rng + ?Sized>(
        &self,
        f: &Cells,
        rng: &mut R,
        scratch: &mut [f64],
    ) -> [f64; 3] {
        let Some(in_u) = self.visible.as_ref().filter(|_| self.grid == f.grid()) else {
            return self.sampler.estimate(f, rng, scratch);
        };
        let n = scratch.len();
        let u: f64 = rng.random();
        let mut sum = [0.0; 3];
        for i in 0..n {
            let v = stratum(u, i, n);
            // Outside every cell, or where the density is zero, a wavelength adds nothing.
            if let Some(cell) = in_u.cell(v) {
                let x = VISIBLE_A - VISIBLE_B * v;
                let p = VISIBLE_PDF_PEAK * ((1.0 - x) * (1.0 + x));
                for (s, v) in sum.iter_mut().zip(f.values[cell]) {
                    *s += v / p;
                }
            }
        }
        sum.map(|s| s / n as f64)
    }
}

impl CellsInU {
    const BUCKETS: usize = 4096;

    fn new(sampler: Sampler, cells: &Cells) -> CellsInU {
        // The least u in [0, 1] where `reaches` turns true (infinite where it never does). The
        // wavelength rises with u (for pbrt's map x falls with u, and atanh and every f64
        // operation are monotonic), so every predicate below is false and then true.
        let least = |reaches: &dyn Fn(f64) -> bool| {
            if reaches(0.0) {
                return 0.0;
            }
            if !reaches(1.0) {
                return f64::INFINITY;
            }
            // Bisection over the bits: non-negative f64 values are ordered as their bits.
            let (mut below, mut at) = (0.0f64.to_bits(), 1.0f64.to_bits());
            while at - below > 1 {
                let mid = below + (at - below) / 2;
                if reaches(f64::from_bits(mid)) {
                    at = mid;
                } else {
                    below = mid;
                }
            }
            f64::from_bits(at)
        };
        let thresholds: Vec<f64> = (0..=cells.values.len())
            .map(|k| {
                least(&|u| {
                    cells
                        .position(sampler.wavelength(u))
                        .is_some_and(|t| t >= k as f64)
                })
            })
            .collect();
        let buckets = (0..Self::BUCKETS)
            .map(|b| {
                let start = b as f64 / Self::BUCKETS as f64;
                thresholds.partition_point(|&t| t <= start) as u32
            })
            .collect();
        let [lo, hi] = sampler.range_nm();
        CellsInU {
            thresholds,
            buckets,
            density_from: least(&|u| sampler.wavelength(u) >= lo),
            density_to: least(&|u| sampler.wavelength(u) > hi),
        }
    }

    /// The cell of the wavelength at `u` in [0, 1), `None` outside every cell and where the
    /// density is zero.
    #[inline]
    fn cell(&self, u: f64) -> Option<usize> {
        if !(self.density_from <= u && u < self.density_to) {
            return None;
        }
        // `u · 2¹²` is exact, so bucket b starts at or below u.
        let b = ((u * Self::BUCKETS as f64) as usize).min(Self::BUCKETS - 1);
        let mut count = self.buckets[b] as usize;
        while count < self.thresholds.len() && self.thresholds[count] <= u {
            count += 1;
        }
        (1..self.thresholds.len())
            .contains(&count)
            .then(|| count - 1)
    }
}

/// `u + i/n` wrapped into [0, 1): the stratum of the i-th of n wavelengths drawn from one `u`.
fn stratum(u: f64, i: usize, n: usize) -> f64 {
    let v = u + i as f64 / n as f64;
    if v >= 1.0 {
        v - 1.0
    } else {
        v
    }
}

/// A spectrum's contribution to X, Y and Z as the report's reference integrates it: constant
/// over cells `step_nm` wide centred on the grid wavelengths `first_nm + k step_nm`, and zero
/// outside them. Its integral is exactly the grid sum `Σ_k values[k] step_nm`.
#[derive(Debug, Clone, PartialEq)]
pub struct Cells {
    first_nm: f64,
    step_nm: f64,
    values: Vec<[f64; 3]>,
}

impl Cells {
    /// Cells centred on `first_nm`, `first_nm + step_nm`, …, one per value (X, Y, Z per nm).
    /// Errors when the step is not positive and finite or there are no values.
    pub fn new(first_nm: f64, step_nm: f64, values: Vec<[f64; 3]>) -> Result<Cells, Error> {
        if !(step_nm > 0.0 && step_nm.is_finite() && first_nm.is_finite()) || values.is_empty() {
            return Err(Error::Sampling(format!(
                "cells need a positive step and at least one value (first {first_nm} nm, step {step_nm} nm, {} values)",
                values.len()
            )));
        }
        Ok(Cells {
            first_nm,
            step_nm,
            values,
        })
    }

    /// `radiance` weighted by a reference set's X, Y, Z weights (weights for a grid sum, as
    /// [`Observer::full_integration`](spectral_quadrature_generator::Observer::full_integration)
    /// makes them): the integrand
    /// whose integral is the reference's XYZ of that radiance. The set's wavelengths must be
    /// evenly spaced.
    pub fn weighted(reference: &EvalSet, radiance: impl Fn(f64) -> f64) -> Result<Cells, Error> {
        let w = &reference.wavelengths_nm;
        let (first, step) = match w.as_slice() {
            [a, b, ..] => (*a, b - a),
            _ => {
                return Err(Error::Sampling(format!(
                    "{}: a reference needs at least two wavelengths",
                    reference.name
                )))
            }
        };
        // The grid is read from a table; 1e-6 nm allows for its decimal rounding only.
        if let Some(k) = (0..w.len()).find(|&k| (w[k] - (first + k as f64 * step)).abs() > 1e-6) {
            return Err(Error::Sampling(format!(
                "{}: wavelength {} nm breaks the even spacing of {step} nm",
                reference.name, w[k]
            )));
        }
        let values = w
            .iter()
            .enumerate()
            .map(|(k, &l)| {
                let r = radiance(l);
                [0, 1, 2].map(|c| reference.xyz_weights[c][k] / step * r)
            })
            .collect();
        Cells::new(first, step, values)
    }

    /// Where the integrand may be non-zero, nm: from half a step before the first grid
    /// wavelength to half a step after the last.
    pub fn span_nm(&self) -> [f64; 2] {
        let half = 0.5 * self.step_nm;
        [
            self.first_nm - half,
            self.first_nm + (self.values.len() - 1) as f64 * self.step_nm + half,
        ]
    }

    /// The value at `nm`: its cell's, zero outside every cell (and for NaN).
    pub fn at(&self, nm: f64) -> [f64; 3] {
        match self.position(nm) {
            Some(t) if t < self.values.len() as f64 => self.values[t as usize],
            _ => [0.0; 3],
        }
    }

    /// Where `nm` lies on the grid, in cells from the first cell's lower edge: its cell is the
    /// integer part. `None` below the first cell and for NaN.
    fn position(&self, nm: f64) -> Option<f64> {
        let t = (nm - self.first_nm) / self.step_nm + 0.5;
        (t >= 0.0).then_some(t)
    }

    /// Where the cells lie, their values aside.
    fn grid(&self) -> Grid {
        Grid {
            first_nm: self.first_nm,
            step_nm: self.step_nm,
            cells: self.values.len(),
        }
    }

    /// The exact integral, `Σ_k values[k] step_nm`.
    pub fn integral(&self) -> [f64; 3] {
        let mut s = [0.0; 3];
        for v in &self.values {
            for (s, v) in s.iter_mut().zip(v) {
                *s += v * self.step_nm;
            }
        }
        s
    }
}

/// The cells of a [`Cells`] without their values: what an [`Estimator`] is prepared for.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Grid {
    first_nm: f64,
    step_nm: f64,
    cells: usize,
}

/// A renderer's per-sample colour path in f32, as pbrt-v4's RGB film runs it: the sensor's
/// matching functions looked up at the sample's wavelengths (the nearest 1 nm entry, as pbrt's
/// `DenselySampledSpectrum` does), times the radiance, divided by the density, averaged over
/// the wavelengths and added to the pixel. The matching functions are the observer's x̄ȳz̄
/// already taken to the display's linear RGB, so no 3×3 product is left per sample (the fixed
/// sets fold the same matrix into their weights).
#[derive(Debug, Clone)]
pub struct SensorRgb {
    first_nm: f32,
    rgb: Vec<[f32; 3]>,
}

impl SensorRgb {
    /// From x̄ȳz̄ on a 1 nm grid starting at `first_nm`, and the matrix from XYZ to the
    /// display's linear RGB, scaled by `scale` (the white's luminance, say).
    pub fn new(first_nm: f64, xyz_bar: &[[f64; 3]], xyz_to_rgb: [[f32; 3]; 3], scale: f64) -> Self {
        let rgb = xyz_bar
            .iter()
            .map(|v| {
                xyz_to_rgb.map(|row| {
                    (row.iter()
                        .zip(v)
                        .map(|(m, x)| f64::from(*m) * x)
                        .sum::<f64>()
                        * scale) as f32
                })
            })
            .collect();
        SensorRgb {
            first_nm: first_nm as f32,
            rgb,
        }
    }

    /// Adds one sample (radiance at `wavelengths` drawn with densities `pdf`) to `pixel`.
    #[inline]
    pub fn add_sample<const N: usize>(
        &self,
        wavelengths: &[f32; N],
        pdf: &[f32; N],
        radiance: &[f32; N],
        pixel: &mut [f32; 3],
    ) {
        let mut sum = [0.0f32; 3];
        for i in 0..N {
            // Nearest entry; outside the table the sensor sees nothing. The cast truncates,
            // which is the floor for the non-negative values it gets (`floor` is a library
            // call on x86-64 without SSE4.1).
            let t = wavelengths[i] - self.first_nm + 0.5;
            if t >= 0.0 && pdf[i] > 0.0 {
                if let Some(m) = self.rgb.get(t as usize) {
                    let w = radiance[i] / pdf[i];
                    for (s, m) in sum.iter_mut().zip(m) {
                        *s += m * w;
                    }
                }
            }
        }
        for (p, s) in pixel.iter_mut().zip(sum) {
            *p += s * (1.0 / N as f32);
        }
    }
}

/// One random sampler as the report runs it: a sampler and the number of wavelengths it
/// draws for each sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Config {
    /// The sampler.
    pub sampler: Sampler,
    /// Wavelengths per sample.
    pub wavelengths: usize,
}

impl Config {
    /// `pbrt-v4 visible ×4`.
    pub fn label(&self) -> String {
        format!("{} ×{}", self.sampler.name(), self.wavelengths)
    }
}

/// One stimulus as a random sampler's trials measure it.
#[derive(Debug, Clone, PartialEq)]
pub struct Target {
    /// The integrand: x̄ȳz̄ times the stimulus' radiance ([`Cells::weighted`]).
    pub cells: Cells,
    /// The exact white's XYZ: a renderer's film normalises by a fixed white, never by one
    /// integrated with the sample's own wavelengths.
    pub white: [f64; 3],
    /// The exact colour, CIELAB.
    pub lab: [f64; 3],
}

/// One trial's errors: per level of samples per pixel, per target, (ΔE00, ΔE*ab).
pub type TrialErrors = Vec<Vec<(f64, f64)>>;

/// The errors of one sampler's trials: `errors[trial][level][target]` is (ΔE00, ΔE*ab) of the
/// estimate at `spp[level]` samples per pixel.
#[derive(Debug, Clone, PartialEq)]
pub struct Trials {
    /// The samples per pixel measured, ascending.
    pub spp: Vec<usize>,
    /// Per trial: per level, per target, (ΔE00, ΔE*ab).
    pub errors: Vec<TrialErrors>,
}

/// A seed for one stream of random numbers: `seed` mixed with the parts that name the stream
/// (splitmix64's finaliser per part, so that neighbouring parts give unrelated seeds).
pub fn stream_seed(seed: u64, parts: &[u64]) -> u64 {
    let mix = |mut z: u64| {
        z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    };
    parts.iter().fold(mix(seed), |h, &p| mix(h ^ mix(p)))
}

/// The random numbers of one pixel: a PCG stream seeded by [`stream_seed`].
pub fn pixel_rng(seed: u64, parts: &[u64]) -> Pcg64Mcg {
    Pcg64Mcg::seed_from_u64(stream_seed(seed, parts))
}

/// Runs the seeded trials `trials` (a range of trial numbers) of `config` on every target: in
/// each, every target gets one pixel of `spp.last()` samples, and the estimate after each level
/// of `spp` (its first samples) is compared with the exact colour, each sample estimated by an
/// [`Estimator`] prepared for the targets' grid. Trial t of target k draws from the stream
/// `[stream, t, k]` of `seed`, so a trial's result depends neither on the trials run with it
/// nor on how they are spread over `threads` threads ([`Trials::append`] joins ranges). Errors
/// when `spp` is empty or not ascending, `config` draws no wavelengths, or its sampler does not
/// cover a target's integrand (which would bias it).
pub fn run_trials(
    config: Config,
    targets: &[Target],
    spp: &[usize],
    trials: std::ops::Range<usize>,
    seed: u64,
    stream: u64,
    threads: usize,
) -> Result<Trials, Error> {
    if spp.is_empty() || spp[0] == 0 || spp.windows(2).any(|w| w[0] >= w[1]) {
        return Err(Error::Sampling(format!(
            "samples per pixel must be positive and ascending: {spp:?}"
        )));
    }
    if config.wavelengths == 0 {
        return Err(Error::Sampling(
            "a sample needs at least one wavelength".into(),
        ));
    }
    if let Some(t) = targets.iter().find(|t| !config.sampler.covers(&t.cells)) {
        return Err(Error::Sampling(format!(
            "{} draws on {:?} nm, which misses part of the integrand's {:?} nm",
            config.sampler.name(),
            config.sampler.range_nm(),
            t.cells.span_nm()
        )));
    }
    // One estimator per grid (the report's targets share one).
    let mut estimators: Vec<Estimator> = Vec::new();
    for t in targets {
        if !estimators.iter().any(|e| e.grid == t.cells.grid()) {
            estimators.push(Estimator::new(config.sampler, &t.cells));
        }
    }
    let estimator_for = |cells: &Cells| {
        estimators
            .iter()
            .find(|e| e.grid == cells.grid())
            .expect("an estimator for every target's grid")
    };
    let one = |t: usize| -> TrialErrors {
        let mut levels = vec![Vec::with_capacity(targets.len()); spp.len()];
        let mut scratch = vec![0.0; config.wavelengths];
        for (k, target) in targets.iter().enumerate() {
            let estimator = estimator_for(&target.cells);
            let mut rng = pixel_rng(seed, &[stream, t as u64, k as u64]);
            let mut sum = [0.0; 3];
            let mut level = 0;
            for s in 1..=spp[spp.len() - 1] {
                let e = estimator.estimate(&target.cells, &mut rng, &mut scratch);
                for (a, e) in sum.iter_mut().zip(e) {
                    *a += e;
                }
                if s == spp[level] {
                    let xyz = sum.map(|v| v / s as f64);
                    let lab = spectral_quadrature::lab_from_xyz(xyz, target.white);
                    levels[level].push((
                        spectral_quadrature::delta_e2000(target.lab, lab),
                        spectral_quadrature::delta_e76(target.lab, lab),
                    ));
                    level += 1;
                }
            }
        }
        levels
    };
    let threads = threads.clamp(1, trials.len().max(1));
    let errors = std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads)
            .map(|h| {
                let one = &one;
                let trials = trials.clone();
                s.spawn(move || {
                    (trials.start + h..trials.end)
                        .step_by(threads)
                        .map(|t| (t, one(t)))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        let mut all: Vec<(usize, TrialErrors)> = handles
            .into_iter()
            .flat_map(|h| h.join().expect("a trial does not panic"))
            .collect();
        all.sort_by_key(|x| x.0);
        all.into_iter().map(|x| x.1).collect()
    });
    Ok(Trials {
        spp: spp.to_vec(),
        errors,
    })
}

/// What the trials give at one level of samples per pixel on some of the targets.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Summary {
    /// Samples per pixel.
    pub spp: usize,
    /// Trials.
    pub trials: usize,
    /// Mean ΔE00 over the targets and trials.
    pub mean_de00: f64,
    /// The standard error of that mean: the standard deviation of the trials' means over
    /// √trials (NaN with one trial).
    pub standard_error: f64,
    /// The standard deviation of the trials' means.
    pub sd_trials: f64,
    /// The 90th percentile of single pixels' ΔE00 (every target in every trial).
    pub p90_pixel: f64,
    /// Mean ΔE*ab over the targets and trials.
    pub mean_de76: f64,
}

impl Trials {
    /// The number of trials.
    pub fn len(&self) -> usize {
        self.errors.len()
    }

    /// Whether there are no trials.
    pub fn is_empty(&self) -> bool {
        self.errors.is_empty()
    }

    /// Adds the trials of `more` (run on the same targets and levels, with the trial numbers
    /// that follow these).
    pub fn append(&mut self, more: Trials) -> Result<(), Error> {
        if more.spp != self.spp {
            return Err(Error::Sampling(format!(
                "trials at {:?} samples per pixel cannot join trials at {:?}",
                more.spp, self.spp
            )));
        }
        self.errors.extend(more.errors);
        Ok(())
    }

    /// The largest standard error relative to its mean over every level and every group of
    /// targets in `groups` (infinite with fewer than two trials).
    pub fn worst_relative_error(&self, groups: &[Vec<usize>]) -> f64 {
        if self.errors.len() < 2 {
            return f64::INFINITY;
        }
        groups
            .iter()
            .flat_map(|g| self.summarize(g))
            .map(|s| s.standard_error / s.mean_de00)
            .fold(0.0, f64::max)
    }

    /// The summary at every level over the targets `which` (indices into the targets the trials
    /// ran on; one out of range panics); empty when `which` is empty or there are no trials.
    pub fn summarize(&self, which: &[usize]) -> Vec<Summary> {
        if which.is_empty() || self.errors.is_empty() {
            return Vec::new();
        }
        let trials = self.errors.len();
        (0..self.spp.len())
            .map(|level| {
                let means: Vec<f64> = self
                    .errors
                    .iter()
                    .map(|t| which.iter().map(|&k| t[level][k].0).sum::<f64>() / which.len() as f64)
                    .collect();
                let mean = means.iter().sum::<f64>() / trials as f64;
                let var = means.iter().map(|m| (m - mean) * (m - mean)).sum::<f64>()
                    / (trials as f64 - 1.0);
                let mut pixels: Vec<f64> = self
                    .errors
                    .iter()
                    .flat_map(|t| which.iter().map(move |&k| t[level][k].0))
                    .collect();
                pixels.sort_by(f64::total_cmp);
                let p90 = pixels
                    [((pixels.len() as f64 * 0.9).ceil() as usize).clamp(1, pixels.len()) - 1];
                let de76 = self
                    .errors
                    .iter()
                    .flat_map(|t| which.iter().map(move |&k| t[level][k].1))
                    .sum::<f64>()
                    / (trials * which.len()) as f64;
                Summary {
                    spp: self.spp[level],
                    trials,
                    mean_de00: mean,
                    standard_error: (var / trials as f64).sqrt(),
                    sd_trials: var.sqrt(),
                    p90_pixel: p90,
                    mean_de76: de76,
                }
            })
            .collect()
    }
}

/// The samples per pixel at which a sampler's mean error reaches a level.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Reach {
    /// Already at the curve's first level (one sample per pixel in the report).
    AtFirst,
    /// Between two measured levels: interpolated linearly in log(spp) against log(error).
    Between(f64),
    /// Not within the measured levels: extrapolated along the last two levels' slope.
    Beyond(f64),
    /// Not within the measured levels, and the error stopped falling.
    Never,
}

/// Where the error curve `curve` (samples per pixel, mean error; ascending samples) first
/// falls to `error` or below.
pub fn reach(curve: &[(usize, f64)], error: f64) -> Reach {
    let log = |(s, e): (usize, f64)| ((s as f64).ln(), e.ln());
    match curve.first() {
        None => return Reach::Never,
        Some(&(_, e)) if e <= error => return Reach::AtFirst,
        _ => {}
    }
    let along = |a: (f64, f64), b: (f64, f64)| {
        // log spp where the line through a and b has log error ln(error).
        let t = (error.ln() - a.1) / (b.1 - a.1);
        (a.0 + t * (b.0 - a.0)).exp()
    };
    for w in curve.windows(2) {
        if w[1].1 <= error {
            return Reach::Between(along(log(w[0]), log(w[1])));
        }
    }
    match curve {
        [.., a, b] if b.1 < a.1 && error > 0.0 => Reach::Beyond(along(log(*a), log(*b))),
        _ => Reach::Never,
    }
}
