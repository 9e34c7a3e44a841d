//! `cellsweep fit`: the beta_crit line with its intervals, beside the paper's; each column's
//! beta* by the model and by interpolation (`report::fitted_line`).

use cellsweep_report::fitted_line::FittedLine;

use crate::cli::{FitArgs, FitFormat};

pub fn run(args: FitArgs) -> anyhow::Result<i32> {
    let loaded = args.select.apply(args.source.load()?)?;
    let fitted = FittedLine::fit(
        &loaded.counts,
        &loaded.scales,
        args.bootstrap as usize,
        args.seed,
        args.method.method(),
    );
    match args.format {
        FitFormat::Json => println!("{}", serde_json::to_string_pretty(&fitted.json())?),
        FitFormat::Text => print!("{}", fitted.text(&loaded.name)),
    }
    match &fitted.line {
        Ok(_) => Ok(0),
        Err(no) => {
            eprintln!(
                "error: cannot fit the beta_crit line to {}: {}",
                loaded.name, no.reason
            );
            Ok(1)
        }
    }
}
