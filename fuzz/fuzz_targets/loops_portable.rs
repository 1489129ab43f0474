//! The batch and planar loops at every width and length, with the portable loops (SSE2 code on x86-64) forced
//! (`common::loops` has the shapes and the checks).
#![no_main]

use libfuzzer_sys::fuzz_target;
use spectral_quadrature::__fuzzing::Loops;

fuzz_target!(
    init: common::loops::announce(Loops::Portable),
    |data: &[u8]| common::loops::run(Loops::Portable, data)
);
