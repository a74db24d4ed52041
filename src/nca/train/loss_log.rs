//! The training log: one row per iteration, written as `loss.csv`.
//!
//! Only deterministic values are logged (no wall-clock times), so a resumed run writes the
//! very same file as an uninterrupted one; speed is shown on the progress bar instead.

use std::path::Path;

use crate::error::{Result, XylemError};
use crate::io::write_bytes_atomic;
use crate::report::MetricsTable;

/// One iteration's figures.
#[derive(Clone, Debug, PartialEq)]
pub struct LossRow {
    pub iteration: usize,
    pub steps: usize,
    /// Total loss (style + weighted overflow).
    pub loss: f32,
    pub style: f32,
    pub overflow: f32,
    pub learning_rate: f64,
}

const HEADER: &str = "iteration,steps,loss,style,overflow,learning_rate";

/// The log as CSV text (floats printed exactly, shortest round-trip form).
pub fn to_csv(rows: &[LossRow]) -> String {
    let rows = rows
        .iter()
        .map(|r| {
            MetricsTable::row(&[
                &r.iteration,
                &r.steps,
                &r.loss,
                &r.style,
                &r.overflow,
                &r.learning_rate,
            ])
        })
        .collect();
    let header: Vec<&str> = HEADER.split(',').collect();
    MetricsTable::new(&header, rows).to_csv()
}

/// Writes `loss.csv` atomically.
pub fn write_csv(path: &Path, rows: &[LossRow]) -> Result<()> {
    write_bytes_atomic(path, to_csv(rows).as_bytes())
}

/// Reads a log written by [`write_csv`].
pub(crate) fn read_csv(path: &Path) -> Result<Vec<LossRow>> {
    let text = std::fs::read_to_string(path).map_err(|e| XylemError::io(path, e))?;
    let bad = |line: usize, msg: &str| {
        XylemError::input(
            format!("{}:{}", path.display(), line + 1),
            format!("{msg}; expected the columns {HEADER}"),
        )
    };
    let mut lines = text.lines().enumerate();
    match lines.next() {
        Some((_, h)) if h.trim() == HEADER => {}
        _ => return Err(bad(0, "unexpected header")),
    }
    lines
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(n, line)| {
            let f: Vec<&str> = line.split(',').collect();
            if f.len() != 6 {
                return Err(bad(n, "wrong number of columns"));
            }
            let num = |i: usize| {
                f[i].trim()
                    .parse::<f64>()
                    .map_err(|_| bad(n, "not a number"))
            };
            Ok(LossRow {
                iteration: num(0)? as usize,
                steps: num(1)? as usize,
                loss: num(2)? as f32,
                style: num(3)? as f32,
                overflow: num(4)? as f32,
                learning_rate: num(5)?,
            })
        })
        .collect()
}
