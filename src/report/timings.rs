//! Time and peak memory per stage of a run (`RUN/timings.csv`), measured by `xylem run` and
//! shown in the report: what a run costs is the first thing someone planning a bigger one
//! asks, and the peak memory is what decides whether it fits at all.
//!
//! `timings.csv`: `stage,seconds,peak_mb,skipped`; `peak_mb` is the stage's peak resident
//! memory (empty where it cannot be measured), `skipped` is `true` when the stage was found
//! done by an earlier call. A resumed run keeps the earlier call's row of a skipped stage,
//! so the table still says what the work cost when it was done.

use std::path::Path;
use std::time::Instant;

use crate::error::{Result, XylemError};
use crate::memory::{peak_resident_bytes, reset_peak_resident};

use super::metrics_table::MetricsTable;

/// File name of the table in the run folder.
pub use crate::run_folder::TIMINGS_CSV as TIMINGS_FILE;

const HEADER: [&str; 4] = ["stage", "seconds", "peak_mb", "skipped"];
const MB: f64 = 1024.0 * 1024.0;

/// One stage's cost.
#[derive(Clone, Debug, PartialEq)]
pub struct StageTiming {
    pub stage: String,
    pub seconds: f64,
    pub peak_mb: Option<f64>,
    pub skipped: bool,
}

/// The stages of a run, in the order they ran.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Timings {
    pub stages: Vec<StageTiming>,
}

impl Timings {
    pub fn read(path: &Path) -> Result<Self> {
        let table = MetricsTable::read(path)?;
        Self::from_table(&table).map_err(|m| XylemError::input(path.display().to_string(), m))
    }

    fn from_table(table: &MetricsTable) -> std::result::Result<Self, String> {
        if table.header != HEADER {
            return Err(format!(
                "expected the columns {}, found {}",
                HEADER.join(","),
                table.header.join(",")
            ));
        }
        let seconds = table.numbers("seconds")?;
        let stages = table
            .rows
            .iter()
            .zip(seconds)
            .enumerate()
            .map(|(i, (row, seconds))| {
                let peak_mb = match row[2].as_str() {
                    "" => None,
                    text => Some(text.parse::<f64>().map_err(|_| {
                        format!("row {}: peak_mb is {text:?}, not a number", i + 2)
                    })?),
                };
                let skipped = row[3].parse::<bool>().map_err(|_| {
                    format!("row {}: skipped is {:?}, not true or false", i + 2, row[3])
                })?;
                Ok(StageTiming {
                    stage: row[0].clone(),
                    seconds,
                    peak_mb,
                    skipped,
                })
            })
            .collect::<std::result::Result<_, String>>()?;
        Ok(Self { stages })
    }

    pub fn to_csv(&self) -> String {
        let rows = self
            .stages
            .iter()
            .map(|s| {
                vec![
                    s.stage.clone(),
                    format!("{:.3}", s.seconds),
                    s.peak_mb.map(|m| format!("{m:.1}")).unwrap_or_default(),
                    s.skipped.to_string(),
                ]
            })
            .collect();
        MetricsTable::new(&HEADER, rows).to_csv()
    }

    /// Adds (or replaces) the row of `timing`'s stage. A skipped stage takes the row of
    /// the same stage from `earlier` when there is one: it says what the stage cost when it
    /// ran, while this call's row would only time the check that it was done.
    pub fn record(&mut self, timing: StageTiming, earlier: Option<&Timings>) {
        let kept = earlier
            .filter(|_| timing.skipped)
            .and_then(|e| e.stages.iter().find(|s| s.stage == timing.stage))
            .cloned();
        let row = kept.unwrap_or(timing);
        match self.stages.iter_mut().find(|s| s.stage == row.stage) {
            Some(old) => *old = row,
            None => self.stages.push(row),
        }
    }
}

/// Measures one stage: wall time, and the peak resident memory since it started when the
/// system lets the peak be reset (Linux); otherwise no peak, rather than the peak of
/// everything that ran before, which would be blamed on this stage.
pub(crate) struct StageClock {
    start: Instant,
    peak_was_reset: bool,
}

impl StageClock {
    pub(crate) fn start() -> Self {
        Self {
            peak_was_reset: reset_peak_resident().is_some(),
            start: Instant::now(),
        }
    }

    pub(crate) fn finish(self, stage: &str, skipped: bool) -> StageTiming {
        let peak = if self.peak_was_reset {
            peak_resident_bytes()
        } else {
            None
        };
        StageTiming {
            stage: stage.to_string(),
            seconds: self.start.elapsed().as_secs_f64(),
            peak_mb: peak.map(|b| b as f64 / MB),
            skipped,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn timing(stage: &str, seconds: f64, skipped: bool) -> StageTiming {
        StageTiming {
            stage: stage.into(),
            seconds,
            peak_mb: Some(100.0),
            skipped,
        }
    }

    #[test]
    fn csv_round_trips_and_damage_is_named() {
        let mut t = Timings::default();
        t.record(timing("fit", 12.5, false), None);
        t.record(
            StageTiming {
                peak_mb: None,
                ..timing("train", 0.01, true)
            },
            None,
        );
        let back = Timings::from_table(&MetricsTable::parse(&t.to_csv()).unwrap()).unwrap();
        assert_eq!(back, t);
        let bad = MetricsTable::parse("stage,seconds,peak_mb,skipped\nfit,1,2,maybe\n").unwrap();
        assert!(Timings::from_table(&bad).unwrap_err().contains("row 2"));
        let bad = MetricsTable::parse("stage,seconds\nfit,1\n").unwrap();
        assert!(
            Timings::from_table(&bad)
                .unwrap_err()
                .contains("expected the columns")
        );
    }

    #[test]
    fn a_skipped_stage_keeps_the_earlier_row_and_a_rerun_replaces_it() {
        let mut earlier = Timings::default();
        earlier.record(timing("fit", 300.0, false), None);
        earlier.record(timing("sheet", 5.0, false), None);
        let mut now = Timings::default();
        now.record(timing("fit", 0.001, true), Some(&earlier));
        now.record(timing("train", 0.002, true), Some(&earlier));
        now.record(timing("sheet", 4.0, false), Some(&earlier));
        assert_eq!(now.stages[0], timing("fit", 300.0, false));
        assert_eq!(
            now.stages[1],
            timing("train", 0.002, true),
            "no earlier row"
        );
        assert_eq!(now.stages[2], timing("sheet", 4.0, false), "it ran again");
        now.record(timing("sheet", 3.0, false), None);
        assert_eq!(now.stages.len(), 3);
    }

    #[test]
    fn the_clock_measures_time_and_memory_on_linux() {
        let t = StageClock::start().finish("x", false);
        assert!(t.seconds >= 0.0 && t.seconds < 5.0);
        if let Some(mb) = t.peak_mb {
            assert!(mb > 1.0, "{mb} MB");
        }
    }
}
