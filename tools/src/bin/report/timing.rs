//! Timing a set on the runtime's path (f32, samples → linear sRGB in one 3×N product), for
//! sections 4, 5 and 7.

use std::time::Instant;

use spectral_quadrature::{tables, FoldedSet, WavelengthSet};
use spectral_quadrature_spectra::{EvalSet, Stimulus};

use crate::Error;

macro_rules! dispatch {
    ($n:expr, $set:expr, $stimuli:expr, $runs:expr; $($k:literal)*) => {
        match $n {
            $($k => Some(time_n::<$k>($set, $stimuli, $runs)),)*
            _ => None,
        }
    };
}

/// Median ns per pixel of the set on the runtime's path (see [`time_n`]); an error for a size
/// with no timing path.
pub fn time_set(set: &EvalSet, stimuli: &[Stimulus], runs: usize) -> Result<f64, Error> {
    dispatch!(set.len(), set, stimuli, runs;
        1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24 25 26 27 28 29 30 31 32
        33 34 35 36 37 38 39 40 41 42 43 44 45 46 47 48 79 391)
    .ok_or(Error::NoTimingPath(set.len()))
}

/// Median ns per pixel of `FoldedSet::<N>::linear_rgb_batch` over pixels cycling through the
/// stimuli, sampled at the set's wavelengths.
fn time_n<const N: usize>(set: &EvalSet, stimuli: &[Stimulus], runs: usize) -> f64 {
    let m = tables::XYZ_TO_AC1C2;
    // The report times sets on radiances: the light (if any) is already in the stimuli.
    let wavelengths_nm = core::array::from_fn(|i| set.wavelengths_nm[i] as f32);
    let weights = core::array::from_fn(|c| {
        core::array::from_fn(|i| {
            (0..3)
                .map(|k| f64::from(m[c][k]) * set.xyz_weights[k][i])
                .sum::<f64>() as f32
        })
    });
    let radiance = spectral_quadrature::Samples::Radiance;
    let ws = WavelengthSet::<N>::new(wavelengths_nm, weights, radiance).expect("a valid set");
    let folded: FoldedSet<N> = ws.fold(&tables::displays::SRGB, 1.0 / tables::UNIT_SPECTRUM_Y);
    const PIXELS: usize = 2048;
    let samples: Vec<[f32; N]> = (0..PIXELS)
        .map(|p| {
            let s = &stimuli[p % stimuli.len()];
            std::array::from_fn(|i| s.radiance(set.wavelengths_nm[i]) as f32)
        })
        .collect();
    let mut out = vec![[0.0f32; 3]; PIXELS];
    // Repeat each run until it lasts about half a millisecond, so the clock's resolution does
    // not matter.
    let reps = (500_000 / (PIXELS * (N + 4))).max(1);
    let mut times: Vec<f64> = (0..runs)
        .map(|_| {
            let t = Instant::now();
            for _ in 0..reps {
                folded
                    .linear_rgb_batch(std::hint::black_box(&samples), &mut out)
                    .expect("lengths agree");
                std::hint::black_box(&mut out);
            }
            t.elapsed().as_nanos() as f64 / (reps * PIXELS) as f64
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}
