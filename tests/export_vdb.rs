//! OpenVDB export, checked with an independent reader: the OpenVDB library itself through
//! `pyopenvdb` (Debian's python3-openvdb). Values encode (i, j, k, channel), so a swapped
//! axis, a shifted leaf or a wrong channel order shows up as mismatches.

mod common;

use std::collections::HashMap;
use std::path::Path;

use xylem::export::vdb::{VdbClass, VdbGrid, VdbValues, write_vdb};
use xylem::volume::Volume;

/// value(i, j, k, ch) = 1 + ch + c (k + nz (j + ny i)): unique per voxel and channel, exact
/// in float32 below 2^24, and never the background 0.
fn coded(dims: [usize; 3], channels: usize) -> Volume {
    let n = dims.iter().product::<usize>() * channels;
    Volume::from_data(dims, channels, (0..n).map(|v| (v + 1) as f32).collect()).unwrap()
}

/// Reads every grid named in the arguments (`name:nx,ny,nz`) and prints `name key value`
/// lines; the expected voxel values are recomputed here from the same formula.
const READER: &str = r#"
import sys
import numpy as np
import pyopenvdb as vdb

path = sys.argv[1]
print("file grids", ",".join(m.name for m in vdb.readAllGridMetadata(path)))
for spec in sys.argv[2:]:
    name, dims = spec.split(":")
    nx, ny, nz = (int(d) for d in dims.split(","))
    g = vdb.read(path, name)
    c = 3 if g.valueTypeName == "vec3s" else 1
    a = np.zeros((nx, ny, nz, 3) if c == 3 else (nx, ny, nz), dtype=np.float32)
    g.copyToArray(a)
    i, j, k = np.indices((nx, ny, nz))
    flat = (k + nz * (j + ny * i))[..., None] * c + np.arange(c)
    expected = (1 + flat).astype(np.float32).reshape(a.shape)
    acc = g.getAccessor()
    meta = g.metadata
    def out(key, *values):
        print(name, key, " ".join(str(v) for v in values))
    out("type", g.valueTypeName)
    out("class", meta["class"])
    out("mismatches", int(np.count_nonzero(a != expected)))
    out("active", g.activeVoxelCount())
    (x0, y0, z0), (x1, y1, z1) = g.evalActiveVoxelBoundingBox()
    out("bbox", x0, y0, z0, x1, y1, z1)
    out("world0", *g.transform.indexToWorld((0, 0, 0)))
    out("world1", *g.transform.indexToWorld((nx - 1, ny - 1, nz - 1)))
    out("map", g.transform.typeName)
    out("nodes", g.leafCount(), g.nonLeafCount())
    out("outside", acc.getValue((nx, ny, nz)), acc.isValueOn((nx, ny, nz)))
    out("file_voxel_count", meta["file_voxel_count"])
    out("file_bbox_max", *meta["file_bbox_max"])
"#;

/// `(grid, key) -> value` from the reader's output.
fn read_with_openvdb(
    path: &Path,
    grids: &[(&str, [usize; 3])],
) -> Option<HashMap<(String, String), String>> {
    let python = common::python_with("pyopenvdb")?;
    let specs: Vec<String> = grids
        .iter()
        .map(|(name, [x, y, z])| format!("{name}:{x},{y},{z}"))
        .collect();
    let mut args = vec![path.to_str().unwrap()];
    args.extend(specs.iter().map(String::as_str));
    let out = common::run_python(&python, READER, &args);
    let mut facts = HashMap::new();
    for line in out.lines() {
        let mut parts = line.splitn(3, ' ');
        let (grid, key) = (parts.next().unwrap(), parts.next().unwrap());
        facts.insert(
            (grid.to_string(), key.to_string()),
            parts.next().unwrap_or("").to_string(),
        );
    }
    Some(facts)
}

/// A file at `path` with the one fog-volume grid `name` of `dims` voxels, read back as
/// [`read_with_openvdb`] does.
fn one_fog_grid(
    path: &Path,
    name: &str,
    values: VdbValues<'_>,
    dims: [usize; 3],
) -> Option<HashMap<(String, String), String>> {
    let grid = VdbGrid {
        name,
        values,
        class: VdbClass::FogVolume,
    };
    write_vdb(path, &[grid]).unwrap();
    read_with_openvdb(path, &[(name, dims)])
}

fn floats(s: &str) -> Vec<f64> {
    s.split_whitespace().map(|v| v.parse().unwrap()).collect()
}

/// Every check one grid must pass: type, class, all values, active voxels, bounding box,
/// voxel-centre transform, node counts.
fn check_grid(
    facts: &HashMap<(String, String), String>,
    name: &str,
    dims: [usize; 3],
    channels: usize,
    class: &str,
    nodes: (usize, usize),
) {
    let fact = |key: &str| {
        facts
            .get(&(name.to_string(), key.to_string()))
            .unwrap_or_else(|| panic!("no {key} for grid {name}: {facts:?}"))
            .as_str()
    };
    let [nx, ny, nz] = dims;
    assert_eq!(fact("type"), if channels == 3 { "vec3s" } else { "float" });
    assert_eq!(fact("class"), class);
    assert_eq!(fact("mismatches"), "0", "voxel values of {name}");
    assert_eq!(fact("active"), (nx * ny * nz).to_string());
    assert_eq!(
        fact("bbox"),
        format!("0 0 0 {} {} {}", nx - 1, ny - 1, nz - 1)
    );
    assert_eq!(
        fact("outside"),
        if channels == 3 {
            "(0.0, 0.0, 0.0) False"
        } else {
            "0.0 False"
        }
    );
    assert_eq!(fact("file_voxel_count"), (nx * ny * nz).to_string());
    assert_eq!(
        fact("file_bbox_max"),
        format!("{} {} {}", nx - 1, ny - 1, nz - 1)
    );
    assert_eq!(fact("nodes"), format!("{} {}", nodes.0, nodes.1));
    let uniform = nx == ny && ny == nz;
    assert_eq!(
        fact("map"),
        if uniform {
            "UniformScaleTranslateMap"
        } else {
            "ScaleTranslateMap"
        }
    );
    // First and last voxel centres: (i + 0.5)/n - 0.5.
    let centre = |i: usize, n: usize| (i as f64 + 0.5) / n as f64 - 0.5;
    for (key, index) in [("world0", [0; 3]), ("world1", [nx - 1, ny - 1, nz - 1])] {
        let got = floats(fact(key));
        for a in 0..3 {
            let want = centre(index[a], dims[a]);
            assert!(
                (got[a] - want).abs() < 1e-12,
                "{name} {key}[{a}] = {}, want {want}",
                got[a]
            );
        }
    }
}

#[test]
fn two_grids_in_one_file_read_back_exactly() {
    let dims = [5, 9, 13];
    let (color, density) = (coded(dims, 3), coded(dims, 1));
    let dir = common::scratch("vdb-two");
    let path = dir.join("two.vdb");
    write_vdb(
        &path,
        &[
            VdbGrid {
                name: "color",
                values: VdbValues::Vec3(&color),
                class: VdbClass::Unknown,
            },
            VdbGrid {
                name: "density",
                values: VdbValues::Float(&density),
                class: VdbClass::FogVolume,
            },
        ],
    )
    .unwrap();
    let Some(facts) = read_with_openvdb(&path, &[("color", dims), ("density", dims)]) else {
        return;
    };
    assert_eq!(facts[&("file".into(), "grids".into())], "color,density");
    // One leaf per 8^3 block (1 x 2 x 2), one lower and one upper node, plus the root.
    check_grid(&facts, "color", dims, 3, "unknown", (4, 3));
    check_grid(&facts, "density", dims, 1, "fog volume", (4, 3));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn cube_with_many_leaves_uses_a_uniform_map() {
    let dims = [40; 3];
    let color = coded(dims, 3);
    let dir = common::scratch("vdb-cube");
    let path = dir.join("cube.vdb");
    let Some(facts) = one_fog_grid(&path, "color", VdbValues::Vec3(&color), dims) else {
        return;
    };
    check_grid(&facts, "color", dims, 3, "fog volume", (125, 3));
    // XYLEM_KEEP_VDB=folder keeps a copy, to look at in Blender or Houdini.
    if let Some(keep) = std::env::var_os("XYLEM_KEEP_VDB") {
        std::fs::copy(&path, Path::new(&keep).join("cube40.vdb")).unwrap();
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn long_volume_spans_several_internal_nodes() {
    // z spans two upper nodes (4096 wide) and 33 lower nodes (128 wide), y two lower nodes.
    let dims = [2, 130, 4099];
    let density = coded(dims, 1);
    let dir = common::scratch("vdb-long");
    let path = dir.join("long.vdb");
    let Some(facts) = one_fog_grid(&path, "density", VdbValues::Float(&density), dims) else {
        return;
    };
    // Leaves 1 x 17 x 513; lower nodes 1 x 2 x 33; upper nodes 1 x 1 x 2; the root.
    check_grid(
        &facts,
        "density",
        dims,
        1,
        "fog volume",
        (17 * 513, 1 + 2 + 66),
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn same_grids_give_the_same_bytes() {
    let dir = common::scratch("vdb-determinism");
    let write = |name: &str, vol: &Volume| {
        let path = dir.join(name);
        write_vdb(
            &path,
            &[VdbGrid {
                name: "d",
                values: VdbValues::Float(vol),
                class: VdbClass::Unknown,
            }],
        )
        .unwrap();
        std::fs::read(path).unwrap()
    };
    let vol = coded([3, 4, 5], 1);
    let mut other = vol.clone();
    other.data[7] = -1.0;
    let (a, b, c) = (
        write("a.vdb", &vol),
        write("b.vdb", &vol),
        write("c.vdb", &other),
    );
    assert_eq!(a, b);
    assert_eq!(a.len(), c.len());
    // The UUID (bytes 21..57) follows the content.
    assert_ne!(a[21..57], c[21..57]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn three_channel_volume_as_float_is_an_error() {
    let dir = common::scratch("vdb-channels");
    let path = dir.join("bad.vdb");
    let rgb = coded([2, 2, 2], 3);
    let err = write_vdb(
        &path,
        &[VdbGrid {
            name: "density",
            values: VdbValues::Float(&rgb),
            class: VdbClass::FogVolume,
        }],
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("density") && err.contains("3 channels"),
        "{err}"
    );
    assert!(!path.exists());
}
