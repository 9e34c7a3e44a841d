//! The beta_crit line over every spacing, and the free speed against beta (Eq. 13, Fig. A4).

use super::{no_data, Claim, Verdict};
use crate::analysis::Analysis;
use crate::figures::mean_and_error;

pub(super) fn global_fit(an: &Analysis<'_>) -> Claim {
    let (source, quote, rule) = (
        "Section 3.3, Eq. (13)",
        "β_crit = 0.6 α̃/L̃ − 12 provides a good global description of the transition between \
         walk-past and training in Fig. 3 and 4 (and also A1).",
        "the line fitted over every spacing at σ = 5 (β* from each column's model, 95% \
         intervals): reproduced when \
         both intervals hold the paper's values, R² ≥ 0.8 and all three spacings are in; \
         partly when one interval holds it or a spacing is missing; else not.",
    );
    let spacings: Vec<u32> = [90, 80, 70]
        .into_iter()
        .filter(|&l| an.collection.diagram(l, 5.0).is_some())
        .collect();
    let fit = match &an.line_sigma5 {
        Ok(f) => f,
        Err(_) if spacings.is_empty() => {
            return no_data(source, quote, rule, "a diagram at σ = 5");
        }
        Err(no) => {
            return Claim {
                source,
                quote,
                rule,
                evidence: format!("no line: {}", no.reason),
                verdict: Verdict::Not,
            }
        }
    };
    let a_in = fit.a_ci[0] <= fit.paper_a && fit.paper_a <= fit.a_ci[1];
    let b_in = fit.b_ci[0] <= fit.paper_b && fit.paper_b <= fit.b_ci[1];
    let all = spacings.len() == 3;
    Claim {
        source,
        quote,
        rule,
        evidence: format!(
            "a = {:.3} [{:.3}, {:.3}], b = {:.1} [{:.1}, {:.1}], R² = {:.3}, over L = {} \
             ({} columns)",
            fit.a,
            fit.a_ci[0],
            fit.a_ci[1],
            fit.b,
            fit.b_ci[0],
            fit.b_ci[1],
            fit.r2,
            spacings
                .iter()
                .map(u32::to_string)
                .collect::<Vec<_>>()
                .join(", "),
            fit.columns.iter().filter(|c| c.beta_star.is_some()).count()
        ),
        verdict: if a_in && b_in && fit.r2 >= 0.8 && all {
            Verdict::Reproduced
        } else if a_in || b_in {
            Verdict::Partly
        } else {
            Verdict::Not
        },
    }
}

/// Spearman's rank correlation of (x, y) pairs (no ties expected in x).
fn spearman(xy: &[(f64, f64)]) -> f64 {
    let rank = |v: Vec<f64>| -> Vec<f64> {
        let mut idx: Vec<usize> = (0..v.len()).collect();
        idx.sort_by(|&a, &b| v[a].total_cmp(&v[b]));
        let mut r = vec![0.0; v.len()];
        for (k, &i) in idx.iter().enumerate() {
            r[i] = k as f64;
        }
        r
    };
    let rx = rank(xy.iter().map(|p| p.0).collect());
    let ry = rank(xy.iter().map(|p| p.1).collect());
    let n = xy.len() as f64;
    let d2: f64 = rx.iter().zip(&ry).map(|(a, b)| (a - b).powi(2)).sum();
    1.0 - 6.0 * d2 / (n * (n * n - 1.0))
}

pub(super) fn speed(an: &Analysis<'_>) -> Claim {
    let (source, quote, rule) = (
        "Discussion, Fig. A4",
        "In our model, cells with higher positive feedback values β also have higher cell \
         speeds (α = 0.2, L = 90; each point an average of 20 simulations, standard error \
         smaller than the marker).",
        "mean free speed per β at α = 0.2: reproduced when Spearman's rank correlation with β \
         is at least 0.9; partly when positive; else not.",
    );
    let Some(r) = an.collection.speed else {
        return no_data(
            source,
            quote,
            rule,
            "the speed check (sweeps/check-speed-alpha0.20.toml)",
        );
    };
    let mut rows: Vec<(f64, f64, f64, usize)> = Vec::new();
    for (i, c) in r.counts.iter().enumerate() {
        let cells: Vec<f64> = r
            .prep_speeds
            .as_ref()
            .map(|s| s[i].clone())
            .unwrap_or_else(|| c.free_speed.into_iter().collect());
        if cells.is_empty() || (c.alpha - 0.2).abs() > 1e-9 {
            continue;
        }
        let (m, se) = mean_and_error(&cells);
        rows.push((c.beta, m, se, cells.len()));
    }
    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
    if rows.len() < 3 {
        return Claim {
            source,
            quote,
            rule,
            evidence: format!(
                "{} β values with a speed at α = 0.2; three are needed",
                rows.len()
            ),
            verdict: Verdict::NoData,
        };
    }
    let rho = spearman(&rows.iter().map(|r| (r.0, r.1)).collect::<Vec<_>>());
    let (first, last) = (rows[0], rows[rows.len() - 1]);
    let max_se = rows.iter().map(|r| r.2).fold(0.0, f64::max);
    Claim {
        source,
        quote,
        rule,
        evidence: format!(
            "speed {:.4} ± {:.4} at β = {} rising to {:.4} ± {:.4} at β = {} (mean ± standard \
             error over {} to {} cells); Spearman ρ = {rho:.2}; largest standard error {:.4}",
            first.1,
            first.2,
            first.0,
            last.1,
            last.2,
            last.0,
            rows.iter().map(|r| r.3).min().unwrap_or(0),
            rows.iter().map(|r| r.3).max().unwrap_or(0),
            max_se
        ),
        verdict: if rho >= 0.9 {
            Verdict::Reproduced
        } else if rho > 0.0 {
            Verdict::Partly
        } else {
            Verdict::Not
        },
    }
}

#[cfg(test)]
mod tests {
    use super::spearman;

    #[test]
    fn spearman_is_one_for_a_rising_and_minus_one_for_a_falling_series() {
        let up: Vec<(f64, f64)> = (0..5).map(|i| (i as f64, (i * i) as f64)).collect();
        let down: Vec<(f64, f64)> = (0..5).map(|i| (i as f64, -(i as f64))).collect();
        assert!((spearman(&up) - 1.0).abs() < 1e-12);
        assert!((spearman(&down) + 1.0).abs() < 1e-12);
    }
}
