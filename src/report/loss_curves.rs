//! The loss curves of a run: the NCA training (`train/loss.csv`) and the growth-field fit
//! (`fit/loss.csv`), read into plot series. A reader looks at them to see whether training
//! converged, diverged or was still falling when it stopped.
//!
//! `train/loss.csv`: `iteration,steps,loss,style,overflow,learning_rate`, one row per
//! iteration. `fit/loss.csv`: `stage,iteration,total,iso,image,smooth`, the stages (pith,
//! trial, distortion, colour) one after another, each counting its own iterations.

use std::path::Path;

use super::metrics_table::MetricsTable;
use super::plot::{LinePlot, PALETTE, Series};

/// A plot, or why there is none (shown in the page instead of failing it: a run killed
/// half-way or a damaged loss file should not cost the reader the rest of the report).
pub(crate) type PlotOrNote = Result<LinePlot, String>;

/// Iterations per point of the training curve's running mean: about 40 windows over the
/// run, so the trend shows through the noise of single iterations.
const SMOOTHING_WINDOWS: usize = 40;

/// The NCA training loss against the iteration, with its running geometric mean.
pub(crate) fn training_plot(path: &Path) -> PlotOrNote {
    let table = read(path)?;
    let named = |e: String| format!("{}: {e}", path.display());
    let iterations = table.numbers("iteration").map_err(named)?;
    let losses = table.numbers("loss").map_err(named)?;
    let points: Vec<(f64, f64)> = iterations.into_iter().zip(losses).collect();
    if points.is_empty() {
        return Err(format!("{}: no iterations recorded yet", path.display()));
    }
    let window = (points.len() / SMOOTHING_WINDOWS).max(1);
    let mut series = vec![Series {
        label: "loss per iteration".into(),
        points: points.clone(),
        colour: "#9ecae1",
        width: 1.0,
    }];
    if window > 1 {
        series.push(Series {
            label: format!("running geometric mean ({window} iterations)"),
            points: running_geometric_mean(&points, window),
            colour: "#08519c",
            width: 2.0,
        });
    }
    Ok(LinePlot {
        x_label: "training iteration".into(),
        y_label: "loss (log scale)".into(),
        description: "NCA training loss against the iteration, log scale".into(),
        series,
    })
}

/// The fit's total loss, one curve per stage, the stages placed one after another.
pub(crate) fn fit_plot(path: &Path) -> PlotOrNote {
    let table = read(path)?;
    let named = |e: String| format!("{}: {e}", path.display());
    let totals = table.numbers("total").map_err(named)?;
    let stage = table
        .column("stage")
        .ok_or_else(|| named("has no `stage` column".into()))?;
    if totals.is_empty() {
        return Err(format!("{}: no iterations recorded yet", path.display()));
    }
    let mut series: Vec<Series> = Vec::new();
    for (step, (row, total)) in table.rows.iter().zip(totals).enumerate() {
        let name = &row[stage];
        let continues = series.last().is_some_and(|s| &s.label == name);
        if !continues {
            let colour = PALETTE[series.len() % PALETTE.len()];
            series.push(Series {
                label: name.clone(),
                points: Vec::new(),
                colour,
                width: 1.5,
            });
        }
        if let Some(s) = series.last_mut() {
            s.points.push((step as f64, total));
        }
    }
    Ok(LinePlot {
        x_label: "fit iteration (all stages in order)".into(),
        y_label: "total loss (log scale)".into(),
        description: "Growth-field fit loss by stage, log scale".into(),
        series,
    })
}

fn read(path: &Path) -> Result<MetricsTable, String> {
    MetricsTable::read(path).map_err(|e| e.to_string())
}

/// Centred running mean of ln(y) over `window` points (losses are compared by ratio, and
/// an arithmetic mean would follow the spikes). Points with y <= 0 are left out.
fn running_geometric_mean(points: &[(f64, f64)], window: usize) -> Vec<(f64, f64)> {
    let logs: Vec<Option<f64>> = points
        .iter()
        .map(|&(_, y)| (y > 0.0 && y.is_finite()).then(|| y.ln()))
        .collect();
    let half = window / 2;
    (0..points.len())
        .filter_map(|i| {
            let span = &logs[i.saturating_sub(half)..(i + half + 1).min(logs.len())];
            let (sum, n) = span
                .iter()
                .flatten()
                .fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
            (n > 0).then(|| (points[i].0, (sum / n as f64).exp()))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_geometric_mean_follows_ratios_not_spikes() {
        let points: Vec<(f64, f64)> = (0..5)
            .map(|i| (i as f64, if i == 2 { 100.0 } else { 1.0 }))
            .collect();
        let smooth = running_geometric_mean(&points, 5);
        assert_eq!(smooth.len(), 5);
        // Window of 5 around the spike: (100 * 1^4)^(1/5) = 2.51, not the mean 20.8.
        assert!((smooth[2].1 - 100f64.powf(0.2)).abs() < 1e-9);
    }
}
