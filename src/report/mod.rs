//! Looking at results: labelled comparison sheets (Mokume figure 18 style), captioned rows of
//! renders, and the static HTML report of a run with its parts: metrics table and legend,
//! loss plots, cuts side by side, stage timings, configs.

pub mod best;
pub mod configs;
pub mod cuts;
pub mod font;
pub mod format;
pub mod html;
pub mod legend;
pub mod loss_curves;
pub mod metrics_html;
pub mod metrics_table;
pub mod page;
pub mod plot;
pub mod sheet;
pub mod timings;
pub mod title;

pub use html::write_report;
pub(crate) use legend::TRUTH_MARK;
pub use metrics_table::MetricsTable;
pub(crate) use sheet::row_plane;
pub use sheet::{Column, SHEET_ROWS, captioned_row, comparison_sheet};
pub(crate) use timings::StageClock;
pub use timings::TIMINGS_FILE;
pub use timings::{StageTiming, Timings};
pub use title::default_title;
