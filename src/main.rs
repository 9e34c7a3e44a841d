//! `cellsweep`: reproduce, resume and query phase diagrams of cell-cell collisions on nanofibers.

mod cli;
mod commands;
mod output;
mod progress;

use clap::Parser;

/// What a write to a closed pipe does: `Die` as any Unix filter (`status | head` ends quietly),
/// `Fail` while a run's workers compute (the write fails and is ignored, so the run finishes
/// its jobs and leaves none `running`).
pub enum OnBrokenPipe {
    Die,
    Fail,
}

pub fn on_broken_pipe(how: OnBrokenPipe) {
    let action = match how {
        OnBrokenPipe::Die => libc::SIG_DFL,
        OnBrokenPipe::Fail => libc::SIG_IGN,
    };
    // SAFETY: setting a signal's disposition to default or ignore runs no handler code.
    unsafe {
        libc::signal(libc::SIGPIPE, action);
    }
}

fn main() {
    // `cellsweep help --help` (and `help run -h`) is a request for help, as `--help` is.
    let mut argv: Vec<std::ffi::OsString> = std::env::args_os().collect();
    if argv.get(1).is_some_and(|a| a == "help") {
        argv.retain(|a| a != "--help" && a != "-h");
    }
    let cli =
        match cli::Cli::try_parse_from(argv) {
            Ok(cli) => cli,
            Err(e) => {
                use clap::error::ErrorKind;
                if matches!(
                    e.kind(),
                    ErrorKind::DisplayHelp
                        | ErrorKind::DisplayVersion
                        | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
                ) {
                    e.exit();
                }
                // Bad flags, like bad files: one line naming the problem, exit 1.
                let text = e.to_string();
                let mut line: Vec<&str> = text
                    .lines()
                    .take_while(|l| !l.trim().is_empty() && !l.starts_with("Usage:"))
                    .map(str::trim)
                    .collect();
                // clap's "did you mean" (a similar subcommand or flag exists) joins the line.
                line.extend(text.lines().map(str::trim).filter(|l| {
                    l.starts_with("tip: a similar") || l.starts_with("tip: some similar")
                }));
                // Lines after one ending in a colon continue it ("not provided: <SWEEP>").
                let mut one = String::new();
                for l in line {
                    if !one.is_empty() {
                        one.push_str(if one.ends_with(':') { " " } else { "; " });
                    }
                    one.push_str(l);
                }
                eprintln!("{one}");
                std::process::exit(1);
            }
        };
    if !matches!(cli.command, cli::Command::Worker(_)) {
        on_broken_pipe(OnBrokenPipe::Die);
    }
    match commands::dispatch(cli) {
        Ok(code) => std::process::exit(code),
        Err(err) => {
            // One clear line naming the problem, with each cause that says something new
            // (SQLite's, say, repeat their message in their source).
            let mut line = err.to_string();
            for cause in err.chain().skip(1) {
                let text = cause.to_string();
                if !line.contains(&text) {
                    line = format!("{line}: {text}");
                }
            }
            eprintln!("error: {}", line.replace('\n', " "));
            std::process::exit(1);
        }
    }
}
