//! Stage one of the command line: clap definitions, parsed into plain data. Nothing here reads a
//! file; `--help` texts are the reference for every flag.

use clap::{Args, Parser, Subcommand};
use std::ffi::OsString;
use std::path::PathBuf;

/// Possibilistic place recognition over annotated topological maps.
///
/// With no --map/--rules, commands use the bundled office example of paper 003
/// (maps/office.map, rules/office.lpl).
#[derive(Debug, Parser)]
#[command(name = "lplace", version, about, long_about = None, propagate_version = true)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Parse and check map (.map) and rule (.lpl) files; print every problem found.
    ///
    /// Rule files are checked against the map given among the files, else --map, else the
    /// bundled office map. Exit 0 when clean, 2 with errors.
    Check(CheckArgs),
    /// Print the closed-form degree function of each place (paper 003 eq. (6) style).
    Explain(ExplainArgs),
    /// Evaluate a percept stream (or one frame) and print one decision per frame.
    ///
    /// With no STREAM and no --frame, evaluates the bundled office recording
    /// (recordings/office.jsonl, made by `lplace simulate`). Exit 0 when every record was
    /// used, 3 when some were rejected (each reported on stderr as STREAM:LINE: reason),
    /// 1 when the stream cannot be read, 2 for bad arguments, map or rules.
    Eval(EvalArgs),
    /// Simulate a robot walking the map and print its percept stream with ground truth.
    ///
    /// Deterministic: the same arguments give byte-identical output.
    Simulate(SimulateArgs),
    /// Turn a raw sensor log (CARMEN) into a percept stream (JSON lines) on stdout.
    ///
    /// One frame per laser scan; with --map, each frame carries its ground-truth place. Exit 0,
    /// or 3 when some log lines were malformed (each reported on stderr with its line number).
    Extract(ExtractArgs),
    /// Run the Fuzzy Position Grid over a landmark percept stream; write the trajectory (TUM)
    /// and print ATE, time to first fix and kidnap recovery against the stream's truth.
    ///
    /// Exit 0, or 3 when some stream lines were malformed (each reported on stderr).
    Grid(GridArgs),
    /// Run several localizers (fpg, pf:N, rmcl) over the same landmark stream and print one
    /// table: ATE RMSE / median / max, time to first fix, kidnap recovery, time per step.
    ///
    /// ATE is scored from each method's own first fix, over the common window (from the latest
    /// first fix of the methods in the table on: the same frames for every row) and over all
    /// frames. Time per step is wall time (the method's whole run over the frames, divided by the
    /// frames), so it depends on the machine and its load. With --sweep, also paper 001's
    /// noisy- and sparse-data runs (seeded). Exit 0, 3 when some stream lines were malformed
    /// (each reported on stderr), 2 for a bad method, flag, map or configuration, 1 when a
    /// file cannot be read or written.
    ///
    /// Example: lplace compare --from-dir ../shared/data/mrclam-dataset7 --robot 1
    /// --kidnap-at mid --tum-dir out --sweep both --svg sweep.svg
    Compare(CompareArgs),
    /// Cooperative object localization (paper 002) on MRCLAM: one robot is the object the others
    /// see; fuse their object grids and compare with each robot's own estimate and with averages.
    ///
    /// Prints, per object robot and overall, mean / median errors (m) of the observers' self
    /// localization, their own object estimates, the best of them, the plain and
    /// reliability-weighted averages and the fused estimate. Exit 0, 2 for bad flags or files,
    /// 3 when data lines were malformed (each reported on stderr as FILE:LINE) or readings rejected.
    Fuse(FuseArgs),
    /// Fit each place's expected percept values from a run with ground truth (the frames'
    /// `truth.place`, or --labels) and write them into the map, changing nothing else.
    ///
    /// Prints per place the scans used and the spread of its readings on stderr, and warns on
    /// places with few scans. With --fit first-visits, fits on each place's first visit,
    /// prints how the written map does on the later visits and warns on places most of whose
    /// later readings lie outside the fitted ranges. The stream is read as `eval` reads
    /// it. Exit 0, 3 when some records were rejected (each reported on stderr as
    /// STREAM:LINE: reason), 2 for bad map, rules or labels, 1 when a file cannot be read or
    /// written.
    Survey(super::survey::SurveyArgs),
    /// Draw a CARMEN log's laser scans at the log's poses (SVG), with a metre grid and the
    /// map's place outlines over them: the picture to read a floor plan off.
    ///
    /// Beam end points are counted in cells (--cell) and the cells hit often enough drawn
    /// (--min-hits); the grid is labelled in the log's frame, the coordinates a map's extents
    /// are written in. In a corrected log the poses are the corrected ones and the scans draw
    /// the walls. Exit 0, 3 when some log lines were malformed (each reported on stderr with
    /// its line number; the picture is drawn from the others), 2 for bad flags, map or output
    /// path, 1 when a file cannot be read or written.
    ///
    /// Example: lplace draw run.log --map my.map -o scans.svg
    Draw(super::draw::DrawArgs),
    /// Evaluate percept streams as `eval` does and write one self-contained HTML page about
    /// them: summary, confusion matrix, place Π/N over time, trajectory, grid beliefs.
    ///
    /// Each RUN is a percept stream (the input of `lplace eval`), evaluated with the --map,
    /// --rules and --tracker given once for all runs; the page has one section per run and,
    /// with several, a table comparing them. It loads nothing from anywhere (inline SVG, no
    /// script). Exit 0, 3 when some records were rejected (each reported on stderr as
    /// STREAM:LINE: reason; the page is written), 2 for bad arguments, map, rules or tracker,
    /// 1 when a file cannot be read or written.
    ///
    /// Example: lplace report intel.jsonl --map maps/intel.map --rules rules/intel.lpl
    /// --tracker config/intel-tracker.ron -o intel.html
    Report(super::report::ReportArgs),
    /// Print a shell completion script on stdout, e.g.
    /// `lplace completions bash > ~/.local/share/bash-completion/completions/lplace`.
    Completions(CompletionsArgs),
    /// Print the man page (roff) on stdout, e.g. `lplace man > lplace.1; man ./lplace.1`.
    Man,
}

/// `lplace completions`.
#[derive(Debug, Args)]
pub struct CompletionsArgs {
    /// The shell.
    #[arg(value_enum)]
    pub shell: clap_complete::Shell,
}

/// The map and rules to load.
#[derive(Debug, Args, Clone)]
pub struct ModelArgs {
    /// Map file (.map). Default: the bundled office map.
    #[arg(long, value_name = "MAP")]
    pub map: Option<PathBuf>,
    /// Rule file (.lpl). Default: the bundled office rules.
    #[arg(long, value_name = "RULES")]
    pub rules: Option<PathBuf>,
}

/// `lplace check`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// Files to check: .map and .lpl.
    #[arg(required = true, value_name = "FILE")]
    pub files: Vec<PathBuf>,
    /// Map to check rule files against when no .map is among FILES.
    #[arg(long, value_name = "MAP")]
    pub map: Option<PathBuf>,
}

/// `lplace explain`.
#[derive(Debug, Args)]
pub struct ExplainArgs {
    /// The map and rules.
    #[command(flatten)]
    pub model: ModelArgs,
    /// Only this place.
    #[arg(long, value_name = "PLACE")]
    pub place: Option<String>,
    /// Also print each formula in the paper's dissimilarity form (δ = 1 − degree).
    #[arg(long)]
    pub dissimilarity: bool,
    /// Show a derived predicate (e.g. beacon_signature) on its own, per place context, instead
    /// of the places.
    #[arg(long, value_name = "PREDICATE")]
    pub atom: Option<String>,
    /// Show how Π and N of a set of places are computed (names of places, rooms, regions or
    /// kinds, combined with `!`, `&`, `(+)`), instead of the places.
    #[arg(long, value_name = "QUERY")]
    pub query: Option<String>,
}

/// What goes to stdout: the same four words on every command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// JSON (for a stream of records: one object per line, as jsonl).
    Json,
    /// One JSON object per line.
    Jsonl,
    /// A human-readable table.
    Table,
    /// Comma-separated values with a header.
    Csv,
}

/// How to print the summary of a stream.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SummaryFormat {
    /// Lines for a person.
    Text,
    /// One JSON object.
    Json,
    /// No summary.
    None,
}

/// The wire form of a stream.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum StreamForm {
    /// JSON Lines.
    Jsonl,
    /// CSV with a header.
    Csv,
}

/// `lplace eval`.
#[derive(Debug, Args)]
pub struct EvalArgs {
    /// The map and rules.
    #[command(flatten)]
    pub model: ModelArgs,
    /// Percept streams: JSON Lines (.jsonl) or CSV (.csv); `-` reads stdin; a folder stands
    /// for its .jsonl and .csv files. Default: the bundled office recording. With more than one
    /// stream (or a folder), prints one summary row per stream and a total instead of decisions.
    #[arg(value_name = "STREAM", conflicts_with = "frame")]
    pub stream: Vec<PathBuf>,
    /// One frame as JSON, e.g. '{"percepts":[{"name":"sonar_wall","args":["North"],"degree":0.8}]}'.
    #[arg(long, value_name = "JSON")]
    pub frame: Option<String>,
    /// Also list the rule instances that fired and how strongly (--frame only).
    #[arg(long)]
    pub trace: bool,
    /// Output format: one JSON object per frame (json, jsonl), csv, or an aligned table.
    /// Default: jsonl for a stream (pretty json for --frame); table for several streams.
    #[arg(long, value_enum)]
    pub format: Option<Format>,
    /// Write the decisions (or the batch table) to this file instead of stdout.
    #[arg(long, short, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Stream form; default from the extension (.csv is CSV, else JSON Lines).
    #[arg(long, value_enum, value_name = "FORM")]
    pub input: Option<StreamForm>,
    /// How times are read: `monotone` (default) rejects a time earlier than the previous
    /// record's — each time is judged against both neighbours, so one corrupt time is the one
    /// record rejected; `restart` reads concatenated logs, accepting a clock that starts again
    /// (each restart reported as a note on stderr).
    #[arg(long, value_enum, value_name = "ORDER", default_value_t = TimeOrder::Monotone)]
    pub time: TimeOrder,
    /// Summary after the stream, on stderr.
    #[arg(long, value_enum, default_value_t = SummaryFormat::Text)]
    pub summary: SummaryFormat,
    /// Print no decisions; print the summary on stdout instead of stderr.
    #[arg(long)]
    pub only_summary: bool,
    /// Add every place's Π and N to each decision.
    #[arg(long)]
    pub degrees: bool,
    /// Also report Π and N of a set of places: place, room, region or kind names combined with
    /// `!`, `&` and `(+)`, e.g. 'EastWing (+) doorway'. May be repeated.
    #[arg(long, value_name = "QUERY")]
    pub query: Vec<String>,
    /// Decide each frame on its own evidence, without tracking along the map graph.
    #[arg(long)]
    pub no_track: bool,
    /// Tracker parameters: a RON file such as config/intel-tracker.ron (which tracks on a
    /// metric grid); fields left out take the defaults given in the README. Default: the rule
    /// file's `tracker { … }` block, else the built-in defaults.
    #[arg(long, value_name = "RON")]
    pub tracker: Option<PathBuf>,
    /// Draw the run (per place Π and N over frames, chosen place, truth) as SVG.
    #[arg(long, value_name = "FILE")]
    pub svg: Option<PathBuf>,
    /// Draw the truth poses over the map's places, one dot per frame coloured by the decision
    /// (right, wrong, disoriented), as SVG. Frames without a truth pose are left out; one point
    /// per frame is kept until the end.
    #[arg(long, value_name = "FILE")]
    pub trajectory_svg: Option<PathBuf>,
    /// Ground truth from a CSV `t,place` (header optional; an empty place is "between
    /// places") instead of the records' own: each frame takes the label nearest its time,
    /// within 0.5 s, and a frame with none has no truth. Every place named must be the map's.
    #[arg(long, value_name = "CSV", conflicts_with = "frame")]
    pub labels: Option<PathBuf>,
    /// Old spelling of --svg.
    #[arg(long, value_name = "SVG", hide = true, conflicts_with = "svg")]
    pub plot: Option<PathBuf>,
    /// Old spelling of --trajectory-svg.
    #[arg(
        long,
        value_name = "SVG",
        hide = true,
        conflicts_with = "trajectory_svg"
    )]
    pub trajectory: Option<PathBuf>,
}

impl EvalArgs {
    /// The run display's file (`--svg`, or the old `--plot`).
    pub fn svg(&self) -> Option<&std::path::Path> {
        self.svg.as_deref().or(self.plot.as_deref())
    }

    /// The trajectory picture's file (`--trajectory-svg`, or the old `--trajectory`).
    pub fn trajectory_svg(&self) -> Option<&std::path::Path> {
        self.trajectory_svg
            .as_deref()
            .or(self.trajectory.as_deref())
    }
}

/// `lplace simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// The map and rules (the rules say which percepts to emit).
    #[command(flatten)]
    pub model: ModelArgs,
    /// Frames to emit.
    #[arg(long, default_value_t = 2000)]
    pub steps: u64,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Metres per frame.
    #[arg(long, default_value_t = 0.3)]
    pub speed: f64,
    /// Probability that a percept is missing.
    #[arg(long, default_value_t = 0.1)]
    pub p_missing: f64,
    /// Probability that a sonar wall is occluded.
    #[arg(long, default_value_t = 0.1)]
    pub p_occlude: f64,
    /// Probability that a frame's measured values are another place's (mislabelled beacon).
    #[arg(long, default_value_t = 0.04)]
    pub p_mislabel: f64,
    /// Probability of a spurious corner in a frame.
    #[arg(long, default_value_t = 0.04)]
    pub p_spurious: f64,
    /// Standard deviation of angular values, degrees.
    #[arg(long, default_value_t = 5.0)]
    pub angle_noise: f64,
    /// Relative standard deviation of other values.
    #[arg(long, default_value_t = 0.05)]
    pub range_noise: f64,
    /// Relative standard deviation of the odometry.
    #[arg(long, default_value_t = 0.05)]
    pub odometry_noise: f64,
    /// Kidnap the robot (teleport to a random other place) at these frames (0-based).
    #[arg(long, value_name = "K", value_delimiter = ',')]
    pub kidnap_at: Vec<u64>,
    /// Emit the robot's heading (as a compass would), with this standard deviation in degrees.
    /// Without it frames carry no heading.
    #[arg(long, value_name = "DEG")]
    pub heading_noise: Option<f64>,
    /// Output form.
    #[arg(long, value_enum, default_value_t = StreamForm::Jsonl)]
    pub format: StreamForm,
    /// Write to this file instead of stdout.
    #[arg(long, short, value_name = "FILE")]
    pub output: Option<PathBuf>,
}

/// Raw log formats `extract` reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum LogFormat {
    /// CARMEN text log (FLASER, ODOM, PARAM), e.g. the Radish "corrected" logs.
    Carmen,
    /// UTIAS MRCLAM data set directory (LOG is the directory; needs --robot).
    Mrclam,
    /// ROS 2 bag, MCAP storage: a `.mcap` file or a bag directory (metadata.yaml); LaserScan +
    /// Odometry (+ a PoseStamped truth topic) as for CARMEN. The sqlite3 storage is not read.
    Rosbag2,
}

/// `lplace extract`.
#[derive(Debug, Clone, Args)]
pub struct ExtractArgs {
    /// Format of the raw log.
    #[arg(long, value_enum, default_value_t = LogFormat::Carmen)]
    pub from: LogFormat,
    /// The raw log (CARMEN, plain or gzipped), or the data set directory (MRCLAM).
    #[arg(value_name = "LOG")]
    pub log: PathBuf,
    /// MRCLAM robot number (1–5); required with --from mrclam.
    #[arg(long, value_name = "N")]
    pub robot: Option<u32>,
    /// Map (.map) whose place extents give each frame's ground-truth place; its `axis D;`
    /// statement, if any, replaces the config's `compass.axis_deg`. With it, the quality line
    /// on stderr also scores the heading against the log's true poses.
    #[arg(long, value_name = "MAP")]
    pub map: Option<PathBuf>,
    /// Extractor parameters (RON; see `percept::ExtractConfig`). Default: the travelling
    /// settings (`ExtractConfig::travelling`: compass on, eight directions, the initial heading
    /// from the first scan's odometry), which need no file per building.
    #[arg(long, value_name = "CONFIG")]
    pub config: Option<PathBuf>,
    /// rosbag2: the LaserScan topic (default: the bag's one LaserScan topic).
    #[arg(long, value_name = "TOPIC")]
    pub scan_topic: Option<String>,
    /// rosbag2: the Odometry topic (default: the bag's one Odometry topic).
    #[arg(long, value_name = "TOPIC")]
    pub odom_topic: Option<String>,
    /// rosbag2: the ground-truth pose topic, PoseStamped or Odometry (default: the bag's one
    /// PoseStamped topic, if any).
    #[arg(long, value_name = "TOPIC")]
    pub truth_topic: Option<String>,
    /// rosbag2: forward offset of the scanner from the robot's origin, metres (CARMEN logs
    /// carry it as PARAM robot_frontlaser_offset).
    #[arg(long, value_name = "M", default_value_t = 0.0)]
    pub laser_offset: f64,
}

/// `lplace fuse`.
#[derive(Debug, Clone, Args)]
pub struct FuseArgs {
    /// MRCLAM dataset directory (Barcodes.dat, Landmark_Groundtruth.dat, RobotN_*.dat).
    #[arg(long, value_name = "DIR")]
    pub from_dir: PathBuf,
    /// Robot (1–5) taken as the object the others see; repeat for several. Default: every
    /// robot in turn (same as --all).
    #[arg(long, value_name = "N", conflicts_with = "all")]
    pub object: Vec<u32>,
    /// Every robot in turn as the object (the default).
    #[arg(long)]
    pub all: bool,
    /// Self-localization grid parameters (RON, see `grid::GridConfig`), e.g.
    /// config/grid-mrclam.ron. Default: the built-in defaults.
    #[arg(long, value_name = "GRID.ron")]
    pub config: Option<PathBuf>,
    /// Object-grid, fusion and event parameters (RON, see `coop::CoopConfig`), e.g.
    /// config/coop-mrclam.ron. Default: the built-in defaults.
    #[arg(long, value_name = "COOP.ron")]
    pub coop_config: Option<PathBuf>,
    /// Only the first SECONDS of the recording.
    #[arg(long, value_name = "SECONDS")]
    pub until: Option<f64>,
    /// Output: a markdown table, one JSON object (with --events: every event too), or CSV.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
    /// With --format json: include every scored event.
    #[arg(long)]
    pub events: bool,
}

/// Where the landmark frames come from — a percept stream or MRCLAM files — and the map that
/// names their landmarks. Shared by `grid` and `compare`, which read their input alike.
#[derive(Debug, Clone, Args)]
pub struct FrameInput {
    /// Map (.map) whose landmarks (with ids) the stream's readings name. Default: the bundled
    /// maps/mrclam.map.
    #[arg(long, value_name = "MAP")]
    pub map: Option<PathBuf>,
    /// Percept stream (JSON lines; CSV when it ends in .csv) with landmark_range/
    /// landmark_bearing percepts; `-` reads stdin. Not needed with --from-dir.
    #[arg(value_name = "STREAM", required_unless_present = "from_dir")]
    pub stream: Option<PathBuf>,
    /// Read MRCLAM robot files from this directory instead of a stream (needs --robot).
    #[arg(
        long,
        value_name = "DIR",
        requires = "robot",
        conflicts_with = "stream"
    )]
    pub from_dir: Option<PathBuf>,
    /// MRCLAM robot number (1–5), with --from-dir.
    #[arg(long, value_name = "N")]
    pub robot: Option<u32>,
    /// Ignore readings whose degree (reliability) is below this.
    #[arg(long, value_name = "DEGREE", default_value_t = 0.0)]
    pub min_degree: f64,
    /// How times are read: `monotone` (default) rejects a time earlier than the previous
    /// record's — each time is judged against both neighbours, so one corrupt time is the one
    /// record rejected; `restart` reads concatenated logs, accepting a clock that starts again
    /// (each restart reported as a note on stderr).
    #[arg(long, value_enum, value_name = "ORDER", default_value_t = TimeOrder::Monotone)]
    pub time: TimeOrder,
}

/// `--time`: how a stream's times are read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum TimeOrder {
    /// Time never goes back.
    #[default]
    Monotone,
    /// Concatenated logs: the clock may start again.
    Restart,
}

impl From<TimeOrder> for crate::io::stream::TimePolicy {
    fn from(t: TimeOrder) -> Self {
        match t {
            TimeOrder::Monotone => Self::Monotone,
            TimeOrder::Restart => Self::Restart,
        }
    }
}

/// The optional injected kidnap, shared by `grid` and `compare`.
#[derive(Debug, Clone, Args)]
pub struct KidnapArgs {
    /// Also run with a kidnap injected this many seconds after the first frame (or `mid`: at
    /// the middle frame) and report the recovery time.
    #[arg(long, value_name = "SECONDS|mid")]
    pub kidnap_at: Option<String>,
    /// The kidnap: forward and left metres and degrees turned, added to one odometry increment,
    /// as one comma-separated value, e.g. 0,1,45. Default: 0,2,85.94 (1.5 rad).
    // The default string is the shortest form of 1.5 rad in degrees, so it parses back to the
    // very same number as before.
    #[arg(
        long,
        value_name = "DX,DY,DTHETA",
        value_delimiter = ',',
        num_args = 1,
        allow_hyphen_values = true,
        default_value = "0,2,85.94366926962348",
        hide_default_value = true
    )]
    pub kidnap_by: Vec<f64>,
}

/// `lplace grid`.
#[derive(Debug, Clone, Args)]
pub struct GridArgs {
    /// The input.
    #[command(flatten)]
    pub input: FrameInput,
    /// Grid parameters (RON, see `grid::GridConfig`), e.g. config/grid-mrclam.ron. Default:
    /// the built-in defaults.
    #[arg(long, value_name = "CONFIG")]
    pub config: Option<PathBuf>,
    /// Cell size in metres (overrides the configuration's).
    #[arg(long, value_name = "METRES")]
    pub cell: Option<f32>,
    /// Write the estimated trajectory here (TUM: `t x y z qx qy qz qw`); with --kidnap-at,
    /// the kidnapped run's.
    #[arg(long, value_name = "FILE")]
    pub tum: Option<PathBuf>,
    /// Write the frames' truth poses here, in the same TUM format (for evo_ape against --tum).
    #[arg(long, value_name = "FILE")]
    pub truth_tum: Option<PathBuf>,
    /// Write a few grid frames as SVG into this directory (created if needed).
    #[arg(long, value_name = "DIR")]
    pub svg: Option<PathBuf>,
    /// The kidnap.
    #[command(flatten)]
    pub kidnap: KidnapArgs,
    /// Output format of the scores: text (table) or one JSON object (json, jsonl).
    #[arg(long, value_enum, value_name = "FORMAT")]
    pub format: Option<Format>,
    /// Old spelling of --format json.
    #[arg(long, hide = true, conflicts_with = "format")]
    pub json: bool,
}

/// Which of paper 001's sweeps `--sweep` runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SweepKind {
    /// Added range/bearing noise.
    Noise,
    /// Fraction of readings kept.
    Sparsity,
    /// Both.
    Both,
}

/// `lplace compare`.
#[derive(Debug, Clone, Args)]
pub struct CompareArgs {
    /// The input.
    #[command(flatten)]
    pub input: FrameInput,
    /// Methods to run, comma-separated: `fpg` (Fuzzy Position Grid), `pf:N` (particle filter,
    /// N particles; `pf` alone: --pf-config's count), `rmcl` (Fuzzy R-MCL).
    #[arg(
        long,
        value_name = "LIST",
        value_delimiter = ',',
        default_value = "fpg,pf:500,pf:2000,rmcl"
    )]
    pub methods: Vec<super::compare::MethodSpec>,
    /// Grid parameters (RON, see `grid::GridConfig`); also the cell size and bounds of R-MCL's
    /// grid. Default: the bundled config/grid-mrclam.ron.
    #[arg(long, value_name = "CONFIG")]
    pub config: Option<PathBuf>,
    /// Particle filter parameters (RON). Default: the bundled config/pf.ron.
    #[arg(long, value_name = "CONFIG")]
    pub pf_config: Option<PathBuf>,
    /// Fuzzy R-MCL parameters (RON). Default: the bundled config/rmcl.ron.
    #[arg(long, value_name = "CONFIG")]
    pub rmcl_config: Option<PathBuf>,
    /// Seed of the sampling methods and of the sweeps' perturbations (same seed, same output).
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub seed: u64,
    /// Tracking: start every method from the first frame's truth pose instead of total
    /// ignorance (the grid in that one cell with its heading, the particles all on it); fpg and
    /// pf only.
    #[arg(long)]
    pub start_at_truth: bool,
    /// Write each method's trajectory (unperturbed run; with --kidnap-at, the kidnapped run)
    /// into this directory as METHOD.tum (`pf:500` → pf-500.tum); the directory is created if
    /// needed.
    #[arg(long, value_name = "DIR")]
    pub tum_dir: Option<PathBuf>,
    /// The kidnap.
    #[command(flatten)]
    pub kidnap: KidnapArgs,
    /// Output format: markdown tables (table), one JSON object (json, jsonl) or one CSV row
    /// per method and run (csv).
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
    /// Also run paper 001's sweeps: added Gaussian noise (σ range / σ bearing: 0/0, 0.1 m/2°,
    /// 0.25 m/5°, 0.5 m/10°, 1 m/20°) and readings kept (100, 50, 25, 10 %), all methods on
    /// the same perturbed frames.
    #[arg(long, value_enum, value_name = "WHICH")]
    pub sweep: Option<SweepKind>,
    /// Plot the sweeps' ATE RMSE per method as SVG into this file (needs --sweep).
    #[arg(long, value_name = "FILE", requires = "sweep")]
    pub svg: Option<PathBuf>,
}

/// A flag value that parsed but makes no sense.
#[derive(Debug, thiserror::Error)]
pub enum ArgError {
    /// A folder given as a stream holds no .jsonl or .csv file.
    #[error("folder `{0}` holds no .jsonl or .csv stream")]
    EmptyFolder(String),
    /// A flag about one stream's frames, given with several streams.
    #[error("{0} is about one stream's frames; not with several streams")]
    NotInBatch(&'static str),
    /// `--place` names no place of the map.
    #[error("no place `{name}` in the map (places: {known})")]
    UnknownPlace {
        /// What was asked.
        name: String,
        /// The places there are.
        known: String,
    },
    /// The frame given with `--frame` is not usable (the stream reader's reason).
    #[error("--frame: {0}")]
    Frame(crate::io::stream::Rejection),
    /// `--frame` was given an empty or blank record.
    #[error("--frame: no record (an empty or blank argument)")]
    EmptyFrame,
    /// A numeric flag outside its range.
    #[error("--{flag}: {value} is out of range ({range})")]
    OutOfRange {
        /// The flag.
        flag: &'static str,
        /// Its value.
        value: f64,
        /// The allowed range.
        range: &'static str,
    },
    /// A `--query` that names no set of places.
    #[error("--query `{query}`: {error}")]
    Query {
        /// The query as written.
        query: String,
        /// Why it names nothing.
        error: crate::engine::QueryError,
    },
    /// `--atom` names no derived predicate of the rule file.
    #[error("--atom: no derived predicate `{name}` (predicates: {known})")]
    UnknownPredicate {
        /// What was asked.
        name: String,
        /// The predicates there are.
        known: String,
    },
}

impl Cli {
    /// Notes for the old spellings used on this command line (one release of grace; see the
    /// README's "Command line" section), to print on stderr.
    pub fn deprecations(&self) -> Vec<&'static str> {
        let mut notes = Vec::new();
        if let Command::Eval(a) = &self.command {
            if a.plot.is_some() {
                notes.push("--plot is deprecated: use --svg FILE");
            }
            if a.trajectory.is_some() {
                notes.push("--trajectory is deprecated: use --trajectory-svg FILE");
            }
        }
        if let Command::Grid(a) = &self.command {
            if a.json {
                notes.push("--json is deprecated: use --format json");
            }
        }
        notes
    }
}

/// Parses the command line (stage one).
pub fn parse<I, T>(args: I) -> Result<Cli, clap::Error>
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    Cli::try_parse_from(args)
}
