//! Files: PNG and NPY images and volumes, atomic writes, output folders, run records.

pub mod atomic;
pub mod npy;
pub(crate) mod output_dir;
pub mod png;
pub mod provenance;
pub mod read;

pub(crate) use atomic::write_atomic;
pub use atomic::write_bytes_atomic;
pub use output_dir::{OutputDir, check_new_file};
pub use png::{load_gray, load_rgb, save_png};
pub use provenance::Provenance;
pub use read::read_bytes;
pub(crate) use read::read_text;
