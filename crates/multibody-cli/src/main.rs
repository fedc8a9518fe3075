//! The `multibody` command: run, check and describe Dyad multibody models.

#[macro_use]
mod console;
mod catalog;
mod check;
mod exit;
mod fmu;
mod import;
mod inputs;
mod linearize;
mod live;
mod load;
mod output;
mod progress;
mod run;
mod sweep;
mod table;

use clap::{Args, Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

const AFTER_HELP: &str = "\
Exit codes:
  0  success
  1  the model files have errors (syntax, lowering or assembly); nothing was simulated
  2  usage error: bad arguments, or an analysis, model or component kind that does not exist
  3  the simulation failed part way; what it computed was written as NAME.partial.csv
  4  input/output error: a file could not be read or written
  130  stopped by Ctrl-C, SIGTERM or SIGHUP; what was computed was written as NAME.partial.csv (a second
       signal ends at once)

Examples:
  multibody run examples/pendulum.dyad
  multibody run examples/double_pendulum.dyad --animate double_pendulum.html --plot double_pendulum.png
  multibody run examples/ --analysis PendulumSimulation --signals 'rev.*' --out pendulum.csv
  multibody sweep examples/pendulum.dyad --param body.m=0.5:0.5:2 --param damper.d=0,0.1 --out sweep.csv
  multibody linearize examples/controlled_pendulum.dyad --at steady --bode bode.png
  multibody live examples/double_pendulum.dyad -o live.html
  multibody check examples/free_body.dyad
  multibody describe Body";

#[derive(Parser)]
#[command(name = "multibody", version, about = "Simulate multibody models written in Dyad", after_help = AFTER_HELP)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate a model and write its signals to a CSV file
    Run(RunArgs),
    /// Assemble a model without simulating: degrees of freedom, states, orientation owners, warnings
    Check(Selection),
    /// Show a library component: its parameters, connectors and variables
    Describe {
        /// The component kind, e.g. Body, Revolute or RotationalComponents.Damper
        kind: String,
    },
    /// List every library component with a line about it
    List,
    /// Run a model over a grid of parameter values, on every core, into one table
    Sweep(SweepArgs),
    /// The linear model around an operating point: A, B, C, D with names, poles, a Bode plot
    Linearize(LinearizeArgs),
    /// Write a page that runs the model itself: change a parameter, a start value or the stop time in
    /// its panel and the motion and plots follow (offline; the engine is embedded as WebAssembly)
    Live(LiveArgs),
    /// Write a URDF robot as a Dyad model file (components named as its links and joints)
    Import(ImportArgs),
    /// Export the model as an FMU (FMI 2.0 or 3.0, model exchange and co-simulation) for any FMI tool
    Fmu(FmuArgs),
}

/// Which model files, and which analysis or component in them.
#[derive(Args, Clone)]
pub struct Selection {
    /// Model files (.dyad), or folders to read every .dyad file from (not their subfolders)
    #[arg(required = true, value_name = "FILE")]
    pub files: Vec<PathBuf>,
    /// The analysis to run (needed when the files have several)
    #[arg(long, value_name = "NAME", conflicts_with = "model")]
    pub analysis: Option<String>,
    /// Simulate this component with default options instead of an analysis
    #[arg(long, value_name = "NAME")]
    pub model: Option<String>,
}

/// The simulation options the command line may set over the analysis's.
#[derive(Args, Clone)]
pub struct OptionArgs {
    /// Stop time [s] (default: the analysis's, or 1 s with --model)
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    pub stop: Option<f64>,
    /// Output interval [s]; 0 saves every integrator step
    #[arg(long, value_name = "DT", allow_hyphen_values = true)]
    pub saveat: Option<f64>,
    /// Absolute tolerance of the integrator
    #[arg(long, value_name = "X", allow_hyphen_values = true)]
    pub abstol: Option<f64>,
    /// Relative tolerance of the integrator
    #[arg(long, value_name = "X", allow_hyphen_values = true)]
    pub reltol: Option<f64>,
    /// Integration method: auto (adaptive Dormand-Prince), Rodas4 (implicit, for stiff models), ROS34PW2
    /// (implicit, keeping its Jacobian over many steps: for stiff models with many states), or RK4
    /// (fixed step, the --saveat or the analysis's saveat/dtmax) (default: the analysis's alg)
    #[arg(long, value_name = "NAME")]
    pub alg: Option<String>,
}

impl OptionArgs {
    pub fn overrides(&self) -> multibody_dyad::OptionOverrides {
        multibody_dyad::OptionOverrides {
            stop: self.stop,
            saveat: self.saveat,
            abstol: self.abstol,
            reltol: self.reltol,
            alg: self.alg.clone(),
        }
    }
}

/// Parameters and start values the command line sets over the files'.
#[derive(Args, Clone)]
pub struct ValueArgs {
    /// Set a parameter of the model, by its path: --param length=2 --param body.m=1.5
    #[arg(long = "param", value_name = "NAME=VALUE", allow_hyphen_values = true)]
    pub params: Vec<String>,
    /// Set a start value, by its path: --initial rev.phi=0.3
    #[arg(long = "initial", value_name = "NAME=VALUE", allow_hyphen_values = true)]
    pub initials: Vec<String>,
}

#[derive(Args)]
pub struct RunArgs {
    #[command(flatten)]
    pub selection: Selection,
    #[command(flatten)]
    pub options: OptionArgs,
    #[command(flatten)]
    pub values: ValueArgs,
    /// Drive an input of the model (a top-level RealInput) from a CSV table of time and value, linearly
    /// interpolated; the table must cover the run: --input tau=torque.csv
    #[arg(long = "input", value_name = "NAME=FILE.csv")]
    pub inputs: Vec<String>,
    /// Output file: CSV, or Parquet when named .parquet (default: NAME.csv in the current folder)
    #[arg(long, short, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Signals to write, as glob patterns such as 'body.r_0[*]' or '*.phi' (default: all; the
    /// plot and the page's plots default to the joint coordinates)
    #[arg(long, value_name = "PATTERN", num_args = 1..)]
    pub signals: Vec<String>,
    /// Also write a 3-D animation: one self-contained HTML page that works offline
    #[arg(long, value_name = "FILE.html")]
    pub animate: Option<PathBuf>,
    /// Also plot the signals against time (.png or .svg)
    #[arg(long, value_name = "FILE.png")]
    pub plot: Option<PathBuf>,
}

#[derive(Args)]
pub struct SweepArgs {
    #[command(flatten)]
    pub selection: Selection,
    #[command(flatten)]
    pub options: OptionArgs,
    /// Values of a parameter, by its path: a list (m=1,2,5), a range START:STEP:STOP (m=1:0.5:3), or one
    /// value; the sweep runs every combination of the values given
    #[arg(long = "param", value_name = "NAME=VALUES", allow_hyphen_values = true, required = true)]
    pub params: Vec<String>,
    /// Values of a start value, by its path, written like --param: --initial rev.phi=0:0.1:0.5
    #[arg(long = "initial", value_name = "NAME=VALUES", allow_hyphen_values = true)]
    pub initials: Vec<String>,
    /// Output file (CSV, or Parquet when named .parquet): one long table, a row per sample of each
    /// run, with the run number and its parameters as the first columns (default: NAME_sweep.csv)
    #[arg(long, short, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Signals to write, as glob patterns (default: the states)
    #[arg(long, value_name = "PATTERN", num_args = 1..)]
    pub signals: Vec<String>,
    /// How many runs at once (default: one per core)
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = parse_jobs)]
    pub jobs: Option<usize>,
}

#[derive(Args, Clone)]
pub struct LinearizeArgs {
    #[command(flatten)]
    pub selection: Selection,
    #[command(flatten)]
    pub options: OptionArgs,
    #[command(flatten)]
    pub values: ValueArgs,
    /// The inputs of B and D, comma-separated (default: the analysis's, else all the model's inputs)
    #[arg(long, value_name = "NAMES", value_delimiter = ',')]
    pub inputs: Option<Vec<String>>,
    /// The outputs of C and D: any variables of the results, comma-separated (default: the
    /// analysis's, else the model's outputs)
    #[arg(long, value_name = "NAMES", value_delimiter = ',')]
    pub outputs: Option<Vec<String>>,
    /// Where: `start`, `steady` (a steady state found from the start by Newton's method) or `t=T`
    /// (after simulating to T)
    #[arg(long, value_name = "WHERE", default_value = "start")]
    pub at: String,
    /// How: `auto` (exact derivatives where the model allows, with central differences beside
    /// them as a check), `exact` or `differences`
    #[arg(long, value_name = "HOW", default_value = "auto")]
    pub derivatives: String,
    /// Output file: the linear model as JSON (default: NAME.json in the current folder)
    #[arg(long, short, value_name = "FILE.json")]
    pub out: Option<PathBuf>,
    /// Also write a Bode plot of every input-output pair (.png or .svg)
    #[arg(long, value_name = "FILE.png")]
    pub bode: Option<PathBuf>,
}

#[derive(Args)]
pub struct LiveArgs {
    #[command(flatten)]
    pub selection: Selection,
    #[command(flatten)]
    pub values: ValueArgs,
    /// Stop time [s] the page starts with (default: the analysis's, or 1 s with --model)
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    pub stop: Option<f64>,
    /// Signals plotted beside the view, as glob patterns (default: the joint coordinates)
    #[arg(long, value_name = "PATTERN", num_args = 1..)]
    pub signals: Vec<String>,
    /// The page to write (.html)
    #[arg(long, short, value_name = "FILE.html")]
    pub out: PathBuf,
    /// The engine compiled to WebAssembly (default: the one scripts/build-web.sh builds, or
    /// $MULTIBODY_WASM)
    #[arg(long, value_name = "FILE.wasm")]
    pub wasm: Option<PathBuf>,
}

#[derive(Args)]
pub struct ImportArgs {
    /// The URDF file
    #[arg(value_name = "FILE.urdf")]
    pub file: PathBuf,
    /// The model file to write (default: the URDF file's name with .dyad, in the current folder)
    #[arg(long, short, value_name = "FILE.dyad")]
    pub out: Option<PathBuf>,
    /// The root link moves freely (a floating base) instead of being fixed to the world
    #[arg(long)]
    pub floating: bool,
    /// A folder that holds ROS packages (or is one), for `package://NAME/...` meshes; repeatable.
    /// Folders above the URDF file and ROS_PACKAGE_PATH are searched too
    #[arg(long, value_name = "DIR")]
    pub package_dir: Vec<PathBuf>,
    /// Leave mesh visuals out (instead of stopping at a mesh that is not found)
    #[arg(long)]
    pub no_meshes: bool,
}

#[derive(Args)]
pub struct FmuArgs {
    #[command(flatten)]
    pub selection: Selection,
    /// FMI version: 2 or 3 (default: the FMUAnalysis's `version`, else 2)
    #[arg(long, value_name = "VERSION")]
    pub fmi: Option<String>,
    /// Which interfaces: me (model exchange), cs (co-simulation) or both (default: the FMUAnalysis's
    /// `fmu_type`, else both)
    #[arg(long, value_name = "KIND")]
    pub kind: Option<String>,
    /// Expose this variable as an output too (the model's RealOutputs always are)
    #[arg(long = "output", value_name = "NAME")]
    pub outputs: Vec<String>,
    /// The FMU to write (default: NAME.fmu in the current folder)
    #[arg(long, short, value_name = "FILE.fmu")]
    pub out: Option<PathBuf>,
    /// The runtime library the FMU carries (default: the one cargo built beside this command, or
    /// $MULTIBODY_FMU_RUNTIME)
    #[arg(long, value_name = "FILE")]
    pub runtime: Option<PathBuf>,
}

fn main() -> ExitCode {
    ignore_file_size_signal();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run(args) => run::run(&args),
        Command::Check(selection) => check::check(&selection),
        Command::Describe { kind } => catalog::describe(&kind),
        Command::List => catalog::list(),
        Command::Sweep(args) => sweep::sweep(&args),
        Command::Linearize(args) => linearize::linearize(&args),
        Command::Live(args) => live::live(&args),
        Command::Fmu(args) => fmu::fmu(&args),
        Command::Import(args) => import::import(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => failure.report(),
    }
}

/// A write past the file size limit (`ulimit -f`) sends SIGXFSZ, which
/// ended the command with no message and left its temporary file behind.
/// Ignored, the write fails with EFBIG instead: the command says which
/// file hit the limit and removes the temporary file.
fn ignore_file_size_signal() {
    #[cfg(unix)]
    // SAFETY: sets the disposition of one signal to "ignore", before any
    // thread of ours starts; no handler runs.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
}

/// `--jobs N`: a whole number of runs at once, 1 or more (clap's own
/// message for `-1` suggested `-- -1`).
fn parse_jobs(text: &str) -> Result<usize, String> {
    match text.trim().parse::<i64>() {
        Ok(n) if n >= 1 => Ok(n as usize),
        Ok(n) => Err(format!("{n} runs at once cannot be: give 1 or more (the default is one per core)")),
        Err(_) => Err(format!("`{text}` is not a whole number of runs: give 1 or more, e.g. --jobs 4")),
    }
}
