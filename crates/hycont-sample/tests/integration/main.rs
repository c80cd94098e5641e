//! The integration tests of `hycont-sample` in one binary, a module per concern: one link and one
//! build of the library code they instantiate, instead of one per file.

mod adaptive;
mod classify;
mod sample;
mod study_files;
mod table_files;
