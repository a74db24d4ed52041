//! The `xylem` command line. All work happens in the library; this binary parses arguments,
//! reports progress and turns errors into messages (anyhow lives only here).

mod cli;

use clap::Parser;

fn main() {
    let args = cli::Cli::parse();
    if let Err(err) = cli::run(args) {
        eprintln!("error: {err:#}");
        std::process::exit(1);
    }
}
