//! Sheets and the HTML report: a tiny run folder is reported, then opened in headless
//! Chromium, which must load every image and find every part a reader needs (metrics with
//! legend and highlighted best cells, loss plots with labelled axes, cuts side by side at
//! one size, timings, configs), with no absolute path in the page; a screenshot of it must
//! be a real picture. A page with a broken image must be caught by the same check.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use xylem::Image2;
use xylem::io::save_png;
use xylem::procedural::ProceduralWood;
use xylem::report::{
    Column, MetricsTable, SHEET_ROWS, StageTiming, TIMINGS_FILE, Timings, captioned_row,
    comparison_sheet, default_title, write_report,
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

/// Headless Chromium on `page` with `extra` arguments (`--dump-dom`, `--screenshot=..`);
/// returns stdout.
fn run_chromium(browser: &Path, page: &Path, extra: &[String]) -> String {
    let profile = common::scratch(&format!(
        "chromium-profile-{}",
        page.file_stem().unwrap().to_string_lossy()
    ));
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
            "--hide-scrollbars",
            "--virtual-time-budget=10000",
        ])
        .args(extra)
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("file://{}", page.canonicalize().unwrap().display()))
        .output()
        .expect("run chromium");
    let _ = std::fs::remove_dir_all(&profile);
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// What the loaded page holds, written by a script into the title: images loaded / all,
/// SVG plots with both axis labels and tick labels, legend rows, highlighted cells, config
/// blocks, timing rows, and the distinct rendered sizes of the cut tiles.
const PROBE: &str = "<script>window.addEventListener('load',()=>{\
    const q=s=>[...document.querySelectorAll(s)];const i=q('img');\
    const ok=i.filter(x=>x.complete&&x.naturalWidth>0).length;\
    const plots=q('svg.plot').filter(s=>s.querySelectorAll('text.axis-label').length==2&&s.querySelectorAll('text.tick-label').length>=4&&s.querySelector('polyline')).length;\
    const sizes=[...new Set(q('table.cuts img').map(x=>{const r=x.getBoundingClientRect();return r.width+'x'+r.height;}))].join('+');\
    document.title='CHECK images='+ok+'/'+i.length+' table='+q('table#metrics tr td').length\
    +' plots='+plots+' legend='+q('#metrics-legend tr td code').length+' best='+q('#metrics td.best').length\
    +' details='+q('details pre').length+' timings='+q('#timings td').length+' cuts='+sizes;});</script>";

/// Loads `page` with [`PROBE`] appended and returns what it found.
fn browser_check(browser: &Path, page: &Path) -> String {
    let html = std::fs::read_to_string(page).unwrap();
    let check = page.with_file_name("check.html");
    std::fs::write(&check, html.replace("</body>", &format!("{PROBE}</body>"))).unwrap();
    let dom = run_chromium(browser, &check, &["--dump-dom".into()]);
    std::fs::remove_file(&check).unwrap();
    let start = dom.find("<title>").map(|i| i + 7).unwrap_or(0);
    let end = dom.find("</title>").unwrap_or(start);
    dom[start..end].to_string()
}

fn write(path: &Path, text: &str) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, text).unwrap();
}

/// A run folder with one of everything the report shows, written the way `xylem run`
/// writes it (tiny images).
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
    // The cuts come in different sizes (truth at the sample's size, the NCA's at its grid):
    // the page must show them at one size.
    save_png(
        &Image2::filled(32, 32, 3, 0.6),
        &dir.join("sample/truth/cut1.png"),
    )
    .unwrap();
    save_png(
        &Image2::filled(16, 16, 3, 0.4),
        &dir.join("synth/cuts/cut1.png"),
    )
    .unwrap();
    save_png(
        &Image2::filled(24, 24, 3, 0.5),
        &dir.join("fit/cuts/cut1_base.png"),
    )
    .unwrap();
    let table = MetricsTable {
        header: ["method", "image", "ring_ncc", "swd", "aniso", "aniso_ref"]
            .map(String::from)
            .to_vec(),
        rows: [
            ["nca", "cut1", "0.46323064", "0.12", "0.39", "0.29"],
            ["base colour", "cut1", "0.55566174", "0.30", "0.99", "0.29"],
            ["procedural (truth)", "cut1", "1", "0", "0.29", "0.29"],
        ]
        .map(|r| r.map(String::from).to_vec())
        .to_vec(),
    };
    std::fs::write(dir.join("metrics.csv"), table.to_csv()).unwrap();
    let mut train_loss = String::from("iteration,steps,loss,style,overflow,learning_rate\n");
    for i in 0..120 {
        let loss = 10.0 * (-(i as f64) / 30.0).exp() * (1.0 + 0.3 * ((i * 7 % 5) as f64));
        train_loss += &format!("{i},12,{loss},{loss},0,0.001\n");
    }
    write(&dir.join("train/loss.csv"), &train_loss);
    let mut fit_loss = String::from("stage,iteration,total,iso,image,smooth\n");
    for (stage, n, scale) in [
        ("pith", 40, 0.01),
        ("distortion", 30, 0.2),
        ("colour", 10, 0.04),
    ] {
        for i in 0..n {
            fit_loss += &format!("{stage},{i},{},0,0,0\n", scale / (1.0 + i as f64 * 0.05));
        }
    }
    write(&dir.join("fit/loss.csv"), &fit_loss);
    // Configs as the pipeline copies them: with the absolute paths of this machine.
    let abs = dir.canonicalize().unwrap();
    write(
        &dir.join("run.toml"),
        &format!(
            "[inputs]\nsample = \"{}\"\nfaces = \"A,B,C,D,E,F\"\n",
            abs.parent().unwrap().join("mokume/CN03-test").display()
        ),
    );
    write(
        &dir.join("nca_quick.toml"),
        "# The demo's NCA <quick> & small\nseed = 1\n",
    );
    write(
        &dir.join("train/train.toml"),
        &format!(
            "# Config used by xylem 0.1.0 (from {}).\nseed = 1\n",
            abs.join("nca_quick.toml").display()
        ),
    );
    write(&dir.join("fit/config.toml"), "[pith]\nrefine = 4\n");
    let mut timings = Timings::default();
    for (stage, seconds, skipped) in [
        ("fit", 95.0, false),
        ("train", 0.01, true),
        ("report", 0.02, false),
    ] {
        timings.record(
            StageTiming {
                stage: stage.into(),
                seconds,
                peak_mb: Some(512.0),
                skipped,
            },
            None,
        );
    }
    std::fs::write(dir.join(TIMINGS_FILE), timings.to_csv()).unwrap();
}

/// Every `src`/`href` value of the page.
fn links(html: &str) -> Vec<&str> {
    ["src=\"", "href=\""]
        .iter()
        .flat_map(|attr| html.split(attr).skip(1))
        .map(|rest| &rest[..rest.find('"').unwrap()])
        .collect()
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
fn report_opens_in_headless_chromium_with_every_part() {
    let dir = common::scratch("report");
    tiny_run(&dir);
    let page = dir.join("report/index.html");
    let title = default_title(&dir);
    assert_eq!(title, "xylem run: CN03-test");
    let images = write_report(&dir, &page, &title).unwrap();
    // sheet, render, train/loss.png and three cut tiles.
    assert_eq!(images, 6);
    let html = std::fs::read_to_string(&page).unwrap();
    // Relative paths only: no folder of this machine, every link inside the run folder.
    let abs = dir.canonicalize().unwrap();
    let temp = std::env::temp_dir().canonicalize().unwrap();
    for forbidden in [
        temp.to_str().unwrap(),
        abs.to_str().unwrap(),
        dir.to_str().unwrap(),
        "file:",
    ] {
        assert!(!html.contains(forbidden), "{forbidden} in the page");
    }
    for link in links(&html) {
        assert!(
            !link.starts_with('/') && (link.starts_with("../") || link.starts_with('#')),
            "{link}"
        );
    }
    // The config copies' paths are shortened, their text escaped; the version is named.
    assert!(html.contains("(from RUN/nca_quick.toml)"), "{html}");
    assert!(html.contains("sample = &quot;\u{2026}/mokume/CN03-test&quot;"));
    assert!(html.contains("&lt;quick&gt; &amp; small"));
    assert!(html.contains(env!("CARGO_PKG_VERSION")) && html.contains("git commit"));
    assert!(html.contains("<title>xylem run: CN03-test</title>"));
    // Three significant digits, the full value in the tooltip.
    assert!(html.contains(">0.463</td>") && html.contains("title=\"0.46323064\""));
    // The same folder gives the same page.
    write_report(&dir, &page, &title).unwrap();
    assert_eq!(std::fs::read_to_string(&page).unwrap(), html);

    let Some(browser) = chromium() else { return };
    // 6 images; 3 rows x 6 cells; 2 plots; 4 legend entries (the table's metrics); best:
    // ring_ncc of base colour, swd and aniso of nca (the truth row is not ranked, aniso_ref
    // is no score); 4 configs; 3 timing rows x 4 cells; one size for every cut tile.
    assert_eq!(
        browser_check(&browser, &page),
        "CHECK images=6/6 table=18 plots=2 legend=4 best=3 details=4 timings=12 cuts=220x220"
    );
    screenshot_is_a_picture(&browser, &page);
    // The check itself must catch a broken image.
    std::fs::remove_file(dir.join("train/loss.png")).unwrap();
    assert!(
        browser_check(&browser, &page).starts_with("CHECK images=5/6 "),
        "a missing image must show"
    );
}

/// A 1200 x 2000 screenshot of the page: a PNG of that size with text, tables and images
/// on it, not a blank or single-colour page.
fn screenshot_is_a_picture(browser: &Path, page: &Path) {
    let shot = page.with_file_name("screenshot.png");
    run_chromium(
        browser,
        page,
        &[
            format!("--screenshot={}", shot.display()),
            "--window-size=1200,2000".into(),
        ],
    );
    let img = image::open(&shot)
        .unwrap_or_else(|e| panic!("{}: {e}", shot.display()))
        .to_luma8();
    assert_eq!(img.dimensions(), (1200, 2000));
    let pixels: Vec<f64> = img.pixels().map(|p| p.0[0] as f64).collect();
    let mean = pixels.iter().sum::<f64>() / pixels.len() as f64;
    let dark = pixels.iter().filter(|&&v| v < 100.0).count();
    let levels: std::collections::BTreeSet<u8> = img.pixels().map(|p| p.0[0]).collect();
    assert!(
        dark > 2000 && levels.len() > 32 && mean > 100.0,
        "blank screenshot? mean {mean}, {dark} dark pixels, {} grey levels",
        levels.len()
    );
    std::fs::remove_file(&shot).unwrap();
}

#[test]
fn bad_metrics_tables_are_clear_errors() {
    let dir = common::scratch_dir("metrics");
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
    common::assert_names(&err, &["metrics.csv", "row 2"]);
}

/// A damaged loss or timings file costs its own part of the page, named in a note, not the
/// page; a run without timings says so.
#[test]
fn damaged_side_files_become_notes() {
    let dir = common::scratch_dir("notes");
    std::fs::write(dir.join("metrics.csv"), "method,image,swd\nnca,cut1,0.1\n").unwrap();
    let page = dir.join("report/index.html");
    write_report(&dir, &page, "x").unwrap();
    let html = std::fs::read_to_string(&page).unwrap();
    assert!(html.contains("Timings were not recorded"), "{html}");
    write(
        &dir.join("train/loss.csv"),
        "iteration,loss\n0,1.5\n1,oops\n",
    );
    write(&dir.join("fit/loss.csv"), "stage,iteration,total\npith,0\n");
    std::fs::write(dir.join(TIMINGS_FILE), "stage,seconds\nfit,1\n").unwrap();
    write_report(&dir, &page, "x").unwrap();
    let html = std::fs::read_to_string(&page).unwrap();
    assert!(
        html.contains("RUN/train/loss.csv: row 3: `loss` is &quot;oops&quot;"),
        "{html}"
    );
    assert!(html.contains("RUN/fit/loss.csv") && html.contains("row 2 has 2 fields"));
    assert!(html.contains("timings.csv") && html.contains("expected the columns"));
    assert!(!html.contains(dir.canonicalize().unwrap().to_str().unwrap()));
}
