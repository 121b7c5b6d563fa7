//! The `dembound` command line as a library: everything the binary does
//! lives here, so that other front ends (the Python bindings,
//! `crates/dembound-py`) produce the very same `--json` documents from the
//! same code. [`cli`] (argument parsing and subcommands), [`scenario_file`]
//! (loading scenarios and `--set` overrides), [`output`] (tables, CSV,
//! JSON, files, progress) and [`plot`] (figures).

pub mod cli;
pub mod output;
pub mod plot;
pub mod scenario_file;
