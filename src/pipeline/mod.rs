//! The pipeline as a library: each stage of `xylem run` (fit, train, synth, then the sheet,
//! renders, metrics and report) as a function on its folder with its options as a plain
//! struct, the whole run on a [`RunLayout`] with resume and provenance, and the demo. The
//! command line only parses arguments into these options and shows the [`Reporter`]'s
//! output; library users pass [`Quiet`] or their own reporter.

mod compared;
mod demo;
mod fit_stage;
mod metrics;
mod procedural_step;
mod reporter;
mod run;
mod run_images;
mod run_options;
mod run_record;
mod stage_log;
mod synth_stage;
mod train_stage;

pub use crate::run_folder::RunLayout;
pub use demo::{DemoOptions, demo};
pub use fit_stage::{FitOptions, fit_into};
pub use metrics::metrics_table;
pub use reporter::{Counter, Quiet, Reporter};
pub use run::{RunOutcome, run};
pub use run_options::{NcaSource, RunOptions};
pub use synth_stage::{SynthStageOptions, synth_into};
pub use train_stage::{TrainStageOptions, TrainStart, train_into};
