//! The integration tests, linked as one test binary (`--test integration`): each file of tests/
//! is a module here, so that a test build compiles and links one binary instead of one per file.
//! Run one file's tests with its module name as the filter, `--test integration -- render::`.

mod cornell;
mod render;
