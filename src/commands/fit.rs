//! `cellsweep fit`: the beta_crit line with bootstrap intervals, beside the paper's.

use cellsweep_stats::{fit_line, Column};
use serde_json::json;

use crate::cli::{FitArgs, FitFormat};

fn column_line(c: &Column) -> String {
    match (c.beta_star, &c.skipped) {
        (Some(b), _) => format!(
            "  L = {:>3}  sigma = {:>3}  alpha = {:<5}  alpha~/L~ = {:>7.2}  beta* = {:>6.2}",
            c.L, c.sigma, c.alpha, c.x, b
        ),
        (None, why) => format!(
            "  L = {:>3}  sigma = {:>3}  alpha = {:<5}  skipped: {}",
            c.L,
            c.sigma,
            c.alpha,
            why.as_deref().unwrap_or("no crossing")
        ),
    }
}

pub fn run(args: FitArgs) -> anyhow::Result<i32> {
    let loaded = args.source.load()?;
    match fit_line(
        &loaded.counts,
        &loaded.scales,
        args.bootstrap as usize,
        args.seed,
    ) {
        Ok(fit) => {
            if args.format == FitFormat::Json {
                println!("{}", serde_json::to_string_pretty(&fit)?);
            } else {
                println!("beta_crit = a alpha~/L~ + b, fitted to {} (alpha~ = 2 pi R0 d alpha_eff, L~ = L/R0):", loaded.name);
                println!(
                    "  a  = {:>8.4}   95% CI [{:.4}, {:.4}]   (paper: {})",
                    fit.a, fit.a_ci[0], fit.a_ci[1], fit.paper_a
                );
                println!(
                    "  b  = {:>8.3}   95% CI [{:.3}, {:.3}]   (paper: {})",
                    fit.b, fit.b_ci[0], fit.b_ci[1], fit.paper_b
                );
                println!(
                    "  R^2 = {:.4}, {} bootstrap resamples over replicates",
                    fit.r2, fit.bootstrap
                );
                println!("columns:");
                for c in &fit.columns {
                    println!("{}", column_line(c));
                }
            }
            Ok(0)
        }
        Err(no) => {
            if args.format == FitFormat::Json {
                println!(
                    "{}",
                    serde_json::to_string_pretty(
                        &json!({ "error": no.reason, "columns": no.columns })
                    )?
                );
            } else {
                println!("columns:");
                for c in &no.columns {
                    println!("{}", column_line(c));
                }
            }
            eprintln!(
                "error: cannot fit the beta_crit line to {}: {}",
                loaded.name, no.reason
            );
            Ok(1)
        }
    }
}
