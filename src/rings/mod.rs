//! Ring localisation from face photos (issue 13; Mokume section 5.1): the first step of the
//! pipeline for a cube that comes without ring images. [`localise`] turns a photo into a
//! ring-localisation image in the U-Net's encoding, [`load_with_rings`] fills in the ring
//! images a sample folder lacks, [`agreement`] measures a prediction against a reference.

pub mod agreement;

pub mod localise;
pub mod sheet;
pub mod source;

pub use crate::fit::localiser_config::LocaliserConfig;
pub use agreement::{Agreement, agreement};
pub use localise::localise;
pub use source::{RingSource, load_with_rings};
