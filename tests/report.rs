//! Sheets and the HTML report: a tiny run folder is reported, then opened in headless
//! Chromium, which must load every image and find the metrics table. A page with a broken
//! image must be caught by the same check.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use xylem::Image2;
use xylem::io::save_png;
use xylem::procedural::ProceduralWood;
use xylem::report::{
    Column, MetricsTable, SHEET_ROWS, captioned_row, comparison_sheet, write_report,
};

fn chromium() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("XYLEM_CHROMIUM") {
        return Some(PathBuf::from(p));
    }
    for name in ["chromium", "chromium-browser", "google-chrome"] {
        if let Ok(out) = Command::new("which").arg(name).output()
            && out.status.success()
        {
            return Some(PathBuf::from(String::from_utf8_lossy(&out.stdout).trim()));
        }
    }
    if std::env::var_os("XYLEM_SKIP_BROWSER").is_some() {
        eprintln!("skipping the browser check: no chromium (XYLEM_SKIP_BROWSER set)");
        return None;
    }
    panic!(
        "headless Chromium not found (install Debian's `chromium`, as .ci/run does, or set XYLEM_CHROMIUM; XYLEM_SKIP_BROWSER=1 skips)"
    );
}

/// Loads `page` in headless Chromium with a script appended that reports, in the page title,
/// how many images loaded and whether the metrics table exists.
fn browser_check(browser: &Path, page: &Path) -> String {
    let html = std::fs::read_to_string(page).unwrap();
    let script = "<script>window.addEventListener('load',()=>{const i=[...document.images];\
        const ok=i.filter(x=>x.complete&&x.naturalWidth>0).length;\
        document.title='CHECK images='+ok+'/'+i.length+' table='+(document.querySelector('table#metrics tr td')?1:0);});</script>";
    let check = page.with_file_name("check.html");
    std::fs::write(&check, html.replace("</body>", &format!("{script}</body>"))).unwrap();
    let profile = common::scratch("chromium-profile");
    let out = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--allow-file-access-from-files",
            "--virtual-time-budget=10000",
            "--dump-dom",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!(
            "file://{}",
            check.canonicalize().unwrap().display()
        ))
        .output()
        .expect("run chromium");
    let _ = std::fs::remove_dir_all(&profile);
    std::fs::remove_file(&check).unwrap();
    let dom = String::from_utf8_lossy(&out.stdout).into_owned();
    let start = dom.find("<title>").map(|i| i + 7).unwrap_or(0);
    let end = dom.find("</title>").unwrap_or(start);
    dom[start..end].to_string()
}

fn tiny_run(dir: &Path) {
    let wood = ProceduralWood::new(&xylem::presets::load_species_preset("chestnut").unwrap());
    let photos: Vec<Option<Image2>> = (0..SHEET_ROWS.len())
        .map(|r| (r < 6).then(|| Image2::filled(8, 8, 3, 0.5)))
        .collect();
    let sheet = comparison_sheet(
        &[
            ("photo".into(), Column::Images(photos)),
            ("procedural".into(), Column::Texture(&wood)),
        ],
        24,
    );
    save_png(&sheet, &dir.join("sheet.png")).unwrap();
    let render = Image2::filled(20, 20, 3, 0.3);
    save_png(
        &captioned_row(&[("cube".into(), &render), ("bowl".into(), &render)]),
        &dir.join("renders/cube.png"),
    )
    .unwrap();
    save_png(&Image2::filled(30, 10, 1, 0.8), &dir.join("train/loss.png")).unwrap();
    let table = MetricsTable {
        header: vec!["method".into(), "image".into(), "swd".into()],
        rows: vec![
            vec!["nca".into(), "cut1".into(), "0.12".into()],
            vec!["base".into(), "cut1".into(), "0.30".into()],
        ],
    };
    std::fs::write(dir.join("metrics.csv"), table.to_csv()).unwrap();
}

#[test]
fn sheet_has_a_labelled_tile_per_row_and_column() {
    let wood = ProceduralWood::new(&xylem::presets::load_species_preset("oak").unwrap());
    let sheet = comparison_sheet(
        &[
            ("a".into(), Column::Texture(&wood)),
            ("b".into(), Column::Images(vec![])),
        ],
        16,
    );
    assert_eq!(sheet.height, 8 * (16 + 6) + 9 * 2 + 12);
    // Column b has no images: its tiles are the light "missing" grey, column a is wood.
    let left_a = sheet.width - 2 * (16 + 6);
    let (a, b) = (
        sheet.pixel(40, left_a + 8),
        sheet.pixel(40, left_a + 22 + 8),
    );
    assert!((b[0] - 0.85).abs() < 1e-6 || b[0] < 0.2, "missing tile");
    assert!(a != b);
    // Labels: some dark ink in the left margin.
    let ink = (0..sheet.height)
        .filter(|&r| sheet.pixel(r, 8)[0] < 0.2)
        .count();
    assert!(ink > 0, "row labels missing");
}

#[test]
fn report_opens_in_headless_chromium_with_every_image() {
    let dir = common::scratch("report");
    tiny_run(&dir);
    let page = dir.join("report/index.html");
    let images = write_report(&dir, &page, "test run").unwrap();
    assert_eq!(images, 3);
    let html = std::fs::read_to_string(&page).unwrap();
    assert!(
        html.contains("src=\"../renders/cube.png\"") && html.contains("<table id=\"metrics\">"),
        "{html}"
    );
    let Some(browser) = chromium() else { return };
    assert_eq!(browser_check(&browser, &page), "CHECK images=3/3 table=1");
    // The check itself must catch a broken image.
    std::fs::remove_file(dir.join("train/loss.png")).unwrap();
    assert_eq!(browser_check(&browser, &page), "CHECK images=2/3 table=1");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_metrics_tables_are_clear_errors() {
    let dir = common::scratch("metrics");
    std::fs::create_dir_all(&dir).unwrap();
    // Issue 16 item 11: a folder without run outputs (e.g. a sample) is not reported on.
    let err = write_report(&dir, &dir.join("r/index.html"), "x")
        .unwrap_err()
        .to_string();
    assert!(err.contains("no run outputs"), "{err}");
    assert!(!dir.join("r/index.html").exists());
    std::fs::write(dir.join("metrics.csv"), "method,image,swd\nnca,cut1\n").unwrap();
    let err = write_report(&dir, &dir.join("r/index.html"), "x")
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("metrics.csv") && err.contains("row 2"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
