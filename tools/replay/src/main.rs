//! `replay IN [--topic T] [--units U] [--config C] [--speed X | --max] [-o OUT] [--json]`:
//! publishes a recorded gyro CSV or ROS 2 bag (MCAP) to `gyrocompd` over iceoryx2, collects one
//! compensated sample per row and writes them with the columns of `gyrocomp compensate`. With no daemon serving the configured services, one is
//! started in-process in a private iceoryx2 domain (see the crate documentation).
//!
//! Without IN (the project's main job): simulates an ADIS16405-like recording at the
//! configuration's `input.rate_hz` (600 s, seed 0) into `out/replay/`, replays it through an
//! embedded daemon into `out/replay/compensated.csv`, and checks that the offline driver
//! (`gyrocomp compensate`'s pipeline) gives the same output bit for bit.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use clap::{Parser, ValueEnum};
use gyrocomp::config::{Config, RateSetting};
use gyrocomp::drive::{compensate_recording, error_chain, offline_config};
use gyrocomp::io::{CompensatedCsvWriter, InputOptions, RateUnit, Recording, write_sim_csv};
use gyrocomp::sim::{Generator, MotionKind, MotionPlan, Preset};
use replay::{Client, EmbeddedDaemon, Pacing, ReplayOptions, Summary, replay};
use tracing_subscriber::EnvFilter;

/// Which daemon serves the replay.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum DaemonChoice {
    /// A daemon already serving the configured services, else an embedded one.
    Auto,
    /// Only an already running daemon (error when none answers).
    Running,
    /// Always an embedded daemon in a private domain (retrain.mode forced to "deterministic").
    Embedded,
}

/// replay: feeds a recorded gyro CSV through gyrocompd and collects the compensated rates.
#[derive(Debug, Parser)]
#[command(name = "replay", version, about)]
struct Args {
    /// Recording: CSV with a time column `t_s`/`t`/`time` and rate columns in deg/s (or EuRoC),
    /// or an MCAP bag (sensor_msgs/msg/Imu). Without it: a simulated recording in `out/replay/`
    /// (see the module documentation).
    input: Option<PathBuf>,
    /// MCAP input: the sensor_msgs/msg/Imu topic to read (default: the only one).
    #[arg(long)]
    topic: Option<String>,
    /// Unit of the rate columns of a gyrocomp CSV: dps (default) or rads.
    #[arg(long, value_name = "dps|rads")]
    units: Option<RateUnit>,
    /// Configuration (keys as in configs/default.toml): services and domain; for an embedded
    /// daemon also its pipeline. Built-in defaults without it.
    #[arg(long)]
    config: Option<PathBuf>,
    /// Rate columns, 1 to 3, on axes x, y, z in order.
    #[arg(long = "column", value_delimiter = ',', default_value = "gx_dps")]
    columns: Vec<String>,
    /// True drift of the first rate column (simulated recordings): the summary adds the drift
    /// error beside the start-up bias-hold baseline's.
    #[arg(long)]
    truth_column: Option<String>,
    /// 0/1 column sent as the publisher's "moving" flag (flags bit 0).
    #[arg(long)]
    moving_column: Option<String>,
    /// Send at the recording's rate times X.
    #[arg(long, conflicts_with = "max")]
    speed: Option<f64>,
    /// Send as fast as the daemon answers, losslessly (the default without --speed).
    #[arg(long)]
    max: bool,
    /// Output CSV (`-` for standard output): the columns of `gyrocomp compensate`.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Print the summary as JSON on standard output.
    #[arg(long)]
    json: bool,
    /// Which daemon to use.
    #[arg(long, value_enum, default_value_t = DaemonChoice::Auto)]
    daemon: DaemonChoice,
    /// How long to look for a running daemon (auto/running), seconds.
    #[arg(long, default_value_t = 0.5)]
    find_daemon_s: f64,
    /// Longest wait for an answer before giving up, seconds.
    #[arg(long, default_value_t = 10.0)]
    timeout_s: f64,
    /// Log filter on stderr (error, warn, info, debug, trace).
    #[arg(long, default_value = "warn,iceoryx2=error", env = "GYROCOMP_LOG")]
    log: String,
}

fn main() -> ExitCode {
    let args = Args::parse();
    let filter = EnvFilter::try_new(&args.log).unwrap_or_else(|_| EnvFilter::new("warn"));
    tracing_subscriber::fmt().with_env_filter(filter).with_writer(std::io::stderr).with_target(false).init();
    match run(&args) {
        Ok(summary) if summary.dropped == 0 && summary.offline_equal != Some(false) => ExitCode::SUCCESS,
        Ok(_) => ExitCode::from(1),
        Err(e) => {
            eprintln!("replay: error: {}", error_chain(e.as_ref()));
            ExitCode::from(2)
        }
    }
}

type BoxError = Box<dyn std::error::Error + Send + Sync>;

fn seconds(name: &str, s: f64) -> Result<Duration, BoxError> {
    Duration::try_from_secs_f64(s).map_err(|_| format!("--{name}: {s} is not a duration in seconds").into())
}

/// Directory of the embedded default's files.
const DEFAULT_DIR: &str = "out/replay";
/// Length of the embedded default's recording, s.
const DEFAULT_DURATION_S: f64 = 1800.0;
/// Static fraction of the turns injected into the embedded default's first column.
const DEFAULT_STATIC_FRACTION: f64 = 0.5;
/// Rate of the simulated default recording when `input.rate_hz` is "auto", Hz.
const DEFAULT_RATE_HZ: f64 = 100.0;

/// The embedded default recording: the ADIS16405 preset at `rate_hz` (seed 0) with seeded turns
/// (`gyrocomp motion --profile turns --seed 0`) added to its first column; returns the path, the
/// injected rate (the truth) and its moving flags. The flags are not sent to the daemon: it
/// has to find the motion itself.
fn default_recording(rate_hz: f64) -> Result<(PathBuf, Vec<f64>, Vec<bool>), BoxError> {
    let dir = PathBuf::from(DEFAULT_DIR);
    std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let mut sim = Preset::Adis16405.config();
    sim.rate_hz = rate_hz;
    sim.duration_s = DEFAULT_DURATION_S;
    let mut out = Generator::generate(&sim, 0)?;
    let t_rel: Vec<f64> = out.t_s.iter().map(|t| t - out.t_s[0]).collect();
    let duration = t_rel.last().copied().unwrap_or(0.0);
    let plan = MotionPlan::plan(MotionKind::Turns, 0, duration, DEFAULT_STATIC_FRACTION)?;
    let (truth, moving) = plan.render(&t_rel);
    for (r, m) in out.axes[0].raw.iter_mut().zip(&truth) {
        *r += m;
    }
    let path = dir.join(format!("adis16405_sim_{rate_hz}hz_turns.csv"));
    write_sim_csv(&path, &out)?;
    eprintln!(
        "replay: no recording given; simulated {} ({DEFAULT_DURATION_S} s at {rate_hz} Hz, {} turns added to gx, not flagged)",
        path.display(),
        plan.segments.len()
    );
    Ok((path, truth, moving.iter().map(|&m| m > 0.5).collect()))
}

fn run(args: &Args) -> Result<Summary, BoxError> {
    let config = Config::load(args.config.as_deref())?;
    let columns: Vec<&str> = args.columns.iter().map(String::as_str).collect();
    let (input, injected) = match &args.input {
        Some(path) => (path.clone(), None),
        None => {
            let (path, truth, moving) = default_recording(match config.input.rate_hz {
                RateSetting::Hz(hz) => hz,
                RateSetting::Auto => DEFAULT_RATE_HZ,
            })?;
            (path, Some((truth, moving)))
        }
    };
    let output = args
        .output
        .clone()
        .or_else(|| args.input.is_none().then(|| PathBuf::from(DEFAULT_DIR).join("compensated.csv")));
    let input_options = InputOptions { topic: args.topic.clone(), units: args.units };
    let rec = Recording::load_with(&input, &columns, args.moving_column.as_deref(), &input_options)?;
    let timeout = seconds("timeout-s", args.timeout_s)?;
    let options =
        ReplayOptions { pacing: args.speed.map_or(Pacing::Max, Pacing::Speed), timeout, ..ReplayOptions::default() };

    let mut embedded = None;
    let mut client = None;
    if args.daemon != DaemonChoice::Embedded {
        let c = Client::connect(&config, timeout)?;
        if c.daemon_running(seconds("find-daemon-s", args.find_daemon_s)?) {
            client = Some(c);
        } else if args.daemon == DaemonChoice::Running {
            return Err("no gyrocompd is serving the configured services (start one, or use --daemon auto)".into());
        }
    }
    let client = match client {
        Some(c) => c,
        None => {
            let (daemon, private) = EmbeddedDaemon::start(&offline_config(&config))?;
            embedded = Some(daemon);
            Client::connect(&private, timeout)?
        }
    };
    let embedded_used = embedded.is_some();
    let mode = if embedded_used { "embedded" } else { "running" };
    let result = replay(&rec, &client, &options, |_| {})?;
    drop(client);
    if let Some(daemon) = embedded {
        daemon.stop()?;
    }
    let mut summary = Summary::new(&rec, &result, mode);
    let truth_column = args.truth_column.clone().or_else(|| args.input.is_none().then(|| "gx_drift_dps".to_owned()));
    if let Some(column) = &truth_column {
        let truth = Recording::load_with(&input, &[column.as_str()], None, &input_options)?;
        let first_motion = injected.as_ref().and_then(|(_, moving)| moving.iter().position(|&m| m));
        summary = summary.with_truth(&rec, &result, truth.rate(0).unwrap_or(&[]), first_motion);
    }
    if let Some((truth, moving)) = injected {
        summary = summary.with_motion(&rec, &result, truth, &moving);
    }
    if args.input.is_none() && embedded_used {
        // The one-pipeline property, shown: the offline driver on the same recording and config.
        let mut offline = Vec::with_capacity(rec.len());
        compensate_recording(&config, &rec, |_, o| offline.push(*o))?;
        summary.offline_equal = Some(offline == result.outputs);
    }
    if let Some(path) = &output {
        let mut writer = CompensatedCsvWriter::create(path, &rec)?;
        for (i, out) in result.outputs.iter().enumerate() {
            writer.write(i, out)?;
        }
        writer.finish()?;
    }
    if args.json {
        println!("{}", serde_json::to_string(&summary)?);
    } else {
        eprintln!("{}", summary.text());
    }
    Ok(summary)
}
