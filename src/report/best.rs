//! Which cell of a metrics column is the best, so the page can highlight it: the reader's
//! first question is "which method wins on this image", and nine columns of numbers with
//! different directions do not answer it at a glance.
//!
//! The rule: within the rows of one reference image (`image` column), among the candidates
//! (truth rows are the ceiling, not a contender), the best value of each known metric by its
//! direction ([`Better`]); values are compared as shown (three significant digits), so cells
//! that read the same are all highlighted. A column with fewer than two comparable values
//! on an image has no winner.

use super::format::as_shown;
use super::legend::{Better, is_truth_method, metric_info};
use super::metrics_table::MetricsTable;

/// Significant digits the metrics are shown and ranked with.
pub const DIGITS: usize = 3;

/// `best[row][column]`: whether that cell is its column's best for its image.
pub(crate) fn best_cells(table: &MetricsTable) -> Vec<Vec<bool>> {
    let mut best = vec![vec![false; table.header.len()]; table.rows.len()];
    for group in image_groups(table) {
        let candidates: Vec<usize> = group
            .into_iter()
            .filter(|&r| !is_truth_row(table, r))
            .collect();
        for (c, name) in table.header.iter().enumerate() {
            let Some(info) = metric_info(name) else {
                continue;
            };
            let scored: Vec<(usize, f64)> = candidates
                .iter()
                .filter_map(|&r| Some((r, badness(table, r, c, info.better)?)))
                .collect();
            if scored.len() < 2 {
                continue;
            }
            let least = scored.iter().map(|s| s.1).fold(f64::INFINITY, f64::min);
            for (r, s) in scored {
                best[r][c] = s == least;
            }
        }
    }
    best
}

/// Row indices per reference image, in first-seen order.
fn image_groups(table: &MetricsTable) -> Vec<Vec<usize>> {
    let Some(image) = table.column("image") else {
        return vec![(0..table.rows.len()).collect()];
    };
    let mut groups: Vec<(String, Vec<usize>)> = Vec::new();
    for (r, row) in table.rows.iter().enumerate() {
        match groups.iter_mut().find(|g| g.0 == row[image]) {
            Some(g) => g.1.push(r),
            None => groups.push((row[image].clone(), vec![r])),
        }
    }
    groups.into_iter().map(|g| g.1).collect()
}

fn is_truth_row(table: &MetricsTable, row: usize) -> bool {
    table
        .column("method")
        .is_some_and(|m| is_truth_method(&table.rows[row][m]))
}

/// The value of cell (row, column) as shown, if it is a finite number.
fn shown(table: &MetricsTable, row: usize, column: usize) -> Option<f64> {
    let v: f64 = table.rows[row][column].parse().ok()?;
    v.is_finite().then(|| as_shown(v, DIGITS))
}

/// How far a cell is from perfect, lower is better; `None` when it is not ranked.
fn badness(table: &MetricsTable, row: usize, column: usize, better: Better) -> Option<f64> {
    let v = shown(table, row, column)?;
    match better {
        Better::Higher => Some(-v),
        Better::Lower => Some(v),
        Better::CloserTo(reference) => {
            let target = shown(table, row, table.column(reference)?)?;
            // Rounded again so that equal-looking distances tie exactly.
            Some(as_shown((v - target).abs(), DIGITS))
        }
        Better::Reference => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(csv: &str) -> MetricsTable {
        MetricsTable::parse(csv).unwrap()
    }

    #[test]
    fn best_follows_each_metrics_direction_per_image() {
        let t = table(
            "method,image,ring_ncc,swd,aniso,aniso_ref\n\
             nca,cut1,0.46,0.025,0.39,0.29\n\
             base colour,cut1,0.56,0.038,0.99,0.29\n\
             nca,cut2,0.44,0.027,0.41,0.72\n\
             base colour,cut2,0.52,0.039,0.99,0.72\n",
        );
        let b = best_cells(&t);
        // ring_ncc: higher; swd: lower; aniso: closer to aniso_ref (0.39 vs 0.29 on cut1,
        // 0.99 vs 0.72 on cut2); aniso_ref and the text columns are never highlighted.
        assert_eq!(b[0], [false, false, false, true, true, false]);
        assert_eq!(b[1], [false, false, true, false, false, false]);
        assert_eq!(b[2], [false, false, false, true, false, false]);
        assert_eq!(b[3], [false, false, true, false, true, false]);
    }

    #[test]
    fn values_that_read_the_same_tie_and_truth_rows_are_not_ranked() {
        let t = table(
            "method,image,swd,style\n\
             procedural (truth),cut1,0,0\n\
             nca,cut1,0.02501,0.5\n\
             base colour,cut1,0.02504,0.4\n",
        );
        let b = best_cells(&t);
        assert_eq!(b[0], [false; 4], "the truth is the ceiling, not a winner");
        assert!(
            b[1][2] && b[2][2],
            "0.0250 and 0.0250 read the same: both best"
        );
        assert!(!b[1][3] && b[2][3]);
    }

    #[test]
    fn a_lone_or_unreadable_value_has_no_winner() {
        let t = table(
            "method,image,swd,dE_mean,unknown\n\
             nca,A,0.1,NaN,1\n\
             base colour,A,0.2,x,2\n\
             nca,B,0.3,1,3\n",
        );
        let b = best_cells(&t);
        assert!(b[0][2] && !b[1][2]);
        assert!(b.iter().all(|r| !r[3] && !r[4]), "{b:?}");
        assert!(!b[2][2], "one row on image B: nothing to beat");
    }
}
