//! Progress of long commands: a bar on a terminal, a log line every few seconds when stderr
//! is a file or a pipe (nohup, CI, `2> log`), nothing with `--quiet`.
//!
//! indicatif draws nothing when stderr is not a terminal, so without the log lines a
//! redirected `xylem run` was silent for minutes.

use std::io::IsTerminal;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};
use xylem::pipeline::{Counter, Reporter};

use super::json_out::say;

static QUIET: AtomicBool = AtomicBool::new(false);

/// Seconds between two log lines.
const LOG_EVERY: Duration = Duration::from_secs(5);

/// Silences every progress display of this process (`--quiet`).
pub fn set_quiet(quiet: bool) {
    QUIET.store(quiet, Ordering::Relaxed);
}

enum Display {
    Bar(ProgressBar),
    Log(Mutex<LogState>),
    Quiet,
}

struct LogState {
    stage: String,
    len: u64,
    pos: u64,
    message: String,
    start: Instant,
    /// Position and time from which the rate (ETA) is measured: a resumed run starts late.
    rate_origin: (u64, Instant),
    last_line: Option<Instant>,
}

/// One progress display of `len` steps.
pub struct Progress {
    display: Display,
}

impl Progress {
    /// `stage` names what is counted (`train`, `unroll`, ...).
    pub fn new(stage: &str, len: u64) -> Self {
        let display = if QUIET.load(Ordering::Relaxed) {
            Display::Quiet
        } else if std::io::stderr().is_terminal() {
            let style = ProgressStyle::with_template(
                "{prefix:>10} [{bar:30}] {pos}/{len} {msg} elapsed {elapsed} ETA {eta}",
            )
            .expect("valid template")
            .progress_chars("=> ");
            let bar = ProgressBar::new(len).with_style(style);
            bar.set_prefix(stage.to_string());
            Display::Bar(bar)
        } else {
            let now = Instant::now();
            Display::Log(Mutex::new(LogState {
                stage: stage.to_string(),
                len,
                pos: 0,
                message: String::new(),
                start: now,
                rate_origin: (0, now),
                last_line: None,
            }))
        };
        Self { display }
    }

    pub fn set_position(&self, pos: u64) {
        match &self.display {
            Display::Bar(bar) => bar.set_position(pos),
            Display::Log(state) => with_state(state, |s| s.pos = pos),
            Display::Quiet => {}
        }
    }

    pub fn inc(&self, steps: u64) {
        match &self.display {
            Display::Bar(bar) => bar.inc(steps),
            Display::Log(state) => with_state(state, |s| s.pos += steps),
            Display::Quiet => {}
        }
    }

    pub fn position(&self) -> u64 {
        match &self.display {
            Display::Bar(bar) => bar.position(),
            Display::Log(state) => state.lock().map_or(0, |s| s.pos),
            Display::Quiet => 0,
        }
    }

    /// Text after the counts (a loss, the current item).
    pub fn set_message(&self, message: String) {
        match &self.display {
            Display::Bar(bar) => bar.set_message(message),
            Display::Log(state) => {
                if let Ok(mut s) = state.lock() {
                    s.message = message;
                }
            }
            Display::Quiet => {}
        }
    }

    /// Measures the rate from here on (after skipping what a resumed run had done).
    pub fn reset_eta(&self) {
        match &self.display {
            Display::Bar(bar) => bar.reset_eta(),
            Display::Log(state) => {
                if let Ok(mut s) = state.lock() {
                    s.rate_origin = (s.pos, Instant::now());
                }
            }
            Display::Quiet => {}
        }
    }

    pub fn finish(&self) {
        match &self.display {
            Display::Bar(bar) => bar.finish(),
            Display::Log(state) => {
                if let Ok(s) = state.lock() {
                    eprintln!("{}", s.line(true));
                }
            }
            Display::Quiet => {}
        }
    }
}

impl Counter for Progress {
    fn set_position(&self, position: u64) {
        Progress::set_position(self, position);
    }
    fn position(&self) -> u64 {
        Progress::position(self)
    }
    fn set_message(&self, message: String) {
        Progress::set_message(self, message);
    }
    fn reset_eta(&self) {
        Progress::reset_eta(self);
    }
    fn finish(&self) {
        Progress::finish(self);
    }
}

/// The library's reporter on the command line: progress displays as above, result lines on
/// stdout (stderr under `--json`), notes on stderr.
pub struct CliReporter;

impl Reporter for CliReporter {
    fn counter(&self, name: &str, total: u64) -> Box<dyn Counter> {
        Box::new(Progress::new(name, total))
    }
    fn say(&self, line: &str) {
        say(line);
    }
    fn note(&self, line: &str) {
        eprintln!("{line}");
    }
}

/// Applies `update`, then prints a line if the last one is old enough.
fn with_state(state: &Mutex<LogState>, update: impl FnOnce(&mut LogState)) {
    let Ok(mut s) = state.lock() else {
        return;
    };
    update(&mut s);
    let due = s.last_line.is_none_or(|t| t.elapsed() >= LOG_EVERY);
    if due {
        s.last_line = Some(Instant::now());
        eprintln!("{}", s.line(false));
    }
}

impl LogState {
    fn line(&self, done: bool) -> String {
        let pct = (100 * self.pos.min(self.len))
            .checked_div(self.len)
            .unwrap_or(100);
        let message = if self.message.is_empty() {
            String::new()
        } else {
            format!(" {}", self.message)
        };
        let elapsed = clock(self.start.elapsed());
        let tail = if done {
            "done".to_string()
        } else {
            format!("ETA {}", self.eta().map_or("?".to_string(), clock))
        };
        format!(
            "{}: {}/{} ({pct}%){message}, elapsed {elapsed}, {tail}",
            self.stage, self.pos, self.len
        )
    }

    fn eta(&self) -> Option<Duration> {
        let (pos0, t0) = self.rate_origin;
        let done = self.pos.checked_sub(pos0).filter(|&d| d > 0)?;
        let left = self.len.saturating_sub(self.pos);
        Some(t0.elapsed().mul_f64(left as f64 / done as f64))
    }
}

/// `1h02m03s`, `2m03s` or `3s`.
fn clock(d: Duration) -> String {
    let s = d.as_secs();
    match (s / 3600, s / 60 % 60, s % 60) {
        (0, 0, sec) => format!("{sec}s"),
        (0, m, sec) => format!("{m}m{sec:02}s"),
        (h, m, sec) => format!("{h}h{m:02}m{sec:02}s"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clock_reads_like_a_log() {
        assert_eq!(clock(Duration::from_secs(3)), "3s");
        assert_eq!(clock(Duration::from_secs(123)), "2m03s");
        assert_eq!(clock(Duration::from_secs(3723)), "1h02m03s");
    }
}
