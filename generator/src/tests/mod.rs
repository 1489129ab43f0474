//! The generator's unit tests: the tests that reach into its modules (the steps of the
//! derivation, the observers' tables, the scene's parts, the caches, the upsampling's solver) through
//! items that are `pub(crate)`, so that the crate's public surface stays what its users need.
//! Each file is a module here; run one file's tests with its module name as the filter:
//! `cargo test -p spectral-quadrature-generator --lib -- tests::calibration::`. The tests that use
//! the public API alone (the layout of the generated tables, the data files' provenance) are the
//! integration tests of `tests/`.

mod calibration;
mod data_files;
mod derivation;
mod errors;
mod high_precision;
mod observers;
mod plan;
mod planckian;
mod scene;
mod shared;
mod shared_cache;
mod upsampling;
mod user;

/// The Rust tables of `scene` resolved against `d`: its model baked (`inputs` for the header),
/// then formatted, as `generate` does.
pub(crate) fn tables_rs(
    d: &crate::Derivation,
    inputs: &[(std::string::String, std::string::String)],
    scene: &crate::scene::Resolved,
) -> Result<std::string::String, crate::Error> {
    let model = crate::emit::model::Model::bake(d, inputs, scene)?;
    Ok(crate::codegen::tables_rs(&model))
}
