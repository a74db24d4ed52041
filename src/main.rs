//! The `xylem` command line. All work happens in the library; this binary parses arguments,
//! reports progress and turns errors into messages (anyhow lives only here).

mod cli;

use clap::Parser;

fn main() {
    let args = cli::Cli::parse();
    if let Err(err) = cli::run(args) {
        eprintln!("error: {}", message(&err));
        std::process::exit(1);
    }
}

/// The error and its causes, each said once: library errors show their source in their own
/// text (so they read well alone) and also expose it as their `source()`, which anyhow's
/// `{:#}` would print a second time.
fn message(err: &anyhow::Error) -> String {
    let mut text = String::new();
    for cause in err.chain() {
        // Library errors name settings as `$name`; the command line shows them as its flags.
        // A wrapped library error (`During`) hands its source on as a `Box<XylemError>`.
        let library = cause.downcast_ref::<xylem::XylemError>().or_else(|| {
            cause
                .downcast_ref::<Box<xylem::XylemError>>()
                .map(|boxed| &**boxed)
        });
        let part = match library {
            Some(e) => e.render(xylem::error::SettingStyle::Flags),
            None => cause.to_string(),
        };
        if text.contains(&part) {
            continue;
        }
        if !text.is_empty() {
            text += ": ";
        }
        text += &part;
    }
    text
}
