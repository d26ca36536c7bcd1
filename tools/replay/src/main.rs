//! `replay IN [--topic T] [--units U] [--config C] [--speed X | --max] [-o OUT] [--json]`:
//! publishes a recorded gyro CSV or ROS 2 bag (MCAP) to `gyrocompd` over iceoryx2, collects one
//! compensated sample per row and writes them with the columns of `gyrocomp compensate`. With no daemon serving the configured services, one is
//! started in-process in a private iceoryx2 domain (see the crate documentation).
//!
//! Without IN (the project's main job): simulates eight ADIS16405-like recordings with seeded
//! turns at the configuration's `input.rate_hz` (1800 s, seeds 0–7), replays each through a
//! fresh embedded daemon without the moving flags, checks that the offline driver (`gyrocomp
//! compensate`'s pipeline) gives the same output bit for bit, and scores the answers per turn
//! beside start-up bias-hold, last-static and the white-noise floor, per recording and pooled
//! ([`replay::main_job`]). The first recording and its answers stay in `out/replay/`.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

use clap::{Parser, ValueEnum};
use gyrocomp::config::{Config, RateSetting};
use gyrocomp::drive::{compensate_recording, error_chain, offline_config};
use gyrocomp::io::{CompensatedCsvWriter, InputOptions, RateUnit, Recording, write_sim_csv};
use gyrocomp::sim::{Generator, MotionKind, MotionPlan, Preset};
use replay::main_job::{MainJob, SeededSummary};
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
    match report(&args) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(e) => {
            eprintln!("replay: error: {}", error_chain(e.as_ref()));
            ExitCode::from(2)
        }
    }
}

type BoxError = Box<dyn std::error::Error + Send + Sync>;

/// Runs the replay (or the main job without IN), prints its summary and tells whether it
/// succeeded (nothing dropped, the offline driver identical where checked).
fn report(args: &Args) -> Result<bool, BoxError> {
    let config = Config::load(args.config.as_deref())?;
    let (json, text, ok) = match &args.input {
        Some(input) => {
            let s = run(args, &config, input)?;
            (serde_json::to_string(&s)?, s.text(), s.dropped == 0 && s.offline_equal != Some(false))
        }
        None => {
            let job = main_job(args, &config)?;
            (serde_json::to_string(&job)?, job.text(), job.succeeded())
        }
    };
    if args.json {
        println!("{json}");
    } else {
        eprintln!("{text}");
    }
    Ok(ok)
}

fn seconds(name: &str, s: f64) -> Result<Duration, BoxError> {
    Duration::try_from_secs_f64(s).map_err(|_| format!("--{name}: {s} is not a duration in seconds").into())
}

/// Directory of the embedded default's files.
const DEFAULT_DIR: &str = "out/replay";
/// Length of each of the embedded default's recordings, s.
const DEFAULT_DURATION_S: f64 = 1800.0;
/// Static fraction of the turns injected into the embedded default's first column.
const DEFAULT_STATIC_FRACTION: f64 = 0.5;
/// Rate of the simulated default recordings when `input.rate_hz` is "auto", Hz.
const DEFAULT_RATE_HZ: f64 = 100.0;
/// Seeds of the embedded default's recordings (simulated gyro and turns alike): 0, 1, …. One
/// recording's per-turn figure against start-up bias-hold is one draw of bias-hold's start-up
/// error ([`replay::main_job`]); eight give a figure that a seed does not decide.
const DEFAULT_SEEDS: u64 = 8;

/// One of the embedded default's recordings: the ADIS16405 preset at `rate_hz` (seed `seed`)
/// with seeded turns (`gyrocomp motion --profile turns --seed SEED`) added to its first column,
/// written to `path`; returns the injected rate (the truth) and its moving flags. The flags are
/// not sent to the daemon: it has to find the motion itself.
fn default_recording(path: &Path, rate_hz: f64, seed: u64) -> Result<(Vec<f64>, Vec<bool>, usize), BoxError> {
    let mut sim = Preset::Adis16405.config();
    sim.rate_hz = rate_hz;
    sim.duration_s = DEFAULT_DURATION_S;
    let mut out = Generator::generate(&sim, seed)?;
    let t_rel: Vec<f64> = out.t_s.iter().map(|t| t - out.t_s[0]).collect();
    let duration = t_rel.last().copied().unwrap_or(0.0);
    let plan = MotionPlan::plan(MotionKind::Turns, seed, duration, DEFAULT_STATIC_FRACTION)?;
    let (truth, moving) = plan.render(&t_rel);
    for (r, m) in out.axes[0].raw.iter_mut().zip(&truth) {
        *r += m;
    }
    write_sim_csv(path, &out)?;
    Ok((truth, moving.iter().map(|&m| m > 0.5).collect(), plan.segments.len()))
}

/// What one replay needs besides the arguments: the recording, its injected motion (the main
/// job), where the answers go, and whether to start an embedded daemon whatever `--daemon` says.
struct ReplayJob<'a> {
    input: &'a Path,
    injected: Option<(Vec<f64>, Vec<bool>)>,
    output: Option<PathBuf>,
    truth_column: Option<String>,
    force_embedded: bool,
}

/// The main job (no IN): [`DEFAULT_SEEDS`] simulated recordings, each replayed through a fresh
/// embedded daemon, scored, and checked against the offline driver; the first recording and its
/// answers are kept in `out/replay/`, the others removed once scored.
fn main_job(args: &Args, config: &Config) -> Result<MainJob, BoxError> {
    if args.daemon == DaemonChoice::Running {
        return Err("the main job replays each of its recordings through a fresh embedded daemon; \
                    give a recording to replay it through a running one"
            .into());
    }
    if args.columns.first().map(String::as_str) != Some("gx_dps") {
        return Err(format!(
            "the main job adds its turns to gx_dps and scores that column; --column {} must start with gx_dps",
            args.columns.join(",")
        )
        .into());
    }
    let rate_hz = match config.input.rate_hz {
        RateSetting::Hz(hz) => hz,
        RateSetting::Auto => DEFAULT_RATE_HZ,
    };
    let dir = PathBuf::from(DEFAULT_DIR);
    std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let kept = dir.join(format!("adis16405_sim_{rate_hz}hz_turns.csv"));
    let mut recordings = Vec::new();
    for seed in 0..DEFAULT_SEEDS {
        let path =
            if seed == 0 { kept.clone() } else { dir.join(format!("adis16405_sim_{rate_hz}hz_turns_seed{seed}.csv")) };
        let (truth, moving, turns) = default_recording(&path, rate_hz, seed)?;
        if seed == 0 {
            eprintln!(
                "replay: no recording given; simulating {DEFAULT_SEEDS} recordings (ADIS16405 preset, {DEFAULT_DURATION_S} s at \
                 {rate_hz} Hz, seeds 0–{}, each with its own seeded turns added to gx, not flagged); the first ({turns} turns) \
                 is kept as {}",
                DEFAULT_SEEDS - 1,
                kept.display()
            );
        }
        let job = ReplayJob {
            input: &path,
            injected: Some((truth, moving)),
            output: (seed == 0).then(|| args.output.clone().unwrap_or_else(|| dir.join("compensated.csv"))),
            truth_column: Some("gx_drift_dps".to_owned()),
            force_embedded: true,
        };
        let summary = replay_one(args, config, job);
        if seed != 0 {
            // Removed whether or not the replay succeeded; a failure to remove is only logged.
            if let Err(e) = std::fs::remove_file(&path) {
                tracing::warn!("cannot remove {}: {e}", path.display());
            }
        }
        recordings.push(SeededSummary { seed, summary: summary? });
    }
    Ok(MainJob::new(recordings))
}

fn run(args: &Args, config: &Config, input: &Path) -> Result<Summary, BoxError> {
    let job = ReplayJob {
        input,
        injected: None,
        output: args.output.clone(),
        truth_column: args.truth_column.clone(),
        force_embedded: false,
    };
    replay_one(args, config, job)
}

/// Replays one recording and summarises it (module documentation).
fn replay_one(args: &Args, config: &Config, job: ReplayJob<'_>) -> Result<Summary, BoxError> {
    let columns: Vec<&str> = args.columns.iter().map(String::as_str).collect();
    let input_options = InputOptions { topic: args.topic.clone(), units: args.units };
    // The main job's flags are not sent: the daemon has to find the motion itself.
    let moving_column = if job.injected.is_some() { None } else { args.moving_column.as_deref() };
    let rec = Recording::load_with(job.input, &columns, moving_column, &input_options)?;
    let timeout = seconds("timeout-s", args.timeout_s)?;
    let options =
        ReplayOptions { pacing: args.speed.map_or(Pacing::Max, Pacing::Speed), timeout, ..ReplayOptions::default() };

    let mut embedded = None;
    let mut client = None;
    if args.daemon != DaemonChoice::Embedded && !job.force_embedded {
        let c = Client::connect(config, timeout)?;
        if c.daemon_running(seconds("find-daemon-s", args.find_daemon_s)?) {
            client = Some(c);
        } else if args.daemon == DaemonChoice::Running {
            return Err("no gyrocompd is serving the configured services (start one, or use --daemon auto)".into());
        }
    }
    let client = match client {
        Some(c) => c,
        None => {
            let (daemon, private) = EmbeddedDaemon::start(&offline_config(config))?;
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
    if let Some(column) = &job.truth_column {
        let truth = Recording::load_with(job.input, &[column.as_str()], None, &input_options)?;
        let first_motion = job.injected.as_ref().and_then(|(_, moving)| moving.iter().position(|&m| m));
        summary = summary.with_truth(&rec, &result, truth.rate(0).unwrap_or(&[]), first_motion);
    }
    let main_job = job.injected.is_some();
    if let Some((truth, moving)) = job.injected {
        summary = summary.with_motion(&rec, &result, truth, &moving);
    }
    if main_job && embedded_used {
        // The one-pipeline property, shown: the offline driver on the same recording and config.
        let mut offline = Vec::with_capacity(rec.len());
        compensate_recording(config, &rec, |_, o| offline.push(*o))?;
        summary.offline_equal = Some(offline == result.outputs);
    }
    if let Some(path) = &job.output {
        let mut writer = CompensatedCsvWriter::create(path, &rec)?;
        for (i, out) in result.outputs.iter().enumerate() {
            writer.write(i, out)?;
        }
        writer.finish()?;
    }
    Ok(summary)
}
