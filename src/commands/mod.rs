//! One module per subcommand. Each returns the process's exit code.

mod bench;
mod compare;
mod converge;
mod export;
mod fit;
mod import;
mod model;
mod plot;
mod relax;
mod replay;
mod report;
mod reset;
mod run;
mod serve;
mod simulate;
mod slurm;
mod status;
mod table;

use crate::cli::{Cli, Command};

pub fn dispatch(cli: Cli) -> anyhow::Result<i32> {
    match cli.command {
        Command::Relax(args) => relax::run(args).map(|_| 0),
        Command::Simulate(args) => simulate::run(args).map(|_| 0),
        Command::Run(args) => run::run(args),
        Command::Status(args) => status::run(args).map(|_| 0),
        Command::Table(args) => table::run(args).map(|_| 0),
        Command::Fit(args) => fit::run(args),
        Command::Compare(args) => compare::run(args).map(|_| 0),
        Command::Converge(args) => converge::run(args).map(|_| 0),
        Command::Replay(args) => replay::run(args),
        Command::Verify(args) => replay::verify(args),
        Command::Export(args) => export::run(args).map(|_| 0),
        Command::Import(args) => import::run(args).map(|_| 0),
        Command::Reset(args) => reset::run(args).map(|_| 0),
        Command::Plot(args) => plot::run(args).map(|_| 0),
        Command::Report(args) => report::run(args).map(|_| 0),
        Command::Serve(args) => serve::run(args).map(|_| 0),
        Command::Bench(args) => bench::run(args).map(|_| 0),
        Command::Completions(args) => {
            let mut cmd = <Cli as clap::CommandFactory>::command();
            clap_complete::generate(args.shell, &mut cmd, "cellsweep", &mut std::io::stdout());
            Ok(0)
        }
        Command::Man => {
            clap_mangen::Man::new(<Cli as clap::CommandFactory>::command())
                .render(&mut std::io::stdout())?;
            Ok(0)
        }
        Command::Submit(args) => slurm::submit(args),
        Command::Collect(args) => slurm::collect(args).map(|_| 0),
        Command::Worker(args) => {
            if let Some(dir) = &args.slurm {
                cellsweep_scheduler::slurm::serve_array_task(dir, args.kind)?;
                return Ok(0);
            }
            let stdin = std::io::stdin();
            let stdout = std::io::stdout();
            cellsweep_scheduler::worker::serve(stdin.lock(), stdout.lock())?;
            Ok(0)
        }
    }
}
