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
    /// Total loss (style + weighted overflow + weighted low band).
    pub loss: f32,
    pub style: f32,
    pub overflow: f32,
    /// The low-band term before its weight (`[loss] low_band`; 0 in logs written before it).
    pub low_band: f32,
    pub learning_rate: f64,
}

const HEADER: &str = "iteration,steps,loss,style,overflow,learning_rate,low_band";
/// The header of logs written before the low-band term (read as low band 0).
const HEADER_V1: &str = "iteration,steps,loss,style,overflow,learning_rate";

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
                &r.low_band,
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
    let columns = match lines.next() {
        Some((_, h)) if h.trim() == HEADER => 7,
        Some((_, h)) if h.trim() == HEADER_V1 => 6,
        _ => return Err(bad(0, "unexpected header")),
    };
    lines
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(n, line)| {
            let f: Vec<&str> = line.split(',').collect();
            if f.len() != columns {
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
                low_band: if columns == 7 { num(6)? as f32 } else { 0.0 },
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(iteration: usize, low_band: f32) -> LossRow {
        LossRow {
            iteration,
            steps: 9,
            loss: 0.5,
            style: 0.25,
            overflow: 0.125,
            low_band,
            learning_rate: 1e-3,
        }
    }

    #[test]
    fn the_log_round_trips_and_older_logs_read_as_low_band_zero() {
        let dir = std::env::temp_dir().join(format!("xylem-loss-log-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("loss.csv");
        let rows = vec![row(0, 0.03125), row(1, 0.0)];
        write_csv(&path, &rows).unwrap();
        assert_eq!(read_csv(&path).unwrap(), rows);
        std::fs::write(&path, format!("{HEADER_V1}\n0,9,0.5,0.25,0.125,0.001\n")).unwrap();
        assert_eq!(read_csv(&path).unwrap(), vec![row(0, 0.0)]);
        std::fs::write(&path, format!("{HEADER}\n0,9,0.5,0.25,0.125,0.001\n")).unwrap();
        let err = read_csv(&path).unwrap_err().to_string();
        assert!(err.contains("wrong number of columns"), "{err}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
