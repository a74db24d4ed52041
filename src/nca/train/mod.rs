//! Training the NCA on a sample's faces (DESIGN section 6, "NCA" in docs/DESIGN.md): built
//! on the model and engines of `nca`, which never import this folder.
//!
//! Files, one concept each:
//! - [`targets`]: white-balanced face photos at the training resolution.
//! - [`face_guides`]: the ring phase of every trained face pixel, for the guided loss.
//! - [`loss`]: the seam to the face losses (`FaceLoss`) and the moment baseline;
//!   [`style_face_loss`] (whole-face statistics, and the choice of loss) and
//!   [`guided_face_loss`] (local, phase-guided) implement it.
//! - [`placement`]: where an iteration's crop lies.
//! - [`pool`]: the pool of states training continues from.
//! - [`iteration`]: one training iteration (Adam, schedule, gradient normalisation, overflow
//!   loss) and the state it carries.
//! - [`loss_log`]: the per-iteration log (`loss.csv`); [`plot`]: the loss curve as an image.
//! - [`snapshot`]: training checkpoints on disk for `--resume`.
//! - [`session`]: a whole training run into a model folder, checkpoints, resume.

pub mod face_guides;
pub mod guided_face_loss;
pub mod iteration;
pub mod loss;
pub mod loss_log;
pub mod low_band;
pub mod placement;
pub mod plot;
pub mod pool;
pub mod session;
pub mod snapshot;
pub mod style_face_loss;
pub mod targets;
pub mod vessel_gate;

pub use iteration::{TrainData, Trainer, adam};
