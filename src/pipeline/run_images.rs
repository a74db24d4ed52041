//! The pictures of a run: the comparison sheet, the reference and NCA faces unfolded side by
//! side, and lit renders (cubes, carved bowls, a turntable) of the textures compared.

use super::compared::Compared;
use crate::Result;
use crate::field::{GrowthField, RingImage};
use crate::frame::Face;
use crate::image2::Image2;
use crate::io::save_png;
use crate::outputs::{CROSS_BACKGROUND, SliceSet};
use crate::render::lathe::{SHIPPED_SEGMENTS, turned_bowl};
use crate::render::{CameraConfig, RenderConfig, Shape, render, turntable};
use crate::report::{Column, captioned_row, comparison_sheet};
use crate::run_folder::RunLayout;
use crate::slice::unfold_cross;
use crate::texture::SolidTexture;

/// `sheet.png`: rows faces A-F, cut1, cut2; columns reference, fitted rings, base colour,
/// procedural, NCA; tiles of `tile` pixels.
pub(crate) fn write_sheet(layout: &RunLayout, compared: &Compared, tile: usize) -> Result<()> {
    let field = GrowthField::from_config(&compared.fit);
    let rings = RingImage(&field);
    let reference = if compared.synthetic { "truth" } else { "photo" };
    let columns = vec![
        (
            reference.to_string(),
            Column::Images(compared.reference.clone()),
        ),
        ("fitted rings".to_string(), Column::Texture(&rings)),
        ("base colour".to_string(), Column::Texture(&compared.base)),
        (
            "procedural".to_string(),
            Column::Texture(&compared.procedural),
        ),
        ("NCA".to_string(), Column::Texture(&compared.nca)),
    ];
    save_png(&comparison_sheet(&columns, tile), &layout.sheet())
}

/// `unfolded.png`: the reference faces (photos, or the synthetic truth) and the NCA's, both
/// unfolded, side by side; faces without a photo are left grey.
pub(crate) fn write_unfolded(layout: &RunLayout, compared: &Compared, tile: usize) -> Result<()> {
    let n = tile;
    let faces: Vec<Image2> = Face::ALL
        .iter()
        .map(|f| {
            compared.reference[f.index()]
                .as_ref()
                .map_or_else(|| Image2::filled(n, n, 3, 0.85), |i| i.resized(n, n))
        })
        .collect();
    let faces: [Image2; 6] = faces.try_into().expect("six faces");
    let photo_cross = unfold_cross(&faces, CROSS_BACKGROUND);
    let nca_cross = SliceSet::render(&compared.nca, n).cross();
    let items = [
        ("reference".to_string(), &photo_cross),
        ("NCA".to_string(), &nca_cross),
    ];
    save_png(&captioned_row(&items), &layout.unfolded())
}

/// `renders/`: the lit cube of each texture, the carved bowl of the NCA and the procedural
/// model, and a turntable of the NCA cube; renders of `2 * tile` pixels.
pub(crate) fn write_renders(layout: &RunLayout, compared: &Compared, tile: usize) -> Result<()> {
    let cfg = RenderConfig::default_config();
    let n = tile * 2;
    let textures: [(&str, &dyn SolidTexture); 3] = [
        ("NCA", &compared.nca),
        ("base colour", &compared.base),
        ("procedural", &compared.procedural),
    ];
    let cubes = render_row(&textures, "cube", &Shape::Cube, &cfg.camera, &cfg, n);
    save_png(&cubes, &layout.render("cubes.png"))?;
    let bowl = Shape::carved(&turned_bowl(SHIPPED_SEGMENTS), &cfg.carve);
    let carved = [textures[0], textures[2]];
    let bowls = render_row(&carved, "bowl", &bowl, &cfg.mesh_camera, &cfg, n);
    save_png(&bowls, &layout.render("bowls.png"))?;
    let strip = turntable(&compared.nca, &Shape::Cube, &cfg, tile, tile);
    save_png(&strip, &layout.render("turntable_nca.png"))
        .map_err(|e| e.during(format!("writing renders into {}", layout.root().display())))
}

/// `textures` rendered as `shape` from `camera` at `n` x `n`, side by side, each captioned
/// "{kind}: {name}".
fn render_row(
    textures: &[(&str, &dyn SolidTexture)],
    kind: &str,
    shape: &Shape,
    camera: &CameraConfig,
    cfg: &RenderConfig,
    n: usize,
) -> Image2 {
    let renders: Vec<(String, Image2)> = textures
        .iter()
        .map(|(name, t)| {
            let image = render(*t, shape, camera, cfg, n, n);
            (format!("{kind}: {name}"), image)
        })
        .collect();
    let items: Vec<(String, &Image2)> = renders.iter().map(|(c, i)| (c.clone(), i)).collect();
    captioned_row(&items)
}
