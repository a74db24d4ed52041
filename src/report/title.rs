//! The page's default title, naming the sample: a reader with several reports open in tabs
//! tells them apart by it. It comes from the run folder alone (`run.toml`), so that `xylem
//! run` and a later `xylem report` on the same folder write the same page.

use std::path::Path;

use crate::run_folder::RUN_RECORD;

/// "xylem run: CN03" from the sample folder `run.toml` records (its last component); a
/// demo, whose sample is the run's own `sample/` folder written from a species preset,
/// is "xylem demo: chestnut". Without a readable record: "xylem run: " and the run
/// folder's name.
pub fn default_title(run: &Path) -> String {
    let folder_name = |p: &Path| {
        p.file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "run".into())
    };
    let Some(sample) = recorded_sample(run) else {
        let run = run.canonicalize().unwrap_or_else(|_| run.to_path_buf());
        return format!("xylem run: {}", folder_name(&run));
    };
    let name = folder_name(Path::new(&sample));
    if name == "sample"
        && let Some(species) = demo_species(run)
    {
        return format!("xylem demo: {species}");
    }
    format!("xylem run: {name}")
}

/// `[inputs] sample` of `RUN/run.toml`.
fn recorded_sample(run: &Path) -> Option<String> {
    let text = std::fs::read_to_string(run.join(RUN_RECORD)).ok()?;
    let record: toml::Table = toml::from_str(&text).ok()?;
    Some(record.get("inputs")?.get("sample")?.as_str()?.to_string())
}

/// The species name of the synthetic sample inside the run folder (a demo's).
fn demo_species(run: &Path) -> Option<String> {
    let text = std::fs::read_to_string(run.join("sample/truth/species.toml")).ok()?;
    let species: toml::Table = toml::from_str(&text).ok()?;
    Some(species.get("name")?.as_str()?.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn titles_name_the_sample_or_the_demo_species() {
        let scratch = tempfile::Builder::new()
            .prefix("xylem-title-")
            .tempdir()
            .unwrap();
        let run = scratch.path();
        std::fs::create_dir_all(run.join("sample/truth")).unwrap();
        assert!(default_title(run).starts_with("xylem run: xylem-title-"));
        std::fs::write(
            run.join("run.toml"),
            "[inputs]\nsample = \"/data/mokume/CN03\"\nfaces = \"A\"\n",
        )
        .unwrap();
        assert_eq!(default_title(run), "xylem run: CN03");
        std::fs::write(
            run.join("run.toml"),
            "[inputs]\nsample = \"/old/place/demo/sample\"\n",
        )
        .unwrap();
        assert_eq!(default_title(run), "xylem run: sample");
        std::fs::write(
            run.join("sample/truth/species.toml"),
            "name = \"chestnut\"\n",
        )
        .unwrap();
        assert_eq!(default_title(run), "xylem demo: chestnut");
        std::fs::write(run.join("run.toml"), "not toml [").unwrap();
        assert!(default_title(run).starts_with("xylem run: xylem-title-"));
    }
}
