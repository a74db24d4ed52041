//! Sample folders in the Mokume layout: the six face photos `A_col.png`..`F_col.png`, the
//! ring localisation images `X_arl-unet.png` (U-Net output, real data) or `X_arl.png` (exact
//! I(G), synthetic samples), and optional knot markers `X_knot.png`.
//!
//! Knot markers (as in the Mokume H11 files): a white (255) grey image, same size as the
//! photos, with one darker pixel at each knot centre on that face. The grey value identifies
//! the knot: markers with the same value on two faces are the entry and exit of one knot
//! (H11 marks its single knot with 186 on faces C and F). `xylem sample` writes 186 - 8 i for
//! knot i.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::Vec3;

use crate::error::{Result, XylemError};
use crate::frame::{Face, pixel_centre};
use crate::image2::Image2;
use crate::io::{load_gray, load_rgb};

/// Grey value of knot `index`'s markers in files xylem writes.
pub fn marker_value(index: usize) -> u8 {
    186u8.saturating_sub(8 * index as u8)
}

/// One marked knot centre on a face.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KnotMarker {
    pub face: Face,
    /// The marker's grey value (knot identity).
    pub value: u8,
    /// Pixel coordinates of the marker centre.
    pub row: f32,
    pub col: f32,
    /// The 3D point on the face.
    pub point: Vec3,
}

/// The files of a sample folder that were found and loaded.
#[derive(Clone, Debug)]
pub struct Sample {
    pub dir: PathBuf,
    /// Face side in pixels (all images share it).
    pub size: usize,
    /// Which faces are used (all six unless a subset was asked for).
    pub faces: Vec<Face>,
    /// RGB photos, indexed by `Face::index`; `None` for faces not loaded or absent.
    pub photos: [Option<Image2>; 6],
    /// Ring localisation images (grey), indexed by `Face::index`.
    pub arl: [Option<Image2>; 6],
    /// Knot markers of the used faces.
    pub knot_markers: Vec<KnotMarker>,
}

/// Which images a caller needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Needs {
    pub photos: bool,
    pub arl: bool,
}

impl Sample {
    /// Loads the used faces of a sample folder. Missing required files, sizes that differ
    /// between files, and non-square images are errors naming the file.
    pub fn load(dir: &Path, faces: &[Face], needs: Needs) -> Result<Self> {
        if !dir.is_dir() {
            return Err(XylemError::sample(
                dir,
                "sample folder not found (expected A_col.png .. F_col.png, X_arl-unet.png or X_arl.png)",
            ));
        }
        if faces.is_empty() {
            return Err(XylemError::sample(dir, "no faces selected"));
        }
        let mut sample = Sample {
            dir: dir.to_path_buf(),
            size: 0,
            faces: faces.to_vec(),
            photos: Default::default(),
            arl: Default::default(),
            knot_markers: Vec::new(),
        };
        for &face in faces {
            if needs.photos {
                let path = dir.join(format!("{face}_col.png"));
                let img = require(&path, load_rgb)?;
                sample.check_size(&img, &path)?;
                check_photo_content(&img, &path)?;
                sample.photos[face.index()] = Some(img);
            }
            if needs.arl && !sample.load_ring_image(face)? {
                return Err(missing_ring_image(dir, face));
            }
            let knot = dir.join(format!("{face}_knot.png"));
            if knot.is_file() {
                let img = load_gray(&knot)?;
                sample.check_size(&img, &knot)?;
                let markers = find_markers(&img, face);
                if markers.len() > MAX_MARKERS_PER_FACE {
                    return Err(XylemError::image(
                        &knot,
                        format!(
                            "holds {} marker spots; expected at most {MAX_MARKERS_PER_FACE} \
                             (one small spot of one grey level per knot on a white image): \
                             stray non-white pixels each count as a knot, remove them",
                            markers.len()
                        ),
                    ));
                }
                sample.knot_markers.extend(markers);
            }
        }
        Ok(sample)
    }

    fn check_size(&mut self, img: &Image2, path: &Path) -> Result<()> {
        if img.width != img.height {
            return Err(XylemError::image(
                path,
                format!(
                    "is {}x{}; face images must be square",
                    img.width, img.height
                ),
            ));
        }
        if img.width < MIN_SIDE {
            return Err(XylemError::image(
                path,
                format!(
                    "is {}x{}; face images must be at least {MIN_SIDE}x{MIN_SIDE} pixels \
                     (the fit and the losses need rings and pores to look at)",
                    img.width, img.height
                ),
            ));
        }
        if self.size == 0 {
            self.size = img.width;
        } else if img.width != self.size {
            return Err(XylemError::image(
                path,
                format!(
                    "is {}x{}, but the sample's other images are {}x{}",
                    img.width, img.height, self.size, self.size
                ),
            ));
        }
        Ok(())
    }

    /// Loads the face's given ring image (`X_arl-unet.png`, else `X_arl.png`) if the folder
    /// has one; false if it has none. A file of the wrong size is an error naming it.
    pub(crate) fn load_ring_image(&mut self, face: Face) -> Result<bool> {
        let Some(path) = given_ring_path(&self.dir, face) else {
            return Ok(false);
        };
        let img = load_gray(&path)?;
        self.check_size(&img, &path)?;
        self.arl[face.index()] = Some(img);
        Ok(true)
    }

    /// The given ring image of `face` in `dir`, if the folder has one (any size).
    pub fn given_ring_image(dir: &Path, face: Face) -> Result<Option<Image2>> {
        given_ring_path(dir, face)
            .map(|path| load_gray(&path))
            .transpose()
    }

    pub fn photo(&self, face: Face) -> Option<&Image2> {
        self.photos[face.index()].as_ref()
    }

    pub fn ring_image(&self, face: Face) -> Option<&Image2> {
        self.arl[face.index()].as_ref()
    }

    /// Markers grouped by knot (grey value), in increasing value order.
    pub fn knots(&self) -> Vec<Vec<KnotMarker>> {
        let mut by_value: BTreeMap<u8, Vec<KnotMarker>> = BTreeMap::new();
        for m in &self.knot_markers {
            by_value.entry(m.value).or_default().push(*m);
        }
        by_value.into_values().collect()
    }
}

fn require(path: &Path, load: fn(&Path) -> Result<Image2>) -> Result<Image2> {
    if path.exists() && !path.is_file() {
        return Err(XylemError::sample(
            path,
            "is not a regular file (a folder, FIFO or device); expected a PNG face image",
        ));
    }
    if !path.is_file() {
        return Err(XylemError::sample(path, "missing face image"));
    }
    load(path)
}

/// `X_arl-unet.png` if present (real data), else `X_arl.png` (synthetic samples and
/// `xylem rings` output), else none.
pub(crate) fn given_ring_path(dir: &Path, face: Face) -> Option<PathBuf> {
    [format!("{face}_arl-unet.png"), format!("{face}_arl.png")]
        .into_iter()
        .map(|name| dir.join(name))
        .find(|path| path.is_file())
}

fn missing_ring_image(dir: &Path, face: Face) -> XylemError {
    XylemError::sample(
        dir.join(format!("{face}_arl-unet.png")),
        format!(
            "missing ring localisation image (neither {face}_arl-unet.png nor {face}_arl.png \
             exists); `xylem rings` predicts them from the photos, and `xylem fit` / `xylem run` \
             do so themselves unless asked for given rings"
        ),
    )
}

/// Connected groups of non-white pixels of equal value, each reduced to its centroid.
fn find_markers(img: &Image2, face: Face) -> Vec<KnotMarker> {
    let n = img.width;
    let value_at = |r: usize, c: usize| (img.get(r, c, 0) * 255.0).round() as u8;
    let mut seen = vec![false; n * n];
    let mut markers = Vec::new();
    for r0 in 0..n {
        for c0 in 0..n {
            let v = value_at(r0, c0);
            if v >= 250 || seen[r0 * n + c0] {
                continue;
            }
            let (mut sum_r, mut sum_c, mut count) = (0.0f32, 0.0f32, 0.0f32);
            let mut stack = vec![(r0, c0)];
            seen[r0 * n + c0] = true;
            while let Some((r, c)) = stack.pop() {
                sum_r += r as f32;
                sum_c += c as f32;
                count += 1.0;
                for (dr, dc) in [(-1i32, 0i32), (1, 0), (0, -1), (0, 1)] {
                    let (rr, cc) = (r as i32 + dr, c as i32 + dc);
                    if rr < 0 || cc < 0 || rr >= n as i32 || cc >= n as i32 {
                        continue;
                    }
                    let (rr, cc) = (rr as usize, cc as usize);
                    if !seen[rr * n + cc] && value_at(rr, cc) == v {
                        seen[rr * n + cc] = true;
                        stack.push((rr, cc));
                    }
                }
            }
            let (row, col) = (sum_r / count, sum_c / count);
            let point = face.point(
                pixel_centre(0, n) + col / n as f32,
                pixel_centre(0, n) + row / n as f32,
            );
            markers.push(KnotMarker {
                face,
                value: v,
                row,
                col,
                point,
            });
        }
    }
    markers
}

/// The faces of an optional `--faces` list: the parsed list, or all six when none is given.
pub fn faces_or_all(list: Option<&str>) -> Result<Vec<Face>> {
    match list {
        Some(list) => parse_faces(list),
        None => Ok(Face::ALL.to_vec()),
    }
}

/// Parses a face list such as "A,B,C,D,E" (`--faces`).
pub fn parse_faces(list: &str) -> Result<Vec<Face>> {
    let mut faces = Vec::new();
    for part in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let face = Face::parse(part).ok_or_else(|| {
            XylemError::input(
                format!("$faces {list:?}"),
                format!(
                    "{} is not a face; expected letters A..F separated by commas",
                    crate::error::literal(&format!("{part:?}"))
                ),
            )
        })?;
        if !faces.contains(&face) {
            faces.push(face);
        }
    }
    if faces.is_empty() {
        return Err(XylemError::input(
            format!("$faces {list:?}"),
            "no faces given; expected e.g. A,B,C,D,E",
        ));
    }
    faces.sort();
    Ok(faces)
}

/// Knot markers accepted per face: each marker becomes a knot of the fit, whose cost grows
/// quickly with their number (5 stray pixels made a 7 s fit take 108 s).
const MAX_MARKERS_PER_FACE: usize = 8;

/// Smallest face image side accepted.
const MIN_SIDE: usize = 16;

/// A photo to learn colour from: not black (white balance divides by its mean colour) and
/// not one flat colour (nothing to fit or imitate).
fn check_photo_content(img: &Image2, path: &Path) -> Result<()> {
    let n = (img.width * img.height) as f64;
    let mut mean = [0.0f64; 3];
    for px in img.data.chunks_exact(3) {
        for c in 0..3 {
            mean[c] += f64::from(px[c]) / n;
        }
    }
    if mean.iter().any(|&m| m < 0.02) {
        return Err(XylemError::image(
            path,
            format!(
                "has mean colour {:.3}/{:.3}/{:.3}: a channel is (nearly) black; expected a \
                 lit photo of a wooden face",
                mean[0], mean[1], mean[2]
            ),
        ));
    }
    let spread = img
        .data
        .chunks_exact(3)
        .map(|px| {
            (0..3)
                .map(|c| (f64::from(px[c]) - mean[c]).abs())
                .sum::<f64>()
        })
        .sum::<f64>()
        / n;
    if spread < 1e-3 {
        return Err(XylemError::image(
            path,
            "is one flat colour; expected a photo of a wooden face with rings",
        ));
    }
    Ok(())
}
