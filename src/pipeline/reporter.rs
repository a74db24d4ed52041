//! What a long job tells its user while it runs: counted progress, result lines and notes.
//! The library only calls this trait; the command line adapts it to progress bars (or log
//! lines when stderr is not a terminal) and to its `--json` mode, and library users pass
//! [`Quiet`] or their own.

/// Progress of one counted phase (`fit`, `train`, `unroll`) of `total` steps.
pub trait Counter {
    fn set_position(&self, position: u64);
    fn position(&self) -> u64;
    /// Text after the counts (the loss, the current sub-stage).
    fn set_message(&self, message: String);
    /// Measures the rate from here on (a resumed run starts late).
    fn reset_eta(&self);
    fn finish(&self);
}

/// Where a job's progress and lines go.
pub trait Reporter {
    /// A new counted phase.
    fn counter(&self, name: &str, total: u64) -> Box<dyn Counter>;
    /// A result for people (what was written, the fit's error).
    fn say(&self, line: &str);
    /// A note on the job's course (`== fit`, a skipped stage, a warning).
    fn note(&self, line: &str);
}

/// Shows nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct Quiet;

impl Counter for Quiet {
    fn set_position(&self, _: u64) {}
    fn position(&self) -> u64 {
        0
    }
    fn set_message(&self, _: String) {}
    fn reset_eta(&self) {}
    fn finish(&self) {}
}

impl Reporter for Quiet {
    fn counter(&self, _: &str, _: u64) -> Box<dyn Counter> {
        Box::new(Quiet)
    }
    fn say(&self, _: &str) {}
    fn note(&self, _: &str) {}
}
