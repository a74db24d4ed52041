//! `metrics.csv` and the other small CSV tables of a run folder (`loss.csv`, `timings.csv`):
//! a header and rows of equal length. Read strictly, so that a damaged file is an error
//! naming the file and the row instead of a page that silently shows the wrong numbers.

use std::path::Path;

use crate::error::{Result, XylemError};

/// A CSV table: header and rows of text fields (`metrics.csv` has `method`, `image`, then
/// one numeric column per metric).
#[derive(Clone, Debug, PartialEq)]
pub struct MetricsTable {
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

impl MetricsTable {
    /// A table of `header` and `rows` (each as long as the header).
    pub fn new(header: &[&str], rows: Vec<Vec<String>>) -> Self {
        Self {
            header: header.iter().map(|h| h.to_string()).collect(),
            rows,
        }
    }

    /// One row of fields as `Display` writes them (floats in their shortest round-trip form).
    pub fn row(values: &[&dyn std::fmt::Display]) -> Vec<String> {
        values.iter().map(|v| v.to_string()).collect()
    }

    pub fn read(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| XylemError::io(path, e))?;
        Self::parse(&text).map_err(|message| XylemError::input(path.display().to_string(), message))
    }

    /// The table in `text`; the error says what is wrong, the caller adds the file.
    pub fn parse(text: &str) -> std::result::Result<Self, String> {
        let mut lines = text.lines().filter(|l| !l.trim().is_empty());
        let header = split(lines.next().ok_or("the table is empty")?);
        let rows: Vec<Vec<String>> = lines.map(split).collect();
        if let Some(bad) = rows.iter().position(|r| r.len() != header.len()) {
            return Err(format!(
                "row {} has {} fields; the header has {}",
                bad + 2,
                rows[bad].len(),
                header.len()
            ));
        }
        Ok(Self { header, rows })
    }

    /// CSV text of the table.
    pub fn to_csv(&self) -> String {
        let mut s = self.header.join(",") + "\n";
        for row in &self.rows {
            s += &(row.join(",") + "\n");
        }
        s
    }

    /// Index of the column named `name`.
    pub fn column(&self, name: &str) -> Option<usize> {
        self.header.iter().position(|h| h == name)
    }

    /// The numbers of column `name`, or what is wrong (no such column; the row and text of
    /// a field that is not a number).
    pub fn numbers(&self, name: &str) -> std::result::Result<Vec<f64>, String> {
        let c = self.column(name).ok_or_else(|| {
            format!(
                "has no `{name}` column (columns: {})",
                self.header.join(",")
            )
        })?;
        self.rows
            .iter()
            .enumerate()
            .map(|(i, row)| {
                row[c]
                    .parse::<f64>()
                    .map_err(|_| format!("row {}: `{name}` is {:?}, not a number", i + 2, row[c]))
            })
            .collect()
    }
}

fn split(line: &str) -> Vec<String> {
    line.split(',').map(|s| s.trim().to_string()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ragged_rows_and_text_in_numeric_columns_are_named() {
        let err = MetricsTable::parse("a,b\n1,2\n3\n").unwrap_err();
        assert!(err.contains("row 3"), "{err}");
        let t = MetricsTable::parse("a,b\n1,2\n3,x\n").unwrap();
        assert_eq!(t.numbers("a").unwrap(), [1.0, 3.0]);
        let err = t.numbers("b").unwrap_err();
        assert!(err.contains("row 3") && err.contains("\"x\""), "{err}");
        assert!(t.numbers("c").unwrap_err().contains("no `c` column"));
    }
}
