//! Line plots as inline SVG, so the page needs no plotting library, no script and no extra
//! file, and stays sharp at any zoom. The y axis is logarithmic: losses fall over decades,
//! and on a linear axis everything after the first few iterations is a flat line on zero.

use std::fmt::Write;

use super::format::significant;
use super::page::escape;

/// One curve.
#[derive(Clone, Debug)]
pub(crate) struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub colour: &'static str,
    pub width: f64,
}

/// A plot: curves, axis labels and the text a screen reader says for it.
#[derive(Clone, Debug)]
pub(crate) struct LinePlot {
    pub x_label: String,
    pub y_label: String,
    pub description: String,
    pub series: Vec<Series>,
}

/// An axis range and where its labelled (major) and unlabelled (minor) ticks go.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    pub min: f64,
    pub max: f64,
    pub ticks: Vec<f64>,
    pub minor: Vec<f64>,
}

/// Colours of successive series (readable on white, distinct in print).
pub(crate) const PALETTE: [&str; 6] = [
    "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b",
];

const WIDTH: f64 = 760.0;
/// Height of the area the curves are drawn in.
const AREA_HEIGHT: f64 = 256.0;
const LEFT: f64 = 72.0;
const RIGHT: f64 = 16.0;
const TOP: f64 = 14.0;
const BOTTOM: f64 = 50.0;
/// Height of one line of the legend, which sits above the curves so it never hides them.
const LEGEND_LINE: f64 = 18.0;
/// The most labelled decades a log axis shows; more would crowd the labels.
const MAX_DECADE_TICKS: i32 = 8;

/// `m` x 10^`k` as the nearest double (so 0.02 is the same number the reader types).
fn scaled(m: f64, k: i32) -> f64 {
    format!("{m}e{k}").parse().unwrap_or(m * 10f64.powi(k))
}

/// A log axis covering `[min, max]` (both > 0). Data spanning two decades or more gets
/// ticks at powers of ten (every second or third one when there are many) and the axis runs
/// from decade to decade; narrower data gets ticks at 1, 2 and 5 times powers of ten and
/// the axis runs between the ticks just outside the data, so a curve that falls from 0.23
/// to 0.0058 still has about seven labels instead of two.
pub(crate) fn log_axis(min: f64, max: f64) -> Axis {
    let (mut min, mut max) = (min.min(max), max.max(min));
    if !(min > 0.0 && max.is_finite()) {
        (min, max) = (0.1, 10.0);
    }
    if max / min < 1.01 {
        // A flat curve still needs a range to sit in.
        (min, max) = (min / 1.5, max * 1.5);
    }
    let lo = min.log10().floor() as i32;
    let hi = max.log10().ceil() as i32;
    if (max / min).log10() >= 2.0 {
        let every = ((hi - lo) + MAX_DECADE_TICKS - 1) / MAX_DECADE_TICKS;
        let ticks = (lo..=hi)
            .filter(|k| (k - lo) % every == 0)
            .map(|k| scaled(1.0, k))
            .collect();
        let minor = if every == 1 {
            (lo..hi)
                .flat_map(|k| (2..10).map(move |m| scaled(m as f64, k)))
                .collect()
        } else {
            Vec::new()
        };
        return Axis {
            min: scaled(1.0, lo),
            max: scaled(1.0, hi),
            ticks,
            minor,
        };
    }
    let candidates: Vec<f64> = (lo..=hi)
        .flat_map(|k| [1.0, 2.0, 5.0].map(|m| scaled(m, k)))
        .collect();
    let tolerance = 1e-9;
    let axis_min = candidates
        .iter()
        .copied()
        .filter(|&c| c <= min * (1.0 + tolerance))
        .fold(scaled(1.0, lo), f64::max);
    let axis_max = candidates
        .iter()
        .copied()
        .filter(|&c| c >= max * (1.0 - tolerance))
        .fold(scaled(1.0, hi), f64::min);
    Axis {
        min: axis_min,
        max: axis_max,
        ticks: candidates
            .into_iter()
            .filter(|&c| c >= axis_min && c <= axis_max)
            .collect(),
        minor: Vec::new(),
    }
}

/// A linear axis spanning exactly `[min, max]` (iterations start at 0 and end at the last
/// one: padding would only suggest data that is not there) with ticks at a 1, 2 or 5 step
/// giving four to nine labels.
pub(crate) fn linear_axis(min: f64, max: f64) -> Axis {
    let (mut min, mut max) = (min.min(max), max.max(min));
    if !(min.is_finite() && max.is_finite()) {
        (min, max) = (0.0, 1.0);
    }
    if max - min < 1e-12 {
        (min, max) = (min - 0.5, max + 0.5);
    }
    let raw = (max - min) / 8.0;
    let magnitude = 10f64.powi(raw.log10().floor() as i32);
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * magnitude)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * magnitude);
    let first = (min / step).ceil() as i64;
    let last = (max / step).floor() as i64;
    Axis {
        min,
        max,
        ticks: (first..=last).map(|i| i as f64 * step).collect(),
        minor: Vec::new(),
    }
}

/// A tick label: the shortest text that names the tick.
fn tick_label(v: f64) -> String {
    let mut best = significant(v, 1);
    for digits in 1..=4 {
        best = significant(v, digits);
        if (best.parse::<f64>().unwrap_or(f64::NAN) - v).abs() <= 1e-9 * v.abs().max(1e-300) {
            break;
        }
    }
    // Plain integers need no trailing ".0".
    if best.contains('.') && !best.contains('e') {
        best = best.trim_end_matches('0').trim_end_matches('.').to_string();
    }
    best
}

/// A label on the linear (iteration) axis: whole numbers in full, "1200" rather than
/// "1.2e3".
fn linear_tick_label(v: f64) -> String {
    if v.fract() == 0.0 && v.abs() < 1e9 {
        format!("{v:.0}")
    } else {
        tick_label(v)
    }
}

impl LinePlot {
    /// The plot as an `<svg>` element, or `None` when no point can be drawn (a log axis
    /// cannot show values at or below zero; such points are left out).
    pub(crate) fn to_svg(&self) -> Option<String> {
        let drawable: Vec<(f64, f64)> = self
            .series
            .iter()
            .flat_map(|s| s.points.iter().copied())
            .filter(|&(x, y)| drawable(x, y))
            .collect();
        if drawable.is_empty() {
            return None;
        }
        let fold = |f: fn(f64, f64) -> f64, init: f64, pick: fn(&(f64, f64)) -> f64| {
            drawable.iter().map(pick).fold(init, f)
        };
        let x = linear_axis(
            fold(f64::min, f64::INFINITY, |p| p.0),
            fold(f64::max, f64::NEG_INFINITY, |p| p.0),
        );
        let y = log_axis(
            fold(f64::min, f64::INFINITY, |p| p.1),
            fold(f64::max, f64::NEG_INFINITY, |p| p.1),
        );
        let legend = self.legend_layout();
        let rows = legend.last().map_or(0, |e| e.row + 1);
        let frame = Frame {
            x,
            y,
            top: TOP + LEGEND_LINE * rows as f64,
        };
        let height = frame.bottom() + BOTTOM;
        let mut svg = String::new();
        let _ = writeln!(
            svg,
            "<svg class=\"plot\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 {WIDTH} {height}\" \
             width=\"{WIDTH}\" height=\"{height}\" role=\"img\" aria-label=\"{}\" font-family=\"sans-serif\" font-size=\"12\">",
            escape(&self.description)
        );
        let _ = writeln!(
            svg,
            "<rect x=\"0\" y=\"0\" width=\"{WIDTH}\" height=\"{height}\" fill=\"#fff\"/>"
        );
        frame.grid(&mut svg);
        for series in &self.series {
            frame.curve(&mut svg, series);
        }
        frame.axes(&mut svg, &self.x_label, &self.y_label);
        self.legend(&mut svg, &legend);
        svg += "</svg>";
        Some(svg)
    }

    /// Where each curve's legend entry goes: left to right above the plot area, wrapping
    /// to a new line at the right edge; none for a single curve (the axis label names it).
    fn legend_layout(&self) -> Vec<LegendEntry> {
        if self.series.len() < 2 {
            return Vec::new();
        }
        let mut entries = Vec::new();
        let (mut x, mut row) = (LEFT, 0);
        for (i, s) in self.series.iter().enumerate() {
            let width = 30.0 + 6.6 * s.label.chars().count() as f64 + 18.0;
            if x > LEFT && x + width > WIDTH - RIGHT {
                (x, row) = (LEFT, row + 1);
            }
            entries.push(LegendEntry { series: i, x, row });
            x += width;
        }
        entries
    }

    fn legend(&self, svg: &mut String, entries: &[LegendEntry]) {
        if entries.is_empty() {
            return;
        }
        *svg += "<g class=\"legend\">\n";
        for e in entries {
            let s = &self.series[e.series];
            let y = TOP + LEGEND_LINE * e.row as f64;
            let _ = writeln!(
                svg,
                "<line x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"{}\" stroke-width=\"{}\"/>\
                 <text x=\"{:.1}\" y=\"{:.1}\">{}</text>",
                e.x,
                y - 4.0,
                e.x + 24.0,
                y - 4.0,
                s.colour,
                s.width.max(2.0),
                e.x + 30.0,
                y,
                escape(&s.label)
            );
        }
        *svg += "</g>\n";
    }
}

/// One legend entry's place.
struct LegendEntry {
    series: usize,
    x: f64,
    row: usize,
}

fn drawable(x: f64, y: f64) -> bool {
    x.is_finite() && y.is_finite() && y > 0.0
}

/// Maps data to the plot area.
struct Frame {
    x: Axis,
    y: Axis,
    /// Top of the plot area (below the legend).
    top: f64,
}

impl Frame {
    fn bottom(&self) -> f64 {
        self.top + AREA_HEIGHT
    }

    fn px(&self, x: f64) -> f64 {
        LEFT + (x - self.x.min) / (self.x.max - self.x.min) * (WIDTH - LEFT - RIGHT)
    }

    fn py(&self, y: f64) -> f64 {
        let t = (y.log10() - self.y.min.log10()) / (self.y.max.log10() - self.y.min.log10());
        self.top + (1.0 - t) * AREA_HEIGHT
    }

    fn grid(&self, svg: &mut String) {
        let (x0, x1) = (LEFT, WIDTH - RIGHT);
        let (y0, y1) = (self.top, self.bottom());
        *svg += "<g class=\"grid\" stroke-width=\"1\">\n";
        for &v in &self.y.minor {
            let y = self.py(v);
            let _ = writeln!(
                svg,
                "<line x1=\"{x0}\" y1=\"{y:.1}\" x2=\"{x1}\" y2=\"{y:.1}\" stroke=\"#f2f2f2\"/>"
            );
        }
        for &v in &self.y.ticks {
            let y = self.py(v);
            let _ = writeln!(
                svg,
                "<line x1=\"{x0}\" y1=\"{y:.1}\" x2=\"{x1}\" y2=\"{y:.1}\" stroke=\"#ddd\"/>"
            );
        }
        for &v in &self.x.ticks {
            let x = self.px(v);
            let _ = writeln!(
                svg,
                "<line x1=\"{x:.1}\" y1=\"{y0}\" x2=\"{x:.1}\" y2=\"{y1}\" stroke=\"#eee\"/>"
            );
        }
        *svg += "</g>\n";
    }

    fn curve(&self, svg: &mut String, series: &Series) {
        // Points that a log axis cannot show split the curve instead of joining across.
        let mut runs: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
        for &(x, y) in &series.points {
            if drawable(x, y) {
                if let Some(run) = runs.last_mut() {
                    run.push((self.px(x), self.py(y)));
                }
            } else if runs.last().is_some_and(|r| !r.is_empty()) {
                runs.push(Vec::new());
            }
        }
        for run in runs.iter().filter(|r| !r.is_empty()) {
            let mut points = String::new();
            for (x, y) in run {
                let _ = write!(points, "{x:.1},{y:.1} ");
            }
            let _ = writeln!(
                svg,
                "<polyline class=\"curve\" fill=\"none\" stroke=\"{}\" stroke-width=\"{}\" \
                 stroke-linejoin=\"round\" points=\"{}\"/>",
                series.colour,
                series.width,
                points.trim_end()
            );
        }
    }

    fn axes(&self, svg: &mut String, x_label: &str, y_label: &str) {
        let (x0, x1) = (LEFT, WIDTH - RIGHT);
        let (y0, y1) = (self.top, self.bottom());
        let _ = writeln!(
            svg,
            "<g class=\"axes\" stroke=\"#333\"><line x1=\"{x0}\" y1=\"{y1}\" x2=\"{x1}\" y2=\"{y1}\"/>\
             <line x1=\"{x0}\" y1=\"{y0}\" x2=\"{x0}\" y2=\"{y1}\"/></g>"
        );
        *svg += "<g class=\"ticks\" fill=\"#333\">\n";
        for &v in &self.y.minor {
            let y = self.py(v);
            let _ = writeln!(
                svg,
                "<line x1=\"{:.1}\" y1=\"{y:.1}\" x2=\"{x0}\" y2=\"{y:.1}\" stroke=\"#333\"/>",
                x0 - 3.0
            );
        }
        for &v in &self.y.ticks {
            let y = self.py(v);
            let _ = writeln!(
                svg,
                "<line x1=\"{:.1}\" y1=\"{y:.1}\" x2=\"{x0}\" y2=\"{y:.1}\" stroke=\"#333\"/>\
                 <text class=\"tick-label\" x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{}</text>",
                x0 - 6.0,
                x0 - 9.0,
                y + 4.0,
                tick_label(v)
            );
        }
        for &v in &self.x.ticks {
            let x = self.px(v);
            let _ = writeln!(
                svg,
                "<line x1=\"{x:.1}\" y1=\"{y1}\" x2=\"{x:.1}\" y2=\"{:.1}\" stroke=\"#333\"/>\
                 <text class=\"tick-label\" x=\"{x:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{}</text>",
                y1 + 6.0,
                y1 + 20.0,
                linear_tick_label(v)
            );
        }
        *svg += "</g>\n";
        let _ = writeln!(
            svg,
            "<text class=\"axis-label\" x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\" font-size=\"13\">{}</text>",
            (x0 + x1) / 2.0,
            y1 + BOTTOM - 10.0,
            escape(x_label)
        );
        let (lx, ly) = (16.0, (y0 + y1) / 2.0);
        let _ = writeln!(
            svg,
            "<text class=\"axis-label\" x=\"{lx}\" y=\"{ly:.1}\" text-anchor=\"middle\" font-size=\"13\" \
             transform=\"rotate(-90 {lx} {ly:.1})\">{}</text>",
            escape(y_label)
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: &[f64], b: &[f64]) -> bool {
        a.len() == b.len()
            && a.iter()
                .zip(b)
                .all(|(x, y)| (x - y).abs() <= 1e-12 * y.abs())
    }

    #[test]
    fn losses_over_decades_get_a_tick_per_decade() {
        // The demo's NCA loss: 0.088 to 49.8.
        let a = log_axis(0.088, 49.8);
        assert!(close(&a.ticks, &[0.01, 0.1, 1.0, 10.0, 100.0]), "{a:?}");
        assert_eq!((a.min, a.max), (0.01, 100.0));
        assert_eq!(a.minor.len(), 4 * 8);
    }

    #[test]
    fn losses_within_two_decades_get_1_2_5_ticks_just_outside_the_data() {
        // The demo's fit loss: 0.0058 to 0.23.
        let a = log_axis(0.0058, 0.23);
        assert!(
            close(&a.ticks, &[0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5]),
            "{a:?}"
        );
        assert_eq!((a.min, a.max), (0.005, 0.5));
        // Exactly on a tick: the tick is the end of the axis.
        let a = log_axis(0.1, 0.5);
        assert!(close(&a.ticks, &[0.1, 0.2, 0.5]), "{a:?}");
    }

    #[test]
    fn many_decades_thin_out_and_flat_or_bad_ranges_still_make_an_axis() {
        let a = log_axis(1e-9, 1e9);
        assert!(a.ticks.len() <= MAX_DECADE_TICKS as usize + 1, "{a:?}");
        assert!(a.ticks.len() >= 5 && a.minor.is_empty());
        let a = log_axis(0.3, 0.3);
        assert!(a.min < 0.3 && a.max > 0.3 && a.ticks.len() >= 2, "{a:?}");
        let a = log_axis(0.0, f64::NAN);
        assert!(a.min > 0.0 && a.max > a.min);
    }

    #[test]
    fn linear_ticks_step_by_1_2_5_inside_the_range() {
        let a = linear_axis(0.0, 599.0);
        assert_eq!(a.ticks, [0.0, 100.0, 200.0, 300.0, 400.0, 500.0]);
        let a = linear_axis(0.0, 1238.0);
        assert_eq!(a.ticks, [0.0, 200.0, 400.0, 600.0, 800.0, 1000.0, 1200.0]);
        let a = linear_axis(3.0, 3.0);
        assert!(a.min < 3.0 && a.max > 3.0);
    }

    #[test]
    fn tick_labels_are_short() {
        let log_axis = [
            (0.01, "0.01"),
            (100.0, "100"),
            (0.005, "0.005"),
            (1200.0, "1.2e3"),
            (1.0, "1"),
        ];
        for (value, want) in log_axis {
            assert_eq!(tick_label(value), want);
        }
        assert_eq!(linear_tick_label(1200.0), "1200");
        assert_eq!(linear_tick_label(0.5), "0.5");
    }

    #[test]
    fn the_svg_has_axes_labels_and_skips_what_a_log_axis_cannot_show() {
        let plot = LinePlot {
            x_label: "iteration".into(),
            y_label: "loss (log scale)".into(),
            description: "test".into(),
            series: vec![Series {
                label: "loss".into(),
                points: vec![(0.0, 1.0), (1.0, 0.0), (2.0, 0.1), (3.0, 0.05)],
                colour: PALETTE[0],
                width: 1.0,
            }],
        };
        let svg = plot.to_svg().unwrap();
        assert_eq!(svg.matches("class=\"axis-label\"").count(), 2);
        assert!(svg.contains(">iteration<") && svg.contains(">loss (log scale)<"));
        assert_eq!(svg.matches("<polyline").count(), 2, "split at the zero");
        let empty = LinePlot {
            series: vec![Series {
                points: vec![(0.0, 0.0)],
                ..plot.series[0].clone()
            }],
            ..plot
        };
        assert!(empty.to_svg().is_none());
    }
}
