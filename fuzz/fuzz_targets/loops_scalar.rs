//! The batch and planar loops at every width and length, with the scalar loops (those of targets without f32 vector units: microcontrollers) forced
//! (`common::loops` has the shapes and the checks).
#![no_main]

use libfuzzer_sys::fuzz_target;
use spectral_quadrature::__fuzzing::Loops;

fuzz_target!(
    init: common::loops::announce(Loops::Scalar),
    |data: &[u8]| common::loops::run(Loops::Scalar, data)
);
