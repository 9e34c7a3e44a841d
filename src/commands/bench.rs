//! `cellsweep bench`: speed of the solver on this machine, on one core (`report::bench`).

use std::path::PathBuf;

use cellsweep_report::bench;
use cellsweep_solver::{Config, Params};

use crate::cli::BenchArgs;

pub fn run(args: BenchArgs) -> anyhow::Result<()> {
    let params = Params {
        alpha: 0.1,
        beta: 14.0,
        L: 90,
        sigma: 5.0,
        ..Params::default()
    };
    let script = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scripts/numpy_yardstick.py");
    let (mut report, check) = bench::kernel_rates(&params);
    if !args.no_yardstick {
        bench::add_yardstick(&mut report, &check, &args.python, &script);
    }
    if !args.quick {
        let mut config = Config {
            params,
            ..Config::default()
        };
        args.numerics.apply(&mut config.protocol);
        bench::add_trajectory(&mut report, &config, &args.python, &script)?;
    }
    match args.json {
        true => println!("{}", serde_json::to_string_pretty(&report)?),
        false => print!("{}", bench::text(&report)),
    }
    Ok(())
}
