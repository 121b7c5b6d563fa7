//! The `dembound` command line. Everything lives in [`cli`] (argument
//! parsing and subcommands), [`scenario_file`] (loading scenarios and
//! `--set` overrides), [`output`] (tables, CSV, JSON, files, progress) and
//! [`plot`] (figures).

mod cli;
mod output;
mod plot;
mod scenario_file;

fn main() -> std::process::ExitCode {
    cli::main()
}
