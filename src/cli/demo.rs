//! `gyrocomp demo`: the main job on data the project makes itself. It runs the other subcommands
//! in sequence, exactly as a user would type them, on a seeded paper-like simulation: simulate,
//! denoise (batch and causal), C-C method, Allan deviation, and the paper protocol with every
//! model beside the baselines.

use std::path::PathBuf;

use clap::Parser;

use super::{Cli, CliError, run};

/// Arguments of `gyrocomp demo`.
#[derive(Debug, clap::Args)]
pub struct DemoArgs {
    /// Folder for the simulated recording and the denoised outputs.
    #[arg(long, default_value = "out/demo")]
    pub out: PathBuf,
    /// Seed of the simulation.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// Runs `gyrocomp demo`.
pub fn run_demo(args: &DemoArgs) -> Result<(), CliError> {
    std::fs::create_dir_all(&args.out).map_err(|e| format!("{}: cannot create: {e}", args.out.display()))?;
    let path = |name: &str| args.out.join(name).display().to_string();
    let recording = path("paper.csv");
    let seed = args.seed.to_string();
    let steps: Vec<Vec<String>> = vec![
        vec!["sim", "--preset", "paper", "--seed", &seed, "-o", &recording],
        vec!["denoise", &recording, "--mode", "batch", "-o", &path("denoised_batch.csv"), "--json"],
        vec!["denoise", &recording, "--mode", "causal", "-o", &path("denoised_causal.csv"), "--json"],
        vec!["cc", &recording],
        vec!["allan", &recording],
        vec!["eval", &recording],
    ]
    .into_iter()
    .map(|step| step.into_iter().map(str::to_owned).collect())
    .collect();
    for step in steps {
        println!("\n$ gyrocomp {}", step.join(" "));
        let cli = Cli::try_parse_from(std::iter::once("gyrocomp".to_owned()).chain(step))?;
        run(cli)?;
    }
    Ok(())
}
