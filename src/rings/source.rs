//! Where a fit's ring images come from: the sample folder's own (`X_arl-unet.png` /
//! `X_arl.png`), the localiser, or the folder's where it has them and the localiser
//! elsewhere (the default, so a folder of six photos fits as it is).

use std::fmt;
use std::path::Path;
use std::str::FromStr;

use super::localise::localise;
use crate::error::{Result, XylemError};
use crate::fit::localiser_config::LocaliserConfig;
use crate::frame::Face;
use crate::sample::{Needs, Sample};

/// The choice behind `--rings`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RingSource {
    /// Given images where the folder has them, predicted for the other faces.
    #[default]
    Auto,
    /// Only the folder's images; a face without one is an error.
    Given,
    /// Predicted from the photos for every face, given images ignored.
    Predict,
}

impl RingSource {
    pub const ALL: [RingSource; 3] = [RingSource::Auto, RingSource::Given, RingSource::Predict];

    /// The name `--rings` takes.
    pub fn name(self) -> &'static str {
        match self {
            RingSource::Auto => "auto",
            RingSource::Given => "given",
            RingSource::Predict => "predict",
        }
    }
}

impl fmt::Display for RingSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for RingSource {
    type Err = XylemError;

    fn from_str(s: &str) -> Result<Self> {
        Self::ALL
            .into_iter()
            .find(|source| source.name() == s)
            .ok_or_else(|| {
                XylemError::input(
                    format!("ring source {s:?}"),
                    "expected auto, given or predict",
                )
            })
    }
}

/// A sample loaded with photos and ring images, and the faces whose ring images the
/// localiser made.
pub struct SampleWithRings {
    pub sample: Sample,
    pub predicted: Vec<Face>,
}

/// Loads the photos of `faces` and their ring images as `source` says.
pub fn load_with_rings(
    dir: &Path,
    faces: &[Face],
    source: RingSource,
    cfg: &LocaliserConfig,
) -> Result<SampleWithRings> {
    let needs = Needs {
        photos: true,
        arl: source == RingSource::Given,
    };
    let mut sample = Sample::load(dir, faces, needs)?;
    let mut predicted = Vec::new();
    if source != RingSource::Given {
        for &face in faces {
            if source == RingSource::Auto && sample.load_ring_image(face)? {
                continue;
            }
            let photo = sample
                .photo(face)
                .expect("Sample::load loads the photos of every face asked for");
            sample.arl[face.index()] = Some(localise(photo, cfg));
            predicted.push(face);
        }
    }
    Ok(SampleWithRings { sample, predicted })
}
