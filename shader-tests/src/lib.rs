//! Nothing to link: this crate holds `tests/shaders.rs`, which parses and validates the WGSL and
//! GLSL snippets that `spectral-quadrature` bakes (naga) and runs them on a Vulkan device
//! (wgpu). It is its own crate so that nothing else compiles naga and wgpu.
//!
//! The README's shader example, with wgpu and naga: put the snippet before your shader.
//!
//! ```
//! use spectral_quadrature::tables::shaders;
//!
//! // Samples at TABLE2_ROW2_WL in, encoded sRGB out.
//! let my_shader = r"
//! @group(0) @binding(0) var<storage, read> samples: array<array<f32, 4>>;
//! @group(0) @binding(1) var<storage, read_write> pixels: array<vec4<f32>>;
//!
//! @compute @workgroup_size(64)
//! fn main(@builtin(global_invocation_id) id: vec3<u32>) {
//!     let i = id.x;
//!     if (i < arrayLength(&samples)) {
//!         pixels[i] = vec4<f32>(srgb_encode(table2_row2_srgb_linear(samples[i])), 1.0);
//!     }
//! }
//! ";
//! let source = format!("{}\n{}", shaders::WGSL, my_shader);
//!
//! fn pixels_module(device: &wgpu::Device, source: &str) -> wgpu::ShaderModule {
//!     device.create_shader_module(wgpu::ShaderModuleDescriptor {
//!         label: Some("spectral pixels"),
//!         source: wgpu::ShaderSource::Wgsl(source.into()),
//!     })
//! }
//!
//! // naga, wgpu's shader compiler, takes it:
//! let module = naga::front::wgsl::parse_str(&source).unwrap();
//! naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::empty())
//!     .validate(&module)
//!     .unwrap();
//! # let _ = pixels_module;
//! ```
