//! The run folder of `xylem run` and `xylem demo`: the one list of its file and folder names,
//! shared by the pipeline that writes it and the report that reads it. It stands below both
//! (it needs only `std`), so neither imports the other to agree on a name.

use std::path::{Path, PathBuf};

/// The fit stage's folder (`xylem fit` output).
pub(crate) const FIT_DIR: &str = "fit";
/// The training stage's folder (`xylem train` output).
pub(crate) const TRAIN_DIR: &str = "train";
/// The synthesis stage's folder (`xylem synth` output).
pub(crate) const SYNTH_DIR: &str = "synth";
/// The stage folders whose results a re-run reuses, in pipeline order.
pub(crate) const STAGE_DIRS: [&str; 3] = [FIT_DIR, TRAIN_DIR, SYNTH_DIR];
/// What the run folder was made with, compared on every re-run.
pub(crate) const RUN_RECORD: &str = "run.toml";
/// Written into a stage folder after its last output: the stage is complete.
pub(crate) const DONE_MARKER: &str = ".done";
/// The comparison sheet (rows: faces and cuts; columns: reference and methods).
pub(crate) const SHEET_PNG: &str = "sheet.png";
/// Reference faces and the NCA's, unfolded side by side.
pub(crate) const UNFOLDED_PNG: &str = "unfolded.png";
/// The metrics table of every method against every fair reference.
pub(crate) const METRICS_CSV: &str = "metrics.csv";
/// Pore density by ring phase.
pub(crate) const PHASE_CSV: &str = "phase.csv";
/// Wall time and peak memory of each stage.
pub const TIMINGS_CSV: &str = "timings.csv";
/// The report page.
pub(crate) const REPORT_PAGE: &str = "report/index.html";

/// Paths inside one run folder.
#[derive(Clone, Debug)]
pub struct RunLayout {
    root: PathBuf,
}

impl RunLayout {
    pub fn new(root: impl Into<PathBuf>) -> Self {
        Self { root: root.into() }
    }

    pub fn root(&self) -> &Path {
        &self.root
    }

    /// Any path under the root.
    pub fn path(&self, relative: impl AsRef<Path>) -> PathBuf {
        self.root.join(relative)
    }

    /// The synthetic sample `xylem demo` writes (and runs on).
    pub(crate) fn demo_sample(&self) -> PathBuf {
        self.path("sample")
    }

    pub(crate) fn fit_dir(&self) -> PathBuf {
        self.path(FIT_DIR)
    }

    /// The fitted field and base colour.
    pub fn fit_file(&self) -> PathBuf {
        self.fit_dir().join("fit.toml")
    }

    pub(crate) fn train_dir(&self) -> PathBuf {
        self.path(TRAIN_DIR)
    }

    pub(crate) fn synth_dir(&self) -> PathBuf {
        self.path(SYNTH_DIR)
    }

    /// The NCA's colour volume.
    pub fn volume(&self) -> PathBuf {
        self.synth_dir().join("volume.npy")
    }

    /// The copy of a built-in NCA config the training was given.
    pub(crate) fn preset_copy(&self, preset: &str) -> PathBuf {
        self.path(format!("nca_{preset}.toml"))
    }

    pub fn record(&self) -> PathBuf {
        self.path(RUN_RECORD)
    }

    pub fn sheet(&self) -> PathBuf {
        self.path(SHEET_PNG)
    }

    pub fn unfolded(&self) -> PathBuf {
        self.path(UNFOLDED_PNG)
    }

    /// A render row (`cubes.png`, `bowls.png`, `turntable_nca.png`).
    pub fn render(&self, name: &str) -> PathBuf {
        self.path("renders").join(name)
    }

    pub fn metrics(&self) -> PathBuf {
        self.path(METRICS_CSV)
    }

    pub fn phase(&self) -> PathBuf {
        self.path(PHASE_CSV)
    }

    pub fn report_page(&self) -> PathBuf {
        self.path(REPORT_PAGE)
    }
}
