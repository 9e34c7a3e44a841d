//! Flags of the commands that run the solver directly: `model`, `relax`, `simulate`, `bench`,
//! and the collision's numerics they share with a sweep.

use clap::Args;

use cellsweep_solver::Geometry;

/// Parameters shared by the commands that run the model.
#[derive(Debug, Args)]
pub struct ModelArgs {
    /// Line-tension parameter alpha.
    #[arg(long, default_value_t = 0.1)]
    pub alpha: f64,
    /// Fiber spacing L (even, lattice sites).
    #[arg(long = "L", default_value_t = 90)]
    pub spacing: u32,
    /// Fiber geometry: two parallel fibers or one.
    #[arg(long, default_value = "two")]
    pub geometry: Geometry,
    /// Any other SPEC parameter, as NAME=VALUE (repeatable), e.g. --set tau=50 --set R0=20.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Single-cell lattice, NXxNY (default 200x200).
    #[arg(long, value_name = "NXxNY")]
    pub lattice: Option<String>,
}

#[derive(Debug, Args)]
pub struct RelaxArgs {
    #[command(flatten)]
    pub model: ModelArgs,
    /// Relaxation steps (default: 40 tau0 = 20,000 steps at dt = 0.002).
    #[arg(long)]
    pub steps: Option<u64>,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct SimulateArgs {
    #[command(flatten)]
    pub model: ModelArgs,
    /// Polarity feedback beta.
    #[arg(long, default_value_t = 10.0)]
    pub beta: f64,
    /// Cell-cell adhesion sigma.
    #[arg(long, default_value_t = 5.0)]
    pub sigma: f64,
    /// Seed of the run; the prep and collision seeds derive from it.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Pair lattice, NXxNY (default: twice the single-cell width, same height).
    #[arg(long, value_name = "NXxNY")]
    pub pair_lattice: Option<String>,
    /// Relaxation time, tau0.
    #[arg(long, default_value_t = 40.0)]
    pub relax_time: f64,
    /// Free-motion time, tau0.
    #[arg(long, default_value_t = 400.0)]
    pub free_time: f64,
    /// Longest collision time, tau0.
    #[arg(long, default_value_t = 400.0)]
    pub collide_time: f64,
    /// Run the collision to the end instead of stopping at the decided outcome.
    #[arg(long)]
    pub full: bool,
    #[command(flatten)]
    pub numerics: CollisionNumerics,
    /// A classifier setting, as NAME=VALUE (repeatable): contact_overlap, speed_fraction,
    /// min_speed, velocity_window, sustain_window, walk_past_margin.
    #[arg(long = "classifier", value_name = "NAME=VALUE")]
    pub classifier: Vec<String>,
    /// Split every step over two threads by rows (the same result, bit for bit): about 1.6x
    /// faster for one interactive run on 2 cores. Sweeps run one process per core instead.
    #[arg(long)]
    pub parallel: bool,
    #[command(flatten)]
    pub movie: MovieArgs,
    /// Print the result as one JSON object.
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Skip the whole trajectory (takes about a minute); only the step rates.
    #[arg(long)]
    pub quick: bool,
    /// Skip the NumPy yardstick.
    #[arg(long)]
    pub no_yardstick: bool,
    /// Python interpreter for the yardstick.
    #[arg(long, default_value = "python3")]
    pub python: String,
    #[command(flatten)]
    pub numerics: CollisionNumerics,
}

/// How the collision stage is computed (`simulate` and `bench`).
#[derive(Debug, Args)]
pub struct CollisionNumerics {
    /// Per-cell windows in the collision (one run of columns per row): a site leaves a cell's
    /// window only while |phi| and |P| are below this bound there and nearby; 0 computes both
    /// cells on the whole lattice
    #[arg(long, value_name = "BOUND", default_value_t = cellsweep_solver::PatchSettings::default().bound)]
    pub patch_bound: f64,
    /// Float type of the collision stage: f64 (the reference) or f32 (faster; agrees with f64
    /// in outcome statistics, not trajectory by trajectory)
    #[arg(long, value_name = "f64|f32", default_value = "f64")]
    pub precision: cellsweep_solver::Precision,
}

impl CollisionNumerics {
    /// Set these options in `protocol`.
    pub fn apply(&self, protocol: &mut cellsweep_solver::Protocol) {
        protocol.patch.bound = self.patch_bound;
        protocol.precision = self.precision;
    }
}

/// A collision's movie and observables (`simulate`, `replay`).
#[derive(Debug, Args, Clone)]
pub struct MovieArgs {
    /// Write PNG snapshots of the collision (phi with its 0.5 contour, fibers, polarity) into
    /// this folder, and an animated GIF of them.
    #[arg(long, value_name = "DIR")]
    pub frames: Option<std::path::PathBuf>,
    /// Time between snapshots, tau0.
    #[arg(long, default_value_t = 10.0)]
    pub frame_every: f64,
    /// Write the collision's observables (one JSON object per sample) to this file.
    #[arg(long, value_name = "FILE")]
    pub track: Option<std::path::PathBuf>,
}
