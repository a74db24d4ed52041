//! Arguments shared by several commands: image size and output folder, a sample with a fit
//! config, WIDTHxHEIGHT sizes.

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::{Arg, Args};
use xylem::Face;
use xylem::fit::FitConfig;
use xylem::sample::faces_or_all;

#[derive(Args, Debug)]
pub struct SizeAndOut {
    /// Image (face) side in pixels.
    #[arg(long, default_value_t = 256, value_parser = side_2_8192)]
    pub size: u32,
    /// Output folder (created; must be new, empty, or an earlier xylem output).
    #[arg(long, short = 'o')]
    pub out: PathBuf,
}

/// The sample, output folder, faces and fit config of the commands that run on a sample
/// with the fit's config (`fit`, `rings`). Each command words the help of `--sample`,
/// `--faces` and `--config` for what it does with them ([`help_texts`] in its `#[command]`).
#[derive(Args, Debug)]
pub struct SampleWithFitConfig {
    #[arg(long, value_name = "DIR")]
    pub sample: PathBuf,
    /// Output folder (created; must be new, empty, or an earlier xylem output).
    #[arg(long, short = 'o', value_name = "DIR")]
    pub out: PathBuf,
    #[arg(long, value_name = "LIST")]
    pub faces: Option<String>,
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
}

impl SampleWithFitConfig {
    /// The fit config (the built-in defaults without `--config`) and the faces (all six
    /// without `--faces`).
    pub fn config_and_faces(&self) -> Result<(FitConfig, Vec<Face>)> {
        let config = FitConfig::load_or_default(self.config.as_deref())?;
        let faces = faces_or_all(self.faces.as_deref())?;
        Ok((config, faces))
    }
}

/// For `#[command(mut_args(...))]`: the help text of each argument named in `helps`, so
/// that shared arguments ([`SampleWithFitConfig`]) read right for each command. Mutating in
/// place keeps the arguments' order (`mut_arg` would move them to the end of the usage line).
pub fn help_texts(helps: &'static [(&'static str, &'static str)]) -> impl FnMut(Arg) -> Arg {
    move |arg| match helps.iter().find(|(id, _)| arg.get_id().as_str() == *id) {
        Some((_, help)) => arg.help(*help),
        None => arg,
    }
}

/// Parses a library value for clap, its error naming settings as this CLI's flags (the
/// library writes them as `$name`, see `xylem::error::SettingStyle`).
pub fn flagged<T>(s: &str) -> Result<T, String>
where
    T: std::str::FromStr<Err = xylem::XylemError>,
{
    s.parse::<T>()
        .map_err(|e| e.render(xylem::error::SettingStyle::Flags))
}

/// Splits `N` (a square) or `WxH`; `None` if either side is not a number.
fn split_size(s: &str) -> Option<(u64, u64)> {
    match s.split_once(['x', 'X']) {
        Some((w, h)) => Some((w.trim().parse().ok()?, h.trim().parse().ok()?)),
        None => {
            let n = s.trim().parse().ok()?;
            Some((n, n))
        }
    }
}

/// Parses an image size given to the flag `flag`: `WIDTHxHEIGHT`, or `N` for N x N.
pub fn parse_size(flag: &str, s: &str) -> Result<(usize, usize)> {
    match split_size(s) {
        Some((w, h)) if (1..=16384).contains(&w) && (1..=16384).contains(&h) => {
            Ok((w as usize, h as usize))
        }
        _ => {
            bail!("{flag} {s:?}: expected WIDTHxHEIGHT or N with sides in 1..=16384, e.g. 800x800")
        }
    }
}

/// A square side for `--size` of commands whose images or volumes are square: `N` or `NxN`
/// (so every `--size` reads sizes the same way), within `lo..=hi`.
fn square(s: &str, lo: u32, hi: u32) -> std::result::Result<u32, String> {
    match split_size(s) {
        Some((w, h)) if w != h => Err(format!(
            "{w}x{h}: this command makes square images or volumes; give N or NxN"
        )),
        Some((n, _)) if (u64::from(lo)..=u64::from(hi)).contains(&n) => Ok(n as u32),
        _ => Err(format!("{s:?}: expected N or NxN with N in {lo}..={hi}")),
    }
}

/// `--size` parsers for the ranges the commands use.
pub fn side_2_8192(s: &str) -> std::result::Result<u32, String> {
    square(s, 2, 8192)
}
pub fn side_16_4096(s: &str) -> std::result::Result<u32, String> {
    square(s, 16, 4096)
}
pub fn side_16_2048(s: &str) -> std::result::Result<u32, String> {
    square(s, 16, 2048)
}
pub fn side_4_1024(s: &str) -> std::result::Result<u32, String> {
    square(s, 4, 1024)
}
pub fn side_2_1024(s: &str) -> std::result::Result<u32, String> {
    square(s, 2, 1024)
}
/// `side_16_2048` for a `usize` flag.
pub fn image_side_16_2048(s: &str) -> std::result::Result<usize, String> {
    square(s, 16, 2048).map(|n| n as usize)
}

/// `--rings auto|given|predict`.
pub fn ring_source(s: &str) -> std::result::Result<xylem::rings::RingSource, String> {
    s.parse().map_err(|_| {
        format!(
            "{s:?} is not a ring source; expected one of {}",
            xylem::rings::RingSource::ALL.map(|r| r.name()).join(", ")
        )
    })
}
