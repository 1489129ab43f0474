//! The tables baked at compile time by `build.rs` from `data/` (see the header of the generated
//! file for the inputs and their checksums), each constant made by its type's checked
//! constructor when the crate compiles. [`ALL_TABLES`] lists every constant of numbers with its
//! size and [`TABLE_BYTES`] sums them; `sets`, `folded`, `groups`, `integer` and `upsampling`
//! each end with the list of what they hold (`NAMES`, `all!`).

// A module of its own, so that lib.rs is a facade. The generated code makes every constant with
// the checked constructor of the crate's type it instantiates, named at the crate's root
// (`crate::WavelengthSet::new`, `crate::Display::from_matrices`, ...), in constant evaluation,
// and a few functions of those types read numbers from it: the observer's matrices
// (`xyz_from_ac1c2`, `ac1c2_from_xyz`, `Display::new`, `WavelengthSet::fold`) and the 8-bit
// encoders of the baked power laws (`TransferFunction::encode_u8`, `Display::encode_u8`,
// `IntegerSet::new`). Item by item the two directions form no loop: the constructors the file
// calls take what they check as arguments and read no table, but `IntegerSet::new`, which reads
// `GAMMA_ENCODERS`, made by `GammaEncoder8::new`, which reads nothing (DESIGN.md, "The runtime,
// by role"). Module by module they meet here, as they must while one generated file holds both
// the numbers and the constants. `.ci/module-graph` does not read the generated file: it counts
// the reads, so `tables` is at the bottom of its layers.

include!(concat!(env!("OUT_DIR"), "/tables.rs"));

/// Shader source for the scene the tables were baked for: its colour sets and displays in WGSL
/// and GLSL. `build.rs` writes it from the same f64 values as the Rust tables and rounds them
/// the same way, so every shader constant is the same f32 as its Rust counterpart.
///
/// For each colour set `<SET>` (lower case `<set>`) and display `<DISPLAY>` (`<display>`) the
/// scene bakes:
///
/// | WGSL item | what | Rust counterpart |
/// |---|---|---|
/// | `<SET>_WL: array<f32, N>` | wavelengths in nm: the samples' order | `<SET>.wavelengths_nm()` |
/// | `<SET>_AC1C2: array<vec3<f32>, N>` | weights for A, C1, C2, one column per wavelength | `<SET>.weights()` |
/// | `<SET>_<DISPLAY>: array<vec3<f32>, N>` | weights for linear RGB, one column per wavelength | `folded::<SET>_<DISPLAY>.weights()` |
/// | `<set>_ac1c2(s: array<f32, N>) -> vec3<f32>` | samples → `[A, C1, C2]` | [`WavelengthSet::ac1c2`](crate::WavelengthSet::ac1c2) |
/// | `<set>_<display>_linear(s: array<f32, N>) -> vec3<f32>` | samples → linear RGB | [`FoldedSet::linear_rgb`](crate::FoldedSet::linear_rgb) |
/// | `<display>_encode(rgb: vec3<f32>) -> vec3<f32>` | linear RGB → clipped, encoded 0..=1 | [`Display::encode`](crate::Display::encode) with [`GamutMapping::Clip`](crate::GamutMapping::Clip) |
///
/// GLSL has the same names with `float[N]`, `vec3[N]`, `vec3 <set>_ac1c2(float s[N])` and so
/// on. Helpers start with `sq_`. Per-channel rule sets are left out (alone they give no
/// colour), and so are run-time lookup-table transfer functions, which a scene cannot name.
///
/// # Accuracy
///
/// The products are summed in the runtime's order. Whether the shader compiler fuses them into
/// FMA or not, each channel of `<set>_ac1c2` and `<set>_<display>_linear` is within
/// [`f32_budget`](crate::f32_budget)`(N, Σ|wᵢ·sᵢ|)` of the runtime's. `<display>_encode` uses
/// the shader's f32 `pow`, whose error WGSL and Vulkan inherit from `exp2(y · log2(x))`; on the
/// same linear input it stays within 5.7e-7 of the runtime's f64 curve (the largest value of
/// the bound `shader-tests/tests/shaders.rs` derives from those precisions). `shader-tests/tests/shaders.rs` runs both
/// snippets on a Vulkan device and checks every output against these bounds.
///
/// Shaders may flush subnormal values to zero, and what they do with not-a-number values is up
/// to the implementation: the runtime's rule that such a pixel turns black does not carry over.
pub mod shaders {
    /// The WGSL snippet: module-scope `const` declarations and functions. Put it before your
    /// own code, e.g. `format!("{}\n{}", WGSL, my_shader)`.
    pub const WGSL: &str = include_str!(concat!(env!("OUT_DIR"), "/shaders.wgsl"));
    /// The GLSL snippet: `const` arrays and functions, without a `#version` line. Put it
    /// after your `#version` (3.30, ES 3.00 or later) and, in GLSL ES, after
    /// `precision highp float;`.
    pub const GLSL: &str = include_str!(concat!(env!("OUT_DIR"), "/shaders.glsl"));
}
