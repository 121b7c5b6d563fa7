//! The `dembound` command line. Everything lives in [`cli`] (argument
//! parsing and subcommands), [`scenario_file`] (loading scenarios and
//! `--set` overrides) and [`output`] (tables, CSV, JSON, files, progress).

mod cli;
mod output;
mod scenario_file;

fn main() -> std::process::ExitCode {
    cli::main()
}
