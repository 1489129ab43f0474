//! One pixel at a time: raw bytes → f32 samples (every bit pattern: NaN payloads, ±Inf,
//! subnormals, ±MAX, −0.0) → `ac1c2`, `xyz` of Table 2's sets, and `linear_rgb`,
//! `encode_u8`, `encode_u16` of their folded sets for every display and both gamut mappings.
//!
//! Checked: no panic; NaN and ±Inf propagate as documented; for finite samples without
//! overflow, `ac1c2` and `linear_rgb` are within `f32_budget` of the f64 derivation's sums;
//! display outputs in 0..=1, NaN → black, encodings consistent (see `common`).
#![no_main]

use common::{check_folded, check_set, f32s, reference, FOLDED_ROW1, FOLDED_ROW2};
use libfuzzer_sys::fuzz_target;
use spectral_quadrature::tables::{displays, TABLE2_ROW1, TABLE2_ROW2};

/// At most this many samples per input (keeps each run short; longer inputs are truncated).
const MAX_SAMPLES: usize = 48;

fuzz_target!(|data: &[u8]| {
    let r = reference();
    let samples: Vec<f32> = f32s(data).take(MAX_SAMPLES).collect();

    for chunk in samples.chunks_exact(4) {
        let s: [f32; 4] = chunk.try_into().unwrap();
        check_set("TABLE2_ROW2", &TABLE2_ROW2, &r.row2, &s);
        for (j, display) in displays::ALL.iter().enumerate() {
            let what = format!("TABLE2_ROW2 folded for {}", display.name());
            check_folded(&what, &FOLDED_ROW2[j], display, &r.row2_folded[j], &s);
        }
    }
    for chunk in samples.chunks_exact(6) {
        let s: [f32; 6] = chunk.try_into().unwrap();
        check_set("TABLE2_ROW1", &TABLE2_ROW1, &r.row1, &s);
        for (j, display) in displays::ALL.iter().enumerate() {
            let what = format!("TABLE2_ROW1 folded for {}", display.name());
            check_folded(&what, &FOLDED_ROW1[j], display, &r.row1_folded[j], &s);
        }
    }
});
