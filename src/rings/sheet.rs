//! The localiser's contact sheet: one row per face, left to right the photo, the predicted
//! ring image, the given one (blank where the folder has none) and both overlaid (given
//! green, predicted magenta, white where they agree).

use crate::fit::sheet::{BACKGROUND, overlay, tile_rows};
use crate::image2::Image2;

/// The images of one face.
pub struct RingsRow {
    pub photo: Image2,
    pub predicted: Image2,
    pub given: Option<Image2>,
}

/// The sheet of the rows, top to bottom.
pub fn rings_sheet(rows: &[RingsRow]) -> Image2 {
    let rows: Vec<[Image2; 4]> = rows.iter().map(row_tiles).collect();
    tile_rows(&rows)
}

fn row_tiles(row: &RingsRow) -> [Image2; 4] {
    let n = row.predicted.width;
    let blank = Image2::filled(n, n, 3, BACKGROUND);
    let (given, both) = match &row.given {
        Some(g) => (g.with_channels(3), overlay(g, &row.predicted)),
        None => (blank.clone(), blank),
    };
    [
        row.photo.with_channels(3),
        row.predicted.with_channels(3),
        given,
        both,
    ]
}
