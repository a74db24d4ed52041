//! Sub-commands of `xylem`, one file each.

mod demo_cmd;
mod field_cmd;
mod fit_cmd;
mod presets;
mod slice_cmd;

use clap::{Parser, Subcommand};

/// xylem: solid (volumetric) wood textures from six photographed cube faces.
///
/// The cube is [-0.5, 0.5]^3 (1 unit = 4 cm); faces A..F and the cuts cut1/cut2 follow
/// docs/DESIGN.md. Every command that writes a folder also writes the config it used there.
#[derive(Parser, Debug)]
#[command(name = "xylem", version, propagate_version = true)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    Demo(demo_cmd::DemoArgs),
    Field(field_cmd::FieldArgs),
    Fit(fit_cmd::FitArgs),
    Slice(slice_cmd::SliceArgs),
}

pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Demo(a) => demo_cmd::run(a),
        Command::Field(a) => field_cmd::run(a),
        Command::Fit(a) => fit_cmd::run(a),
        Command::Slice(a) => slice_cmd::run(a),
    }
}
