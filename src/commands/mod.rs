//! One module per subcommand.

mod model;
mod relax;
mod simulate;

use crate::cli::{Cli, Command};

pub fn dispatch(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Relax(args) => relax::run(args),
        Command::Simulate(args) => simulate::run(args),
    }
}
