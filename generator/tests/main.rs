//! The integration tests, linked as one test binary (`--test integration`): each file of tests/
//! is a module here, so that a test build compiles and links one binary instead of one per file.
//! Run one file's tests with its module name as the filter, `--test integration -- calibration::`.

mod calibration;
mod data_files;
mod derivation;
mod errors;
mod high_precision;
mod layout;
mod observers;
mod planckian;
mod provenance;
mod scene;
mod shared_cache;
mod upsampling;
mod user;
