//! The `dembound` command line: a thin caller of the library
//! ([`dembound::cli::main`]).

fn main() -> std::process::ExitCode {
    dembound::cli::main()
}
