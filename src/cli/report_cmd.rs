//! `xylem report`: one static HTML page gathering a run's sheets, renders, loss curves and
//! metrics.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use xylem::report::write_report;

/// Gather a run folder's sheets, renders, loss curves and metrics table into one HTML page.
#[derive(Args, Debug)]
#[command(after_help = "Example:
  xylem report --run out/demo --out out/demo/report/index.html

The page links the run's images with relative paths, so the run folder can be moved or
served as a whole.")]
pub struct ReportArgs {
    /// The run folder (as written by `xylem demo` or `xylem run`).
    #[arg(long)]
    pub run: PathBuf,
    /// Output HTML file (default: RUN/report/index.html).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Page title.
    #[arg(long, default_value = "xylem run")]
    pub title: String,
}

pub fn run(args: ReportArgs) -> Result<()> {
    let out = args
        .out
        .unwrap_or_else(|| args.run.join("report/index.html"));
    let images = write_report(&args.run, &out, &args.title)?;
    println!("wrote {} ({images} images)", out.display());
    Ok(())
}
