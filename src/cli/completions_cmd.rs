//! `xylem completions`: shell completion scripts.

use std::io::Write;

use anyhow::Result;
use clap::{Args, CommandFactory};
use clap_complete::Shell;

/// Print a shell completion script (bash, zsh, fish, elvish, powershell) to stdout.
#[derive(Args, Debug)]
#[command(after_help = "Examples:
  xylem completions bash > ~/.local/share/bash-completion/completions/xylem
  xylem completions zsh > ~/.zfunc/_xylem
  xylem completions fish > ~/.config/fish/completions/xylem.fish")]
pub struct CompletionsArgs {
    /// The shell.
    #[arg(value_enum)]
    pub shell: Shell,
}

pub fn run(args: CompletionsArgs) -> Result<()> {
    let mut cmd = super::Cli::command();
    // Generated into memory first: clap_complete panics when stdout closes early (`| head`).
    let mut script = Vec::new();
    clap_complete::generate(args.shell, &mut cmd, "xylem", &mut script);
    match std::io::stdout().write_all(&script) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        other => Ok(other?),
    }
}
