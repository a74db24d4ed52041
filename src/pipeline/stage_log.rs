//! `RUN/timings.csv`, rewritten after every stage, so that a killed run keeps the cost of
//! the stages it finished and its resumption can show them (see [`Timings::record`]).

use std::path::PathBuf;

use super::reporter::Reporter;
use crate::Result;
use crate::io::write_bytes_atomic;
use crate::report::{StageClock, TIMINGS_FILE, Timings};
use crate::run_folder::RunLayout;

pub(crate) struct StageLog {
    path: PathBuf,
    earlier: Option<Timings>,
    now: Timings,
}

impl StageLog {
    /// Starts this call's table; an unreadable earlier table is reported and replaced
    /// (it only costs the earlier rows of skipped stages).
    pub(super) fn open(layout: &RunLayout, reporter: &dyn Reporter) -> Self {
        let path = layout.path(TIMINGS_FILE);
        let earlier = if path.is_file() {
            Timings::read(&path)
                .map_err(|e| reporter.note(&format!("warning: {e}; its rows are not kept")))
                .ok()
        } else {
            None
        };
        Self {
            path,
            earlier,
            now: Timings::default(),
        }
    }

    /// Records a finished stage and rewrites the table.
    pub(super) fn finish(&mut self, clock: StageClock, stage: &str, skipped: bool) -> Result<()> {
        self.now
            .record(clock.finish(stage, skipped), self.earlier.as_ref());
        write_bytes_atomic(&self.path, self.now.to_csv().as_bytes())
    }

    /// This call's rows.
    pub(crate) fn into_timings(self) -> Timings {
        self.now
    }
}
