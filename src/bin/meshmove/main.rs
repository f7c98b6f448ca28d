//! The `meshmove` command line: `meshmove bench` measures the solvers (more subcommands join it).

use clap::{Parser, Subcommand};

mod bench;

#[derive(Parser)]
#[command(name = "meshmove", version, about = "Biharmonic, Laplacian and spring mesh deformation")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Cost per solve of every method against a direct solve and plain Jacobi, 16k to 4M vertices.
    Bench(bench::Args),
}

fn main() -> std::process::ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Bench(a) => bench::run(&a),
    };
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("meshmove: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}
