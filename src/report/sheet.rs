//! Comparison sheets like Mokume figure 18: one row per face A-F and per validation cut,
//! one column per method (photo or truth, growth-field rings, base colour, procedural, NCA),
//! every tile labelled.

use crate::frame::{Face, Plane};
use crate::image2::Image2;
use crate::slice::slice_plane;
use crate::texture::SolidTexture;

use super::font::{LINE, draw_text, text_width};

/// Row names of a comparison sheet, in order.
pub const SHEET_ROWS: [&str; 8] = ["A", "B", "C", "D", "E", "F", "cut1", "cut2"];

/// The plane of each sheet row.
pub(crate) fn row_plane(row: usize) -> Plane {
    match row {
        0..=5 => Plane::face(Face::ALL[row]),
        6 => Plane::cut1(),
        _ => Plane::cut2(),
    }
}

/// One column of a sheet.
pub enum Column<'a> {
    /// Given images per row (e.g. photos, or a truth that exists only for some rows).
    Images(Vec<Option<Image2>>),
    /// A solid texture, sliced on every row's plane.
    Texture(&'a dyn SolidTexture),
}

const TEXT_SCALE: usize = 2;
const GAP: usize = 6;
const BACKGROUND: f32 = 1.0;
const INK: [f32; 3] = [0.1, 0.1, 0.1];
const MISSING: f32 = 0.85;

fn tile_image(column: &Column, row: usize, tile: usize) -> Option<Image2> {
    let img = match column {
        Column::Images(images) => images.get(row)?.as_ref()?.resized(tile, tile),
        Column::Texture(t) => slice_plane(*t, &row_plane(row), tile, tile),
    };
    let img = match img.channels {
        1 | 3 => img.with_channels(3),
        _ => Image2::filled(tile, tile, 3, MISSING),
    };
    Some(img)
}

/// A labelled grid: a header with the column titles, a left margin with the row names, and
/// `tile` x `tile` images; missing tiles are light grey marked "n/a".
pub fn comparison_sheet(columns: &[(String, Column)], tile: usize) -> Image2 {
    let label_w = text_width("cut1", TEXT_SCALE) + 2 * GAP;
    let header_h = LINE * TEXT_SCALE + 2 * GAP;
    let width = label_w + columns.len() * (tile + GAP) + GAP;
    let height = header_h + SHEET_ROWS.len() * (tile + GAP);
    let mut sheet = Image2::filled(width, height, 3, BACKGROUND);
    for (ci, (title, column)) in columns.iter().enumerate() {
        let left = label_w + ci * (tile + GAP);
        let (title, scale) = fit_text(title, tile);
        draw_text(
            &mut sheet,
            &title,
            GAP + (TEXT_SCALE - scale) * LINE / 2,
            left + (tile.saturating_sub(text_width(&title, scale))) / 2,
            scale,
            &INK,
        );
        for row in 0..SHEET_ROWS.len() {
            let top = header_h + row * (tile + GAP);
            match tile_image(column, row, tile) {
                Some(img) => sheet.blit(&img, top, left),
                None => {
                    sheet.blit(&Image2::filled(tile, tile, 3, MISSING), top, left);
                    let (w, h) = (text_width("n/a", TEXT_SCALE), LINE * TEXT_SCALE);
                    let (r, c) = (
                        top + tile.saturating_sub(h) / 2,
                        left + tile.saturating_sub(w) / 2,
                    );
                    draw_text(&mut sheet, "n/a", r, c, TEXT_SCALE, &INK);
                }
            }
        }
    }
    for (row, name) in SHEET_ROWS.iter().enumerate() {
        let top = header_h + row * (tile + GAP) + tile.saturating_sub(LINE * TEXT_SCALE) / 2;
        draw_text(&mut sheet, name, top, GAP, TEXT_SCALE, &INK);
    }
    sheet
}

/// A title and its text scale for `width` pixels: the sheet's scale if it fits, else the
/// small font (small tiles), shortened only if even that is too wide.
fn fit_text(text: &str, width: usize) -> (String, usize) {
    for scale in [TEXT_SCALE, 1] {
        if text_width(text, scale) <= width {
            return (text.to_string(), scale);
        }
    }
    let max_chars = (width / text_width("M", 1)).max(1);
    (text.chars().take(max_chars).collect(), 1)
}

/// Images side by side with a caption above each (renders, turntables).
pub fn captioned_row(items: &[(String, &Image2)]) -> Image2 {
    let header_h = LINE * TEXT_SCALE + 2 * GAP;
    let height = header_h + items.iter().map(|(_, i)| i.height).max().unwrap_or(0) + GAP;
    let width = items.iter().map(|(_, i)| i.width + GAP).sum::<usize>() + GAP;
    let mut out = Image2::filled(width, height, 3, BACKGROUND);
    let mut left = GAP;
    for (caption, img) in items {
        let (caption, scale) = fit_text(caption, img.width);
        draw_text(
            &mut out,
            &caption,
            GAP + (TEXT_SCALE - scale) * LINE / 2,
            left,
            scale,
            &INK,
        );
        out.blit(&img.with_channels(3), header_h, left);
        left += img.width + GAP;
    }
    out
}
