//! Sub-commands of `xylem`, one file each.

mod compare_cmd;
mod demo_cmd;
mod export_cmd;
mod field_cmd;
mod fit_cmd;
mod mesh_cmd;
mod output_args;
mod presets;
mod procedural_cmd;
mod render_cmd;
mod report_cmd;
mod sample_cmd;
mod slice_cmd;
mod synth_cmd;
mod texture2d_cmd;
mod texture_source;
mod train_cmd;

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
    Compare(compare_cmd::CompareArgs),
    Demo(demo_cmd::DemoArgs),
    Export(export_cmd::ExportArgs),
    Field(field_cmd::FieldArgs),
    Fit(fit_cmd::FitArgs),
    MeshBowl(mesh_cmd::MeshBowlArgs),
    Procedural(procedural_cmd::ProceduralArgs),
    Render(render_cmd::RenderArgs),
    Report(report_cmd::ReportArgs),
    Sample(sample_cmd::SampleArgs),
    Slice(slice_cmd::SliceArgs),
    Synth(synth_cmd::SynthArgs),
    Texture2d(texture2d_cmd::Texture2dArgs),
    Train(train_cmd::TrainArgs),
}

pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Compare(a) => compare_cmd::run(a),
        Command::Demo(a) => demo_cmd::run(a),
        Command::Export(a) => export_cmd::run(a),
        Command::Field(a) => field_cmd::run(a),
        Command::Fit(a) => fit_cmd::run(a),
        Command::MeshBowl(a) => mesh_cmd::run(a),
        Command::Procedural(a) => procedural_cmd::run(a),
        Command::Render(a) => render_cmd::run(a),
        Command::Report(a) => report_cmd::run(a),
        Command::Sample(a) => sample_cmd::run(a),
        Command::Slice(a) => slice_cmd::run(a),
        Command::Synth(a) => synth_cmd::run(a),
        Command::Texture2d(a) => texture2d_cmd::run(a),
        Command::Train(a) => train_cmd::run(a),
    }
}
