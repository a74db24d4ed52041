//! Sub-commands of `xylem`, one file each.

mod compare_cmd;
mod completions_cmd;
mod demo_cmd;
mod export_cmd;
mod field_cmd;
mod fit_cmd;
mod gallery_cmd;
mod json_out;
mod mesh_cmd;
mod output_args;
mod presets;
mod procedural_cmd;
mod progress;
mod render_cmd;
mod report_cmd;
mod rings_cmd;
mod run_cmd;
mod sample_cmd;
mod slice_cmd;
mod synth_cmd;
mod texture2d_cmd;
mod texture_source;
mod train_cmd;

use clap::{Parser, Subcommand};

/// `xylem --version`: the crate version and the git commit it was built from.
const VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (",
    env!("XYLEM_GIT_COMMIT"),
    ")"
);

/// xylem: solid (volumetric) wood textures from six photographed cube faces.
///
/// The cube is [-0.5, 0.5]^3 (1 unit = 4 cm); faces A..F and the cuts cut1/cut2 follow
/// docs/DESIGN.md. Every command that writes a folder also writes the config it used there.
#[derive(Parser, Debug)]
#[command(name = "xylem", version = VERSION, propagate_version = true)]
pub struct Cli {
    /// No progress output (bars on a terminal, log lines every 5 s otherwise).
    #[arg(long, short = 'q', global = true)]
    pub quiet: bool,
    /// run, fit, train, compare: print one JSON summary on stdout at the end (the
    /// human-readable lines go to stderr).
    #[arg(long, global = true)]
    pub json: bool,
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    Compare(compare_cmd::CompareArgs),
    Completions(completions_cmd::CompletionsArgs),
    Demo(demo_cmd::DemoArgs),
    Export(export_cmd::ExportArgs),
    Field(field_cmd::FieldArgs),
    Fit(fit_cmd::FitArgs),
    Gallery(gallery_cmd::GalleryArgs),
    MeshBowl(mesh_cmd::MeshBowlArgs),
    Procedural(procedural_cmd::ProceduralArgs),
    Render(render_cmd::RenderArgs),
    Report(report_cmd::ReportArgs),
    Rings(rings_cmd::RingsArgs),
    Run(run_cmd::RunArgs),
    Sample(sample_cmd::SampleArgs),
    Slice(slice_cmd::SliceArgs),
    Synth(synth_cmd::SynthArgs),
    Texture2d(texture2d_cmd::Texture2dArgs),
    Train(train_cmd::TrainArgs),
}

pub fn run(cli: Cli) -> anyhow::Result<()> {
    progress::set_quiet(cli.quiet);
    let name = command_name(&cli.command);
    if cli.json && !json_out::COMMANDS.contains(&name) {
        anyhow::bail!(
            "--json: `xylem {name}` has no summary; it is for {}",
            json_out::COMMANDS.join(", ")
        );
    }
    json_out::init(name, cli.json);
    match cli.command {
        Command::Compare(a) => compare_cmd::run(a),
        Command::Completions(a) => completions_cmd::run(a),
        Command::Demo(a) => demo_cmd::run(a),
        Command::Export(a) => export_cmd::run(a),
        Command::Field(a) => field_cmd::run(a),
        Command::Fit(a) => fit_cmd::run(a),
        Command::Gallery(a) => gallery_cmd::run(a),
        Command::MeshBowl(a) => mesh_cmd::run(a),
        Command::Procedural(a) => procedural_cmd::run(a),
        Command::Render(a) => render_cmd::run(a),
        Command::Report(a) => report_cmd::run(a),
        Command::Rings(a) => rings_cmd::run(a),
        Command::Run(a) => run_cmd::run(a),
        Command::Sample(a) => sample_cmd::run(a),
        Command::Slice(a) => slice_cmd::run(a),
        Command::Synth(a) => synth_cmd::run(a),
        Command::Texture2d(a) => texture2d_cmd::run(a),
        Command::Train(a) => train_cmd::run(a),
    }
}

/// The sub-command's name as typed (clap's kebab-case).
fn command_name(command: &Command) -> &'static str {
    match command {
        Command::Compare(_) => "compare",
        Command::Completions(_) => "completions",
        Command::Demo(_) => "demo",
        Command::Export(_) => "export",
        Command::Field(_) => "field",
        Command::Fit(_) => "fit",
        Command::Gallery(_) => "gallery",
        Command::MeshBowl(_) => "mesh-bowl",
        Command::Procedural(_) => "procedural",
        Command::Render(_) => "render",
        Command::Report(_) => "report",
        Command::Rings(_) => "rings",
        Command::Run(_) => "run",
        Command::Sample(_) => "sample",
        Command::Slice(_) => "slice",
        Command::Synth(_) => "synth",
        Command::Texture2d(_) => "texture2d",
        Command::Train(_) => "train",
    }
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    use super::Cli;

    /// Every flag of every command says what it does, and `-o` always means `--out`.
    #[test]
    fn every_flag_has_help_and_o_is_out() {
        let cli = Cli::command();
        let mut missing = Vec::new();
        for cmd in cli.get_subcommands() {
            for arg in cmd.get_arguments() {
                let id = arg.get_id().as_str();
                if id == "help" || id == "version" {
                    continue;
                }
                if arg.get_help().is_none() && arg.get_long_help().is_none() {
                    missing.push(format!("{} --{id}", cmd.get_name()));
                }
                if arg.get_short() == Some('o') {
                    assert_eq!(arg.get_long(), Some("out"), "{} -o", cmd.get_name());
                }
            }
        }
        assert!(missing.is_empty(), "flags without help: {missing:?}");
    }
}
