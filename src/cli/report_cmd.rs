//! `xylem report`: one static HTML page gathering a run's metrics, cuts, sheets, renders,
//! loss curves, stage timings and configs (`xylem::report::html`).

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;
use xylem::io::check_new_file;
use xylem::report::{default_title, write_report};

/// Gather a run folder's metrics, cuts, sheets, renders, loss curves, timings and configs
/// into one HTML page.
#[derive(Args, Debug)]
#[command(after_help = "Example:
  xylem report --run out/demo --out out/demo/report/index.html

The page links the run's images with relative paths, so the run folder can be moved or
served as a whole; the same folder always gives the same page.")]
pub struct ReportArgs {
    /// The run folder (as written by `xylem demo` or `xylem run`).
    #[arg(long)]
    pub run: PathBuf,
    /// Output HTML file (default: RUN/report/index.html, which is replaced on every call);
    /// must end in .html or .htm; an existing file is only replaced with --force.
    #[arg(long, short = 'o')]
    pub out: Option<PathBuf>,
    /// Replace an existing --out file.
    #[arg(long)]
    pub force: bool,
    /// Page title (default: "xylem run: SAMPLE" with the sample folder's name from
    /// RUN/run.toml, or "xylem demo: SPECIES" for a demo).
    #[arg(long)]
    pub title: Option<String>,
}

pub fn run(args: ReportArgs) -> Result<()> {
    let default = args.run.join("report/index.html");
    let out = match args.out {
        // The default page is the report's own file, rewritten by every `xylem run`.
        None => default,
        Some(out) if out == default => out,
        Some(out) => {
            let html = out
                .extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| e.eq_ignore_ascii_case("html") || e.eq_ignore_ascii_case("htm"));
            if !html {
                bail!(
                    "--out {}: expected an .html or .htm file (the report is one HTML page)",
                    out.display()
                );
            }
            check_new_file(&out, args.force)?;
            out
        }
    };
    let title = args.title.unwrap_or_else(|| default_title(&args.run));
    let images = write_report(&args.run, &out, &title)?;
    println!("wrote {} ({images} images)", out.display());
    Ok(())
}
