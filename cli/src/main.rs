//! `meshmove`: the paper's cases in one command, the user's own mesh deformed from a TOML case
//! file, and two `.vtu` files compared. One file per subcommand; `Command` is a plain list of
//! variants so that more subcommands merge in without touching the others.

mod bench;
mod compare;
mod deform;
mod demo;
#[cfg(feature = "mpi")]
mod distributed;
mod plot;
mod plot3d;

use clap::{Parser, Subcommand};
use meshmove::Mesh;
use std::path::Path;
use std::process::ExitCode;

/// Writes `mesh` moved by `displacement` (`dim` values per vertex) as a `.vtu`
/// ([`meshmove::io::write_deformed`]); the error names the file.
fn write_deformed(path: &Path, mesh: &Mesh, displacement: &[f64]) -> Result<(), String> {
    meshmove::io::write_deformed(path, mesh, displacement).map_err(|e| format!("{}: {e}", path.display()))
}

#[derive(Parser)]
#[command(name = "meshmove", version, about = "Biharmonic, Laplacian and spring mesh deformation")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run every case of the paper with every method: .vtu meshes, PNG pictures, results.csv.
    Demo(demo::Args),
    /// Deform a mesh (.msh or .vtu) as a TOML case file says; writes a .vtu.
    Deform(deform::Args),
    /// Exit 0 when the coordinates of two .vtu files agree within a tolerance.
    Compare(compare::Args),
    /// Cost per solve of every method against a direct solve and plain Jacobi, 16k to 4M vertices.
    Bench(Box<bench::Args>),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Demo(a) => demo::run(a),
        Command::Deform(a) => deform::run(a),
        Command::Compare(a) => compare::run(a),
        Command::Bench(a) => bench::run(&a).map(|()| ExitCode::SUCCESS).map_err(|e| e.to_string()),
    };
    match result {
        Ok(code) => code,
        Err(msg) => {
            eprintln!("meshmove: error: {msg}");
            ExitCode::FAILURE
        }
    }
}
