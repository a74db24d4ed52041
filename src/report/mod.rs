//! Looking at results: labelled comparison sheets (Mokume figure 18 style), captioned rows of
//! renders, and the static HTML report of a run.

pub mod font;
pub mod html;
pub mod sheet;

pub use html::{MetricsTable, write_report};
pub use sheet::{Column, SHEET_ROWS, captioned_row, comparison_sheet, row_plane};
