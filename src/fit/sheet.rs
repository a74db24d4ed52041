//! The fit's contact sheet: one row per face A..F with five tiles, left to right: the photo,
//! the target ring image, the fitted ring image, both ring images overlaid (target green,
//! fitted magenta, white where they agree) and the fitted base colour. Faces left out of the
//! fit (`--faces`) get a red frame, so a leave-one-face-out prediction stands out.

use crate::image2::Image2;

/// Gap between tiles and rows (pixels).
const GAP: usize = 4;
pub const BACKGROUND: f32 = 0.12;
/// Width of the frame marking a held-out face.
const FRAME: usize = 3;

/// The images of one face.
pub(crate) struct SheetRow {
    pub photo: Option<Image2>,
    pub target: Option<Image2>,
    pub fitted: Image2,
    pub base: Image2,
    pub held_out: bool,
}

/// Target (green) and fitted (magenta) ring images in one RGB image.
pub fn overlay(target: &Image2, fitted: &Image2) -> Image2 {
    let mut out = Image2::filled(fitted.width, fitted.height, 3, 0.0);
    for r in 0..fitted.height {
        for c in 0..fitted.width {
            let f = fitted.get(r, c, 0);
            let t = target.get(r, c, 0);
            out.pixel_mut(r, c).copy_from_slice(&[f, t, f]);
        }
    }
    out
}

/// The sheet of up to six rows.
pub(crate) fn fit_sheet(rows: &[SheetRow]) -> Image2 {
    let rows: Vec<[Image2; 5]> = rows.iter().map(row_tiles).collect();
    tile_rows(&rows)
}

/// Rows of tiles (left to right) stacked top to bottom, `GAP` pixels of `BACKGROUND` between
/// tiles and rows: the layout of this sheet and the localiser's (`rings::sheet`).
pub(crate) fn tile_rows<R: AsRef<[Image2]>>(rows: &[R]) -> Image2 {
    let lines: Vec<Image2> = rows
        .iter()
        .map(|tiles| Image2::hstack(tiles.as_ref(), GAP, BACKGROUND))
        .collect();
    Image2::vstack(&lines, GAP, BACKGROUND)
}

fn row_tiles(row: &SheetRow) -> [Image2; 5] {
    let n = row.fitted.width;
    let blank = Image2::filled(n, n, 3, BACKGROUND);
    let photo = row.photo.clone().unwrap_or_else(|| blank.clone());
    let target = row.target.clone().unwrap_or_else(|| blank.clone());
    let both = match &row.target {
        Some(t) if t.width == n => overlay(t, &row.fitted),
        _ => blank.clone(),
    };
    let mut tiles = [photo, target, row.fitted.clone(), both, row.base.clone()];
    if row.held_out {
        tiles.iter_mut().for_each(frame_red);
    }
    tiles
}

/// Paints a red frame into the tile's border (in place, as RGB).
fn frame_red(tile: &mut Image2) {
    *tile = tile.with_channels(3);
    let (w, h) = (tile.width, tile.height);
    for r in 0..h {
        for c in 0..w {
            if r < FRAME || c < FRAME || r + FRAME >= h || c + FRAME >= w {
                tile.pixel_mut(r, c).copy_from_slice(&[0.9, 0.1, 0.1]);
            }
        }
    }
}
