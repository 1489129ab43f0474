//! The integration tests, which use the public API alone, linked as one test binary
//! (`--test integration`): each file of tests/ is a module here. Run one file's tests with its
//! module name as the filter, `--test integration -- layout::`. The tests that reach into the
//! generator's modules are its unit tests, `src/tests/`.

mod layout;
mod provenance;
