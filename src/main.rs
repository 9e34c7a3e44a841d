//! `cellsweep`: reproduce, resume and query phase diagrams of cell-cell collisions on nanofibers.

mod cli;
mod commands;
mod frames;
mod progress;

use clap::Parser;

fn main() {
    let cli = cli::Cli::parse();
    match commands::dispatch(cli) {
        Ok(code) => std::process::exit(code),
        Err(err) => {
            // One clear line naming the problem; the chain of causes joined on it.
            eprintln!("error: {err:#}");
            std::process::exit(1);
        }
    }
}
