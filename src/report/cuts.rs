//! The hidden cuts, truth beside each candidate at one size: the comparison the whole
//! pipeline is judged on, and one a reader cannot make from images of different sizes
//! stacked under each other. Every tile links to its full-size file.

use std::path::{Path, PathBuf};

/// Where each column's cut images are in a run folder (`{cut}` is the cut's name).
pub const CUT_COLUMNS: [(&str, &str); 4] = [
    ("truth", "sample/truth/{cut}.png"),
    ("fitted rings", "fit/cuts/{cut}_arl.png"),
    ("base colour", "fit/cuts/{cut}_base.png"),
    ("NCA", "synth/cuts/{cut}.png"),
];

/// One cut: its name and, per column of [`CUT_COLUMNS`], the image if the run has it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct CutRow {
    pub cut: String,
    pub images: Vec<Option<PathBuf>>,
}

/// The cuts of `run` (any `cutN.png` of the truth or of the synthesis), sorted by name,
/// with the columns that exist for at least one of them.
pub(crate) fn cut_rows(run: &Path) -> (Vec<&'static str>, Vec<CutRow>) {
    let mut cuts: Vec<String> = ["sample/truth", "synth/cuts"]
        .iter()
        .flat_map(|dir| cut_names(&run.join(dir)))
        .collect();
    cuts.sort_by_key(|c| natural_key(c));
    cuts.dedup();
    let rows: Vec<CutRow> = cuts
        .into_iter()
        .map(|cut| CutRow {
            images: CUT_COLUMNS
                .iter()
                .map(|(_, pattern)| {
                    let path = run.join(pattern.replace("{cut}", &cut));
                    path.is_file().then_some(path)
                })
                .collect(),
            cut,
        })
        .collect();
    let present: Vec<usize> = (0..CUT_COLUMNS.len())
        .filter(|&c| rows.iter().any(|r| r.images[c].is_some()))
        .collect();
    let columns = present.iter().map(|&c| CUT_COLUMNS[c].0).collect();
    let rows = rows
        .into_iter()
        .map(|r| CutRow {
            images: present.iter().map(|&c| r.images[c].clone()).collect(),
            cut: r.cut,
        })
        .collect();
    (columns, rows)
}

/// `cutN` for every `cutN.png` in `dir`.
fn cut_names(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .flatten()
        .filter_map(|e| e.file_name().to_str().map(str::to_string))
        .filter_map(|n| n.strip_suffix(".png").map(str::to_string))
        .filter(|n| {
            n.strip_prefix("cut")
                .is_some_and(|d| !d.is_empty() && d.chars().all(|c| c.is_ascii_digit()))
        })
        .collect()
}

/// Sorts cut2 before cut10.
fn natural_key(cut: &str) -> (usize, String) {
    (cut.len(), cut.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_per_cut_and_only_columns_that_exist() {
        let scratch = tempfile::tempdir().unwrap();
        let run = scratch.path();
        for f in [
            "sample/truth/cut1.png",
            "sample/truth/cut2.png",
            "sample/truth/cut_notes.png",
            "synth/cuts/cut1.png",
            "synth/cuts/cut10.png",
        ] {
            let p = run.join(f);
            std::fs::create_dir_all(p.parent().unwrap()).unwrap();
            std::fs::write(p, b"").unwrap();
        }
        let (columns, rows) = cut_rows(run);
        assert_eq!(columns, ["truth", "NCA"]);
        let names: Vec<&str> = rows.iter().map(|r| r.cut.as_str()).collect();
        assert_eq!(names, ["cut1", "cut2", "cut10"]);
        assert!(rows[1].images[0].is_some() && rows[1].images[1].is_none());
        assert!(rows[2].images[0].is_none() && rows[2].images[1].is_some());
    }
}
