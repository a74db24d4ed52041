//! The metrics table of a run (`metrics.csv`): every method's image against every reference
//! the sample offers, with the metrics of `xylem compare`.
//!
//! References, in order of value: the true cuts of a synthetic sample (`truth/cut1.png`,
//! `cut2.png`: hidden from fit and training), then the photos of held-out faces (faces left
//! out with `--faces`), and, when neither exists, the photos of the faces trained on (marked
//! "(trained)": they show how well the method reproduces its own targets, not how well it
//! predicts).
//!
//! Methods: every column of the sheet that is a candidate (NCA, base colour, procedural).
//! On a synthetic sample the procedural texture is the truth itself; its rows are kept,
//! named "procedural (truth)", because they show the best each metric can read on that
//! image (the report does not rank them).

use std::path::Path;

use burn::tensor::Device;

use crate::Result;
use crate::field::{FieldConfig, GrowthField, base_colour_as_seen};
use crate::frame::{Face, Plane};
use crate::image2::Image2;
use crate::io::load_rgb;
use crate::loss::LossConfig;
use crate::metrics::phase_density::{PhaseDensity, curve_correlation, curve_slope};
use crate::metrics::{Comparer, METRIC_NAMES};
use crate::report::{MetricsTable, SHEET_ROWS, TRUTH_MARK, row_plane};
use crate::slice::slice_plane;
use crate::texture::SolidTexture;

/// One reference image and the plane it shows.
struct Reference {
    name: String,
    image: Image2,
    plane: Plane,
    face: Option<Face>,
}

fn references(sample: &Path, trained: &[Face]) -> Result<Vec<Reference>> {
    let mut refs = Vec::new();
    for (name, plane) in [("cut1", Plane::cut1()), ("cut2", Plane::cut2())] {
        let path = sample.join(format!("truth/{name}.png"));
        if path.is_file() {
            refs.push(Reference {
                name: name.into(),
                image: load_rgb(&path)?,
                plane,
                face: None,
            });
        }
    }
    let held_out: Vec<Face> = Face::ALL
        .into_iter()
        .filter(|f| !trained.contains(f))
        .collect();
    let (faces, suffix) = match (refs.is_empty(), held_out.is_empty()) {
        (_, false) => (held_out, " (held out)"),
        (true, true) => (trained.to_vec(), " (trained)"),
        (false, true) => (vec![], ""),
    };
    for face in faces {
        let image = load_rgb(&sample.join(format!("{face}_col.png")))?;
        refs.push(Reference {
            name: format!("{face}{suffix}"),
            image,
            plane: Plane::face(face),
            face: Some(face),
        });
    }
    Ok(refs)
}

/// The metrics table of a run whose fit, synthesis and procedural texture are given; the
/// comparison's features are computed on `device`.
pub fn metrics_table(
    sample: &Path,
    trained: &[Face],
    fit: &FieldConfig,
    procedural: &dyn SolidTexture,
    nca: &dyn SolidTexture,
    device: &Device,
) -> Result<MetricsTable> {
    let comparer = Comparer::new(&LossConfig::default_config(), device);
    let field = GrowthField::from_config(fit);
    let colour = fit.base_colour.clone();
    let mut header = vec!["method".to_string(), "image".to_string()];
    header.extend(METRIC_NAMES.iter().map(|s| s.to_string()));
    let procedural_name = &procedural_method(sample);
    let mut rows = Vec::new();
    for reference in references(sample, trained)? {
        let base = colour.clone().map(|c| {
            base_colour_as_seen(&field, c, reference.face.filter(|f| trained.contains(f)))
        });
        let mut methods: Vec<(&str, &dyn SolidTexture)> = vec![("nca", nca)];
        if let Some(b) = &base {
            methods.push(("base colour", b));
        }
        methods.push((procedural_name, procedural));
        let (w, h) = (reference.image.width, reference.image.height);
        for (method, texture) in methods {
            let candidate = slice_plane(texture, &reference.plane, w, h);
            let metrics = comparer.compare(&reference.image, &candidate)?;
            let mut row = vec![method.to_string(), reference.name.clone()];
            row.extend(metrics.csv_fields());
            rows.push(row);
        }
    }
    Ok(MetricsTable { header, rows })
}

/// The procedural texture's method name: on a synthetic sample (one with
/// `truth/species.toml`) it is the truth and says so.
fn procedural_method(sample: &Path) -> String {
    if sample.join("truth/species.toml").is_file() {
        format!("procedural {TRUTH_MARK}")
    } else {
        "procedural".into()
    }
}

/// Phase bins of the pore-density curves.
const PHASE_BINS: usize = 10;

/// Pore density by ring phase (`phase.csv`): the curve of the sample's photos (all its faces
/// pooled), and for every sheet row the curve of each texture with its correlation to the
/// photos' curve and its slope on it (`curve_slope`: how strong its pore bands are);
/// `reference` is the sheet's reference column (photos of the faces, true cuts of a
/// synthetic sample, in `SHEET_ROWS` order). The ring phase everywhere is the fitted field's.
pub(crate) fn phase_table(
    reference: &[Option<Image2>],
    fit: &FieldConfig,
    textures: &[(&str, &dyn SolidTexture)],
    size: usize,
) -> Result<MetricsTable> {
    let field = GrowthField::from_config(fit);
    let g_map = |plane: &Plane| slice_plane(&field, plane, size, size);
    let is_face = |row: &str| Face::parse(row).is_some();
    let mut photos = PhaseDensity::new(PHASE_BINS);
    for (i, name) in SHEET_ROWS.iter().enumerate() {
        if let (true, Some(photo)) = (is_face(name), &reference[i]) {
            photos.add(photo, &g_map(&row_plane(i)))?;
        }
    }
    let photo_curve = photos.curve();
    let mut header = vec![
        "method".to_string(),
        "image".to_string(),
        "corr".to_string(),
        "slope".to_string(),
    ];
    header.extend((0..PHASE_BINS).map(|b| format!("bin{b}")));
    let row = |method: &str, image: &str, curve: &[f32]| {
        let mut r = vec![
            method.to_string(),
            image.to_string(),
            curve_correlation(curve, &photo_curve).to_string(),
            curve_slope(curve, &photo_curve).to_string(),
        ];
        r.extend(curve.iter().map(|v| v.to_string()));
        r
    };
    let mut rows = vec![row("photos", "all faces", &photo_curve)];
    for (i, name) in SHEET_ROWS.iter().enumerate() {
        let g = g_map(&row_plane(i));
        if let (false, Some(truth)) = (is_face(name), &reference[i]) {
            let mut d = PhaseDensity::new(PHASE_BINS);
            d.add(truth, &g)?;
            rows.push(row("truth", name, &d.curve()));
        }
        for (method, texture) in textures {
            let mut d = PhaseDensity::new(PHASE_BINS);
            d.add(&slice_plane(*texture, &row_plane(i), size, size), &g)?;
            rows.push(row(method, name, &d.curve()));
        }
    }
    Ok(MetricsTable { header, rows })
}
