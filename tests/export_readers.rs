//! Exports opened by the tools people use, not by our own parser: VTK's `vtkNrrdReader`
//! (ParaView), SimpleITK (the reader of 3D Slicer), pynrrd, and Mitsuba 3 rendering the
//! exported scene. Each test needs a Python with the reader (see `common::python_with`);
//! `.ci/run` installs them all and sets `XYLEM_EXTERNAL_READERS=required`.

mod common;

use glam::Vec3;
use xylem::Volume;
use xylem::export::{Format, SceneSize, Values, export, export_scene};
use xylem::render::{RenderConfig, Shape, render};
use xylem::series::pearson;
use xylem::texture::SolidTexture;

/// Colour that encodes the voxel index, so a swapped or flipped axis shows: (i/(nx-1),
/// j/(ny-1), k/(nz-1)) in a volume of distinct sizes per axis.
fn index_colour(dims: [usize; 3]) -> Volume {
    let mut v = Volume::zeros(dims, 3);
    for i in 0..dims[0] {
        for j in 0..dims[1] {
            for k in 0..dims[2] {
                let o = v.offset(i, j, k);
                v.data[o] = i as f32 / (dims[0] - 1) as f32;
                v.data[o + 1] = j as f32 / (dims[1] - 1) as f32;
                v.data[o + 2] = k as f32 / (dims[2] - 1) as f32;
            }
        }
    }
    v
}

const DIMS: [usize; 3] = [5, 7, 9];
/// An asymmetric voxel and its colour.
const PROBE: [usize; 3] = [3, 1, 6];

fn probe_colour() -> [f32; 3] {
    [3.0 / 4.0, 1.0 / 6.0, 6.0 / 8.0]
}

fn write_nrrd(name: &str) -> (common::Scratch, std::path::PathBuf) {
    let dir = common::scratch(name);
    let path = dir.join("wood.nrrd");
    let volume = index_colour(DIMS);
    export(&volume, Values::Colour, Format::Nrrd, &path, "index colour").unwrap();
    (dir, path)
}

/// A Python with the reader `module` (None: skip the test) and the index-colour volume
/// exported as NRRD into the scratch folder `name` (kept while the guard lives).
fn nrrd_and_reader(
    module: &str,
    name: &str,
) -> Option<(std::path::PathBuf, common::Scratch, std::path::PathBuf)> {
    let python = common::python_with(module)?;
    let (dir, path) = write_nrrd(name);
    Some((python, dir, path))
}

/// The lines a reader's `script` prints for the volume at `path`, given the probe voxel's
/// indices as its arguments 2 to 4.
fn read_at_probe(python: &std::path::Path, script: &str, path: &std::path::Path) -> Vec<String> {
    let p = PROBE.map(|v| v.to_string());
    common::run_python(
        python,
        script,
        &[path.to_str().unwrap(), &p[0], &p[1], &p[2]],
    )
    .lines()
    .map(str::to_string)
    .collect()
}

fn floats(line: &str) -> Vec<f32> {
    line.split_whitespace()
        .map(|s| s.parse().unwrap_or_else(|_| panic!("not a number: {s}")))
        .collect()
}

fn assert_close(got: &[f32], want: &[f32], tol: f32, what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: {got:?} vs {want:?}");
    for (g, w) in got.iter().zip(want) {
        assert!((g - w).abs() <= tol, "{what}: got {got:?}, want {want:?}");
    }
}

#[test]
fn nrrd_opens_in_vtk_with_x_fastest_and_rgb_components() {
    let Some((python, _dir, path)) = nrrd_and_reader("vtk", "nrrd-vtk") else {
        return;
    };
    let script = r#"
import sys
# The plain reader ParaView uses; `import vtk` would load the MPI override
# (vtkPNrrdReader), which needs an MPI controller.
from vtkmodules.vtkIOImage import vtkNrrdReader
r = vtkNrrdReader()
r.SetFileName(sys.argv[1])
r.Update()
img = r.GetOutput()
d = img.GetDimensions()
a = img.GetPointData().GetScalars()
i, j, k = (int(x) for x in sys.argv[2:5])
print(*d)
print(a.GetNumberOfComponents(), a.GetNumberOfTuples())
print(*a.GetTuple(i + d[0] * (j + d[1] * k)))
print(*img.GetSpacing())
"#;
    let lines = read_at_probe(&python, script, &path);
    assert_eq!(floats(&lines[0]), vec![5.0, 7.0, 9.0], "VTK dimensions");
    assert_eq!(floats(&lines[1]), vec![3.0, 315.0], "components, tuples");
    assert_close(
        &floats(&lines[2]),
        &probe_colour(),
        1e-6,
        "VTK value at the probe",
    );
}

#[test]
fn nrrd_opens_in_simpleitk_and_pynrrd_with_geometry_in_cm() {
    let Some((python, _dir, path)) = nrrd_and_reader("SimpleITK", "nrrd-itk") else {
        return;
    };
    let script = r#"
import sys
import SimpleITK as sitk
img = sitk.ReadImage(sys.argv[1])
i, j, k = (int(x) for x in sys.argv[2:5])
print(*img.GetSize())
print(img.GetNumberOfComponentsPerPixel())
print(*img.GetPixel(i, j, k))
print(*img.GetSpacing())
print(*img.TransformIndexToPhysicalPoint((i, j, k)))
"#;
    let lines = read_at_probe(&python, script, &path);
    assert_eq!(floats(&lines[0]), vec![5.0, 7.0, 9.0], "ITK size");
    assert_eq!(floats(&lines[1]), vec![3.0], "ITK components");
    assert_close(&floats(&lines[2]), &probe_colour(), 1e-6, "ITK value");
    assert_close(
        &floats(&lines[3]),
        &[4.0 / 5.0, 4.0 / 7.0, 4.0 / 9.0],
        1e-5,
        "ITK spacing (cm)",
    );
    // Voxel (3, 1, 6) centre in cm: 4 * ((i + 0.5)/n - 0.5).
    let centre = [3.5 / 5.0 - 0.5, 1.5 / 7.0 - 0.5, 6.5 / 9.0 - 0.5].map(|c| 4.0 * c);
    assert_close(&floats(&lines[4]), &centre, 1e-5, "ITK physical point");

    if let Some(py) = common::python_with("nrrd") {
        let script = r#"
import sys, nrrd
data, h = nrrd.read(sys.argv[1])
i, j, k = (int(x) for x in sys.argv[2:5])
print(*data.shape)
print(*data[:, i, j, k])
print(*h['space units'])
print(h['kinds'][0])
"#;
        let lines = read_at_probe(&py, script, &path);
        assert_eq!(floats(&lines[0]), vec![3.0, 5.0, 7.0, 9.0], "pynrrd shape");
        assert_close(&floats(&lines[1]), &probe_colour(), 1e-6, "pynrrd value");
        assert_eq!(lines[2], "cm cm cm");
        assert_eq!(lines[3], "RGB-color");
    }
}

/// A wood-like colour that differs on every face and inside, in display sRGB.
struct Stripes;
impl SolidTexture for Stripes {
    fn channels(&self) -> usize {
        3
    }
    fn eval(&self, p: Vec3, out: &mut [f32]) {
        let ring = (0.5 + 0.5 * (18.0 * (p.x * p.x + p.z * p.z).sqrt()).sin()) * 0.35;
        out[0] = 0.45 + ring + 0.15 * p.y;
        out[1] = 0.30 + 0.6 * ring + 0.2 * p.x;
        out[2] = 0.20 + 0.3 * ring + 0.2 * p.z;
    }
}

#[test]
fn mitsuba_renders_the_exported_scene_like_xylem_render() {
    let Some(python) = common::python_with("mitsuba") else {
        return;
    };
    let dir = common::scratch("mitsuba");
    let volume = Volume::from_texture(&Stripes, 48);
    let mut cfg = RenderConfig::default_config();
    cfg.samples_per_axis = 2;
    let (w, h) = (96, 96);
    let size = SceneSize {
        width: w,
        height: h,
        spp: 64,
    };
    export_scene(&volume, &dir, &cfg, size, "stripes").unwrap();
    let script = r#"
import sys
import mitsuba as mi
mi.set_variant('scalar_rgb')
scene = mi.load_file(sys.argv[1])
img = mi.render(scene)
bmp = mi.Bitmap(img).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.UInt8, srgb_gamma=True)
bmp.write(sys.argv[2])
"#;
    let png = dir.join("mitsuba.png");
    let scene = dir.join("scene.xml");
    common::run_python(
        &python,
        script,
        &[scene.to_str().unwrap(), png.to_str().unwrap()],
    );
    let theirs = xylem::io::load_rgb(&png).unwrap();
    let ours = render(&volume, &Shape::Cube, &cfg.camera, &cfg, w, h);
    let bg = Vec3::from(cfg.background);
    let (mut n, mut sum_t, mut sum_o) = (0.0f32, Vec3::ZERO, Vec3::ZERO);
    let (mut lt, mut lo) = (Vec::new(), Vec::new());
    for r in 0..h {
        for c in 0..w {
            let o = Vec3::from_slice(ours.pixel(r, c));
            if (o - bg).length() < 1e-4 || !inside_cube_image(&ours, r, c, bg) {
                continue;
            }
            let t = Vec3::from_slice(theirs.pixel(r, c));
            n += 1.0;
            sum_t += t;
            sum_o += o;
            lt.push(t.dot(Vec3::new(0.2126, 0.7152, 0.0722)));
            lo.push(o.dot(Vec3::new(0.2126, 0.7152, 0.0722)));
        }
    }
    assert!(n > 0.2 * (w * h) as f32, "the cube covers the image centre");
    let (mt, mo) = (sum_t / n, sum_o / n);
    eprintln!(
        "mean colour: mitsuba {mt:?}, xylem {mo:?}, r = {}",
        pearson(&lt, &lo)
    );
    assert!(
        (mt - mo).abs().max_element() < 0.06,
        "mean colour of the cube: mitsuba {mt:?} vs xylem {mo:?}"
    );
    assert!(pearson(&lt, &lo) > 0.9, "the same figure on the same faces");
}

/// A pixel whose 8 neighbours are all on the cube too (edges differ between renderers).
fn inside_cube_image(img: &xylem::Image2, r: usize, c: usize, bg: Vec3) -> bool {
    if r == 0 || c == 0 || r + 1 >= img.height || c + 1 >= img.width {
        return false;
    }
    (r - 1..=r + 1).all(|rr| {
        (c - 1..=c + 1).all(|cc| (Vec3::from_slice(img.pixel(rr, cc)) - bg).length() > 1e-4)
    })
}
