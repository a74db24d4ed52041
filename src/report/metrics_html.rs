//! The metrics table as a reader needs it: three significant digits, the direction of each
//! metric in its header, the best value per column and image highlighted, and a legend that
//! says what each metric measures, so the page can be judged without `src/metrics/`.

use std::fmt::Write;

use super::best::{DIGITS, best_cells};
use super::format::significant;
use super::legend::{METRICS, is_truth_method, metric_info};
use super::metrics_table::MetricsTable;
use super::page::{Page, escape};
use crate::run_folder::{METRICS_CSV, PHASE_CSV};

/// The metrics table, its legend and links to the CSV files.
pub(super) fn metrics_section(page: &mut Page, table: &MetricsTable) {
    page.section("metrics", "Metrics");
    page.push(&metrics_table_html(table));
    page.push(&legend_html(table));
    let mut files = vec![page.file_link(&page.run().join(METRICS_CSV))];
    let phase = page.run().join(PHASE_CSV);
    if phase.is_file() {
        files.push(format!(
            "{} (pore density by ring phase)",
            page.file_link(&phase)
        ));
    }
    page.push(&format!(
        "<p class=\"meta\">Full precision: {}</p>\n",
        files.join(", ")
    ));
}

/// The table: numbers with [`DIGITS`] significant digits, best cells marked `best`, the
/// first row of each reference image marked so the groups read apart, truth rows marked.
pub(crate) fn metrics_table_html(table: &MetricsTable) -> String {
    let best = best_cells(table);
    let image = table.column("image");
    let method = table.column("method");
    let mut html = String::from("<div class=\"scroll\"><table id=\"metrics\">\n<tr>");
    for name in &table.header {
        match metric_info(name) {
            Some(info) => {
                let _ = write!(
                    html,
                    "<th title=\"{}: {}\">{}</th>",
                    escape(info.meaning),
                    info.better.words(),
                    format!("{} {}", escape(name), info.better.arrow()).trim_end()
                );
            }
            None => {
                let _ = write!(html, "<th>{}</th>", escape(name));
            }
        }
    }
    html += "</tr>\n";
    let mut previous_image: Option<&str> = None;
    for (r, row) in table.rows.iter().enumerate() {
        let mut classes = Vec::new();
        if let Some(i) = image {
            if previous_image.is_some_and(|p| p != row[i]) {
                classes.push("first-of-image");
            }
            previous_image = Some(&row[i]);
        }
        if method.is_some_and(|m| is_truth_method(&row[m])) {
            classes.push("truth");
        }
        if classes.is_empty() {
            html += "<tr>";
        } else {
            let _ = write!(html, "<tr class=\"{}\">", classes.join(" "));
        }
        for (c, cell) in row.iter().enumerate() {
            html += &cell_html(cell, best[r][c]);
        }
        html += "</tr>\n";
    }
    html + "</table></div>\n"
}

fn cell_html(cell: &str, best: bool) -> String {
    let Ok(value) = cell.parse::<f64>() else {
        return format!("<td>{}</td>", escape(cell));
    };
    let class = if best { "num best" } else { "num" };
    format!(
        "<td class=\"{class}\" title=\"{}\">{}</td>",
        escape(cell),
        significant(value, DIGITS)
    )
}

/// What each metric column of `table` means and which way is better, then how to read the
/// rows.
pub(crate) fn legend_html(table: &MetricsTable) -> String {
    let mut html = String::from(
        "<table id=\"metrics-legend\" class=\"legend\"><tr><th>metric</th><th>better</th>\
         <th>perfect</th><th>what it measures</th></tr>\n",
    );
    for info in METRICS.iter().filter(|m| table.column(m.name).is_some()) {
        let _ = writeln!(
            html,
            "<tr><td><code>{}</code>&nbsp;{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            info.name,
            info.better.arrow(),
            info.better.words(),
            escape(info.perfect),
            escape(info.meaning)
        );
    }
    html += "</table>\n<p class=\"meta\">Highlighted: the best value of each column among the \
             methods compared on the same image, as shown (ties are all highlighted). \
             Images: <code>cutN</code> are cuts through the synthetic sample's truth that \
             neither the fit nor the training saw; <code>X (held out)</code> are photos of \
             faces left out with <code>--faces</code>; <code>X (trained)</code> are photos of \
             the faces trained on (how well a method reproduces its own targets, not how well \
             it predicts).";
    let method = table.column("method");
    if method.is_some_and(|m| table.rows.iter().any(|r| is_truth_method(&r[m]))) {
        html += " Rows in grey italics compare the truth with itself (up to the rounding of \
                 its 8-bit images): the best each metric can read on that image; they are not \
                 ranked.";
    }
    html + "</p>\n"
}
