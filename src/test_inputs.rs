//! Inputs shared by the unit tests that compare the encoding paths with each other: a small
//! deterministic generator (the library's tests take no dependency for it) and the edge values
//! every path must treat alike.

#![forbid(unsafe_code)]

/// xorshift64*: deterministic inputs. The seed must not be 0.
pub(crate) struct Rng(pub(crate) u64);

impl Rng {
    /// The next 64 random bits.
    pub(crate) fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// Uniform in 0..1, 24 bits.
    pub(crate) fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// The edge inputs: NaN, ±Inf, ±0, negative (tiny to huge), subnormal (the smallest, a middle
/// one, the largest), the smallest normal, tiny, ½, values next to 1, huge, and the f32 ends.
pub(crate) const EDGES: [f32; 22] = [
    f32::NAN,
    f32::INFINITY,
    f32::NEG_INFINITY,
    0.0,
    -0.0,
    -1.0,
    -1e-30,
    -1e-3,
    1.4e-45,
    1.0e-40,
    1.1e-38,
    f32::MIN_POSITIVE,
    1.0e-4,
    0.5,
    1.0,
    0.999_999_94,
    1.000_000_1,
    1.0e30,
    -1.0e30,
    f32::MAX,
    f32::MIN,
    -f32::MIN_POSITIVE,
];

/// Says in the test's output that a check did not run on this machine, and why: written to the
/// process's standard error directly, past the test harness's capture (which holds back
/// `eprintln!` of passing tests), so that a skipped check shows in every run; once per message.
///
/// `capability` names what is missing (`"avx512"`, `"avx2"`). Where the environment variable
/// `SPECTRAL_QUADRATURE_REQUIRE` lists it (comma-separated; `.ci/run` sets it from the machine's
/// `/proc/cpuinfo`), the machine has it and the test must not pass by skipping: this panics.
pub(crate) fn skipped(capability: &str, what: &str, why: &str) {
    use std::io::Write;
    if required(capability) {
        panic!(
            "{what}: {why}, but SPECTRAL_QUADRATURE_REQUIRE says this machine has {capability}: \
             the check may not be skipped here"
        );
    }
    static SAID: std::sync::Mutex<std::vec::Vec<std::string::String>> =
        std::sync::Mutex::new(std::vec::Vec::new());
    let line = std::format!("skipped: {what}: {why}");
    let mut said = SAID.lock().unwrap_or_else(|e| e.into_inner());
    if !said.contains(&line) {
        let _ = writeln!(std::io::stderr(), "{line}");
        said.push(line);
    }
}

/// Whether `SPECTRAL_QUADRATURE_REQUIRE` (a comma-separated list) names `capability`.
pub(crate) fn required(capability: &str) -> bool {
    std::env::var("SPECTRAL_QUADRATURE_REQUIRE")
        .is_ok_and(|list| list.split(',').any(|c| c.trim() == capability))
}
