//! The `gyrocomp` offline command-line driver: argument types and one module per subcommand.
//! This is an edge of the library: it reads files, calls the pure numerics and prints results.

pub mod allan;
pub mod cc;
pub mod compensate;
pub mod demo;
pub mod denoise;
pub mod eval;
pub mod eval_args;
pub mod eval_motion;
pub mod input;
pub mod motion;
pub mod plot;
pub mod progress;
pub mod sim;
pub mod simgap;
pub mod simgap_args;
pub mod simgap_json;
pub mod simgap_report;
pub mod simgap_selftest;
pub mod simgap_text;

use clap::{Parser, Subcommand};

/// Error type of the CLI: any error, with its chain of causes printed by `main`.
pub type CliError = Box<dyn std::error::Error + Send + Sync + 'static>;

/// gyrocomp: MEMS gyroscope drift modelling and compensation (offline tools).
#[derive(Debug, Parser)]
#[command(name = "gyrocomp", version, about, long_about = None)]
pub struct Cli {
    /// Log level filter for messages on stderr (error, warn, info, debug, trace).
    #[arg(long, global = true, default_value = "info", env = "GYROCOMP_LOG")]
    pub log: String,
    /// The command to run.
    #[command(subcommand)]
    pub command: Command,
}

/// Subcommands of `gyrocomp`.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// The main job: simulate a paper-like recording and run every offline stage on it.
    Demo(demo::DemoArgs),
    /// Simulate a gyro triad (seeded error model: preset or TOML config).
    Sim(sim::SimArgs),
    /// Add a known motion profile to the rate columns of a static recording.
    Motion(motion::MotionArgs),
    /// Wavelet-denoise one column (db4, universal soft threshold), batch or causal.
    Denoise(denoise::DenoiseArgs),
    /// C-C method: delay τ, delay window τw and embedding dimension m of a column.
    Cc(cc::CcArgs),
    /// Overlapping Allan deviation of a rate column and the IEEE Std 952 noise-term fit.
    Allan(allan::AllanArgs),
    /// Evaluate the models beside honest baselines (paper or motion-injected protocol).
    Eval(eval_args::EvalArgs),
    /// Compensate a recording offline with the daemon's pipeline (CSV in, CSV out).
    Compensate(compensate::CompensateArgs),
    /// Sim-to-real gap: where a simulation differs from a recording, which unmodelled effect
    /// explains it, how far the gap shrinks on a held-out part.
    Simgap(simgap_args::SimgapArgs),
}

/// Runs the parsed command line.
pub fn run(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        Command::Demo(args) => demo::run_demo(&args),
        Command::Sim(args) => sim::run(&args),
        Command::Motion(args) => motion::run(&args),
        Command::Denoise(args) => denoise::run(&args),
        Command::Cc(args) => cc::run(&args),
        Command::Allan(args) => allan::run(&args),
        Command::Eval(args) => eval::run(&args),
        Command::Compensate(args) => compensate::run(&args),
        Command::Simgap(args) => simgap::run(&args),
    }
}
