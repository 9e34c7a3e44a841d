//! Flags of the commands that read results: `status`, `table`, `fit`, `compare`, `plot`,
//! `report`, `export` and `import`, and where they read counts from.

use clap::Args;

use super::{DbArgs, Selection};

#[derive(Debug, Args)]
pub struct StatusArgs {
    #[command(flatten)]
    pub db: DbArgs,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
    /// List every failed job and prep with its error.
    #[arg(long)]
    pub failed: bool,
}

/// Where outcome counts come from: a store, or a counts file.
#[derive(Debug, Args)]
pub struct CountsSource {
    /// SQLite database of results.
    #[arg(
        long,
        default_value = "cellsweep.sqlite",
        value_name = "PATH",
        conflicts_with = "counts"
    )]
    pub db: std::path::PathBuf,
    /// The sweep to read (needed when the store holds several).
    #[arg(long)]
    pub sweep: Option<String>,
    /// Read counts from a CSV file instead of a store: columns alpha, beta, L, sigma, n_train,
    /// n_walk, n_reversal, n_undetermined, and optionally label (unstable / breakup).
    #[arg(long, value_name = "FILE.csv", conflicts_with = "data")]
    pub counts: Option<std::path::PathBuf>,
    /// Read the results of a `cellsweep export` file instead of a store (e.g.
    /// data/paper/adaptive-L90-sigma5.csv): no store, no recomputation. Give it again to read
    /// several sweeps as one (`--data data/collapse/R0-32.csv --data data/collapse/R0-48.csv`).
    #[arg(long, value_name = "EXPORT.csv", conflicts_with_all = ["db", "sweep"])]
    pub data: Vec<std::path::PathBuf>,
    /// With several --data: read the runs they share once instead of refusing them (an
    /// extension beside the sweep whose seed it shares, e.g. `--data
    /// data/paper/refined-L90-sigma5.csv --data data/extended/extended-L90-sigma5.csv`): at a
    /// point both hold, the one with more replicates is read, if the other's are among them.
    #[arg(long, requires = "data")]
    pub pool: bool,
}

impl CountsSource {
    /// The results these flags name: an export file, a counts file, or a store.
    pub fn load(&self) -> Result<cellsweep_report::Results, cellsweep_report::load::LoadError> {
        use cellsweep_report::load;
        match (self.data.as_slice(), &self.counts) {
            ([path], _) => load::from_export(path),
            ([], Some(path)) => load::from_counts_csv(path),
            ([], None) => load::from_store(&self.db, self.sweep.as_deref()),
            (paths, _) if self.pool => cellsweep_report::pool::pooled_exports(
                &paths.iter().map(|p| p.as_path()).collect::<Vec<_>>(),
            ),
            (paths, _) => cellsweep_report::Results::merged(
                paths
                    .iter()
                    .map(|p| load::from_export(p))
                    .collect::<Result<_, _>>()?,
            ),
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    Text,
    Csv,
    Json,
}

/// What `fit` prints: a fit has no table to give as CSV.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum FitFormat {
    Text,
    Json,
}

/// The plane of the diagrams: any two axes (`--x R0 --y beta`).
#[derive(Debug, Args)]
pub struct PlaneArgs {
    /// The axis across the diagrams: alpha (the paper's), beta, L, sigma, any other axis of
    /// the sweep (R0, E0, ...), xt (alpha~/L~ at each point's own R0 and d) or Lt (L/R0).
    #[arg(long, default_value = "alpha", value_name = "AXIS")]
    pub x: String,
    /// The axis up the diagrams (beta, the paper's, or any as for --x).
    #[arg(long, default_value = "beta", value_name = "AXIS")]
    pub y: String,
    /// The axes that tell one diagram from another, comma-separated (default: every axis of
    /// the points but --x and --y; `--x R0 --by xt,sigma,Lt` sets cell sizes side by side at
    /// one alpha~/L~ and the paper's geometry scaled).
    #[arg(long, value_name = "AXIS,...", value_delimiter = ',')]
    pub by: Vec<String>,
}

impl PlaneArgs {
    pub fn plane(&self) -> cellsweep_stats::Plane {
        cellsweep_stats::Plane {
            x: self.x.clone(),
            y: self.y.clone(),
            // `--by ''`: no axis, every point in one diagram.
            by: (!self.by.is_empty())
                .then(|| self.by.iter().filter(|a| !a.is_empty()).cloned().collect()),
        }
    }
}

#[derive(Debug, Args)]
pub struct TableArgs {
    #[command(flatten)]
    pub source: CountsSource,
    #[command(flatten)]
    pub select: Selection,
    #[command(flatten)]
    pub plane: PlaneArgs,
    #[arg(long, value_enum, default_value = "text")]
    pub format: Format,
}

#[derive(Debug, Args)]
pub struct FitArgs {
    #[command(flatten)]
    pub source: CountsSource,
    #[command(flatten)]
    pub select: Selection,
    /// text or json.
    #[arg(long, value_enum, default_value = "text")]
    pub format: FitFormat,
    /// How each column's beta* is read: `model`, a logistic model of walk-past against
    /// training over the whole column with a profile-likelihood interval (the line weighted by
    /// the columns' intervals), or `interpolate`, the paper's linear interpolation between
    /// grid points (the line by least squares, intervals by bootstrap). Both are shown.
    #[arg(long, value_enum, default_value = "model")]
    pub method: FitMethod,
    /// Bootstrap resamples (interpolate) or draws from the columns' intervals (model) for the
    /// 95% intervals of the line.
    #[arg(long, default_value_t = 1000, value_parser = clap::value_parser!(u32).range(0..=1_000_000))]
    pub bootstrap: u32,
    /// Seed of the bootstrap.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// How `fit` reads a column's beta*.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum FitMethod {
    Model,
    Interpolate,
}

impl FitMethod {
    pub fn method(self) -> cellsweep_stats::Method {
        match self {
            FitMethod::Model => cellsweep_stats::Method::Model,
            FitMethod::Interpolate => cellsweep_stats::Method::Interpolate,
        }
    }
}

#[derive(Debug, Args)]
pub struct CompareArgs {
    /// The first sweep (A), by name.
    pub a: String,
    /// The second sweep (B), by name (the same name as A to compare two solver versions).
    pub b: String,
    /// The store of A (and of B, unless --db-b is given).
    #[command(flatten)]
    pub db: DbArgs,
    /// The store of B, when it is not A's.
    #[arg(long = "db-b", value_name = "PATH")]
    pub db_b: Option<std::path::PathBuf>,
    /// Solver version of A's results (default: this build's).
    #[arg(long = "version-a", value_name = "VERSION")]
    pub version_a: Option<String>,
    /// Solver version of B's results (default: this build's).
    #[arg(long = "version-b", value_name = "VERSION")]
    pub version_b: Option<String>,
    #[arg(long, value_enum, default_value = "text")]
    pub format: Format,
}

/// Where stored rows come from: a store, or an export file.
#[derive(Debug, Args)]
pub struct RowsSource {
    /// SQLite database of results.
    #[arg(long, default_value = "cellsweep.sqlite", value_name = "PATH")]
    pub db: std::path::PathBuf,
    /// The sweep to read (needed when the store holds several).
    #[arg(long)]
    pub sweep: Option<String>,
    /// Read the rows of a `cellsweep export` file instead of a store (for `verify`, also a
    /// folder of exports: every `*.csv` in it).
    #[arg(long, value_name = "EXPORT.csv", conflicts_with_all = ["db", "sweep"])]
    pub data: Option<std::path::PathBuf>,
}

impl RowsSource {
    /// The sweep's definition and its finished rows.
    pub fn rows(
        &self,
    ) -> Result<
        (
            cellsweep_scheduler::Sweep,
            Vec<cellsweep_store::export::ExportRow>,
        ),
        cellsweep_report::load::LoadError,
    > {
        use cellsweep_report::load;
        match &self.data {
            Some(path) => Ok(cellsweep_scheduler::export_file::read_export(path)?),
            None => load::rows_of_store(&self.db, self.sweep.as_deref()),
        }
    }

    /// Every sweep's rows: a folder given as `--data` is every export (`*.csv`) in it.
    pub fn all_rows(
        &self,
    ) -> anyhow::Result<
        Vec<(
            cellsweep_scheduler::Sweep,
            Vec<cellsweep_store::export::ExportRow>,
        )>,
    > {
        let Some(dir) = self.data.as_ref().filter(|d| d.is_dir()) else {
            return Ok(vec![self.rows()?]);
        };
        let mut files: Vec<std::path::PathBuf> = std::fs::read_dir(dir)
            .map_err(|e| anyhow::anyhow!("{}: {e}", dir.display()))?
            .flatten()
            .map(|e| e.path())
            .filter(|p| p.extension().is_some_and(|x| x == "csv"))
            .collect();
        files.sort();
        if files.is_empty() {
            anyhow::bail!("{}: no export (*.csv) in it", dir.display());
        }
        files
            .iter()
            .map(|f| Ok(cellsweep_scheduler::export_file::read_export(f)?))
            .collect()
    }

    pub fn name(&self) -> String {
        self.data.as_ref().unwrap_or(&self.db).display().to_string()
    }
}

#[derive(Debug, Args)]
pub struct ReplayArgs {
    #[command(flatten)]
    pub source: RowsSource,
    /// The point, as NAME=VALUE pairs over any of its axes (alpha=0.1,beta=46 or
    /// alpha=0.125,beta=22,R0=32); axes left out must not be needed to tell points apart.
    #[arg(long, value_name = "NAME=VALUE,...")]
    pub point: String,
    /// The replicate's index at that point.
    #[arg(long)]
    pub replicate: u32,
    #[command(flatten)]
    pub movie: super::MovieArgs,
    /// Split every step over two threads (the same result, bit for bit).
    #[arg(long)]
    pub parallel: bool,
}

#[derive(Debug, Args)]
pub struct VerifyArgs {
    #[command(flatten)]
    pub source: RowsSource,
    /// How many rows to replay, chosen by --seed.
    #[arg(long, default_value_t = 20, conflicts_with = "all")]
    pub sample: usize,
    /// Seed of the choice of rows.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Replay every row.
    #[arg(long)]
    pub all: bool,
    /// Only rows that ended so (repeat for several): train, walk_past, reversal,
    /// undetermined, collision_breakup, or a prep's unstable or breakup. E.g. `--ended
    /// collision_breakup --ended breakup --all` replays every stored breakup under this
    /// build's rule.
    #[arg(long, value_name = "END")]
    pub ended: Vec<String>,
}

#[derive(Debug, Args)]
pub struct ConvergeArgs {
    /// The baseline's export (e.g. data/paper/refined-L90-sigma5.csv).
    #[arg(long, value_name = "EXPORT")]
    pub baseline: std::path::PathBuf,
    /// The export of a variant of the numerics (repeat for several): a sweep run with dt
    /// halved, another pair lattice, f64 collisions or a finer lattice, over columns the
    /// baseline holds.
    #[arg(long = "variant", value_name = "EXPORT", required = true)]
    pub variants: Vec<std::path::PathBuf>,
    #[arg(long, value_enum, default_value = "text")]
    pub format: Format,
}

#[derive(Debug, Args)]
pub struct PlotArgs {
    #[command(flatten)]
    pub source: CountsSource,
    #[command(flatten)]
    pub select: Selection,
    /// Diagrams on two other axes than (alpha, beta): only those are drawn.
    #[command(flatten)]
    pub plane: PlaneArgs,
    /// Folder for the pictures (created if missing).
    #[arg(long, value_name = "DIR")]
    pub out: std::path::PathBuf,
}

#[derive(Debug, Args)]
#[command(group(clap::ArgGroup::new("source").required(true).args(["db", "data"])))]
pub struct ReportArgs {
    /// A store: every sweep in it.
    #[arg(long, value_name = "PATH")]
    pub db: Option<std::path::PathBuf>,
    /// A `cellsweep export` file, or a folder of them (every *.csv in it, e.g. data/paper):
    /// no store, no recomputation. Give it again to add more (`--data data/paper --data
    /// data/collapse`).
    #[arg(long, value_name = "DIR|FILE.csv")]
    pub data: Vec<std::path::PathBuf>,
    /// Exports of variants of the numerics (a folder of them, e.g. data/convergence, or one
    /// file; give it again to add more): compared column by column with the shown diagrams
    /// under "Is it converged?", never shown as diagrams themselves.
    #[arg(long, value_name = "DIR|FILE.csv")]
    pub variants: Vec<std::path::PathBuf>,
    /// The HTML file to write.
    #[arg(long, value_name = "FILE.html")]
    pub out: std::path::PathBuf,
}

#[derive(Debug, Args)]
pub struct ExportArgs {
    #[command(flatten)]
    pub db: DbArgs,
    /// The sweep to export (needed when the store holds several).
    #[arg(long)]
    pub sweep: Option<String>,
    /// The CSV file to write (replaced atomically).
    #[arg(long, value_name = "FILE.csv")]
    pub out: std::path::PathBuf,
}

#[derive(Debug, Args)]
pub struct ImportArgs {
    /// A file written by `cellsweep export`.
    pub file: std::path::PathBuf,
    #[command(flatten)]
    pub db: DbArgs,
}
