//! What the target has: whether its f32 vector units make the portable chunked loops worth
//! running. A leaf, so that `forced` (the loop caps) and `planar` read it without importing each
//! other.

#![forbid(unsafe_code)]

/// Whether the target has vector units for f32 that the chunked loops vectorize for (SSE2 on
/// x86, NEON, WebAssembly SIMD). Without them (microcontrollers such as the Cortex-M4F, whose
/// FPU is scalar) the chunks' buffers are only extra loads and stores, and
/// [`FoldedSet::encode_u8_planar_to_interleaved`](crate::FoldedSet::encode_u8_planar_to_interleaved) goes one pixel at a time
/// instead (`planar::scalar` for sRGB with `Clip`), in fewer instructions per pixel on the M4F
/// (docs/performance.md has the counts under QEMU and their commands). `tests/planar.rs` checks
/// that the chunked form equals `encode_u8`.
pub(crate) const VECTOR_UNITS: bool = cfg!(any(
    target_feature = "sse2",
    target_feature = "neon",
    target_feature = "simd128"
));
