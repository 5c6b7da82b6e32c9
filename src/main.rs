//! The `pdbem` binary: see [`pdbem::cli`].

fn main() -> std::process::ExitCode {
    pdbem::cli::main()
}
