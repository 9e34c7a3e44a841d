//! The values `submit` writes into `#SBATCH` lines, checked against Slurm's own syntax before
//! anything is written: a time limit as sbatch reads one, partition and account names, and an
//! extra option as one word (no space, quote, `$`, backtick, `;` or backslash can reach a
//! script).

/// A value Slurm would not read, with what it should look like.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct SyntaxError(pub String);

/// Slurm's `--time`: `MM`, `MM:SS`, `HH:MM:SS`, `D-HH`, `D-HH:MM`, `D-HH:MM:SS`, or
/// `UNLIMITED` / `INFINITE`; every field a whole number, the time not zero.
pub fn time_limit(s: &str) -> Result<(), SyntaxError> {
    let bad = || {
        format!(
            "{s:?} is not a Slurm time limit (MM, MM:SS, HH:MM:SS, D-HH, D-HH:MM, D-HH:MM:SS, \
             or UNLIMITED)"
        )
    };
    if matches!(s, "UNLIMITED" | "INFINITE" | "unlimited" | "infinite") {
        return Ok(());
    }
    let (days, rest) = match s.split_once('-') {
        Some((d, r)) => (Some(d), r),
        None => (None, s),
    };
    let fields: Vec<&str> = rest.split(':').collect();
    let whole = |f: &str| !f.is_empty() && f.len() <= 9 && f.bytes().all(|b| b.is_ascii_digit());
    let shape_ok = match days {
        Some(d) => whole(d) && (1..=3).contains(&fields.len()),
        None => (1..=3).contains(&fields.len()),
    };
    if !shape_ok || !fields.iter().all(|f| whole(f)) {
        return Err(SyntaxError(bad()));
    }
    let n = |f: &str| f.parse::<u64>().unwrap_or(0);
    // Minutes and seconds past the first field are below 60.
    if fields.iter().skip(1).any(|f| n(f) >= 60) {
        return Err(SyntaxError(bad()));
    }
    if days.map_or(0, n) + fields.iter().map(|f| n(f)).sum::<u64>() == 0 {
        return Err(SyntaxError(format!("{s:?} is a time limit of zero")));
    }
    Ok(())
}

fn is_name_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.')
}

/// A Slurm partition, or a comma-separated list of them (sbatch takes either).
pub fn partition(s: &str) -> Result<(), SyntaxError> {
    if !s.is_empty()
        && s.split(',')
            .all(|p| !p.is_empty() && p.chars().all(is_name_char))
    {
        Ok(())
    } else {
        Err(SyntaxError(format!(
            "{s:?} is not a Slurm partition (letters, digits, '_', '-', '.'; several separated \
             by commas)"
        )))
    }
}

/// A Slurm account name.
pub fn account(s: &str) -> Result<(), SyntaxError> {
    if !s.is_empty() && s.chars().all(is_name_char) {
        Ok(())
    } else {
        Err(SyntaxError(format!(
            "{s:?} is not a Slurm account (letters, digits, '_', '-', '.')"
        )))
    }
}

/// One extra sbatch option as one word: `--name`, `--name=value` or `-X` / `-Xvalue`, the
/// value free of whitespace, quotes, `$`, backticks, `;`, `\`, `<` and `>`.
pub fn sbatch_arg(s: &str) -> Result<(), SyntaxError> {
    let (name, value) = match s.split_once('=') {
        Some((n, v)) => (n, Some(v)),
        None => (s, None),
    };
    let long = name.strip_prefix("--").is_some_and(|n| {
        n.starts_with(|c: char| c.is_ascii_alphabetic())
            && n.chars().all(|c| c.is_ascii_alphanumeric() || c == '-')
    });
    let short = !name.starts_with("--")
        && name.strip_prefix('-').is_some_and(|n| {
            n.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
                && n.chars().skip(1).all(|c| !c.is_whitespace())
        });
    let safe = |v: &str| {
        v.chars().all(|c| {
            c.is_ascii_graphic() && !matches!(c, '"' | '\'' | '`' | '$' | ';' | '\\' | '<' | '>')
        })
    };
    if (long || short) && safe(name) && value.is_none_or(|v| !v.is_empty() && safe(v)) {
        Ok(())
    } else {
        Err(SyntaxError(format!(
            "{s:?} is not one sbatch option (--name or --name=value, one word without spaces, \
             quotes, $, backticks, ;, \\, < or >)"
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slurm_time_limits() {
        for ok in [
            "30",
            "30:00",
            "1:00:00",
            "2-0",
            "2-12:30",
            "1-00:00:00",
            "UNLIMITED",
        ] {
            assert!(time_limit(ok).is_ok(), "{ok}");
        }
        for bad in [
            "abc", "", "1:2:3:4", "1:60", "-5", "1-", "0", "0:00:00", "1h", "1:00 ;x",
        ] {
            assert!(time_limit(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn names_and_options() {
        assert!(partition("debug").is_ok() && partition("gpu,cpu-long").is_ok());
        for bad in ["a b;x", "", "a,,b", "$(id)", "x\ny"] {
            assert!(partition(bad).is_err(), "{bad}");
        }
        assert!(account("lab_1").is_ok() && account("a,b").is_err());
        for ok in [
            "--account=abc",
            "--exclusive",
            "--constraint=a|b",
            "-N1",
            "--mem=4G",
        ] {
            assert!(sbatch_arg(ok).is_ok(), "{ok}");
        }
        for bad in [
            "--x=$(id)",
            "--x=a b",
            "account=abc",
            "--",
            "--x=",
            "--x='y'",
            "-",
        ] {
            assert!(sbatch_arg(bad).is_err(), "{bad}");
        }
    }
}
