//! A Mitsuba 3 scene of the wood cube: `scene.xml` beside the colour volume `color.vol`.
//!
//! It reproduces `xylem render --view cube` with Mitsuba's own plugins so that the file opens
//! and renders with no edits (`mitsuba scene.xml`): the same camera (look-at, vertical field of
//! view), the key light as a `directional` emitter and the ambient term as a `constant`
//! emitter, on a `cube` shape scaled to [-0.5, 0.5]^3 whose `diffuse` BSDF takes its
//! reflectance from a `volume` texture. The clear coat of xylem's renderer is left out:
//! Mitsuba's `plastic` needs the mean of its texture, which `volume` textures do not provide.
//! The grid volume sets `use_grid_bbox`, so its [-0.5, 0.5]^3 bounding box (written in the
//! `.vol` header) is where the texture lies; without it Mitsuba maps the grid to [0, 1]^3.
//! Irradiance: xylem's key light adds `albedo * intensity * cos` to the outgoing radiance,
//! which a Lambertian surface returns for an irradiance of `pi * intensity`; the ambient term
//! `albedo * ambient` is a constant environment of radiance `ambient`.

use std::fmt::Write as _;
use std::path::Path;

use crate::error::Result;
use crate::export::mitsuba::write_vol;
use crate::io::write_bytes_atomic;
use crate::render::RenderConfig;
use crate::volume::Volume;

/// File name of the colour volume the scene refers to.
pub(crate) const VOLUME_FILE: &str = "color.vol";
/// File name of the scene.
pub const SCENE_FILE: &str = "scene.xml";

/// Image size and samples per pixel of the scene's sensor (overridable on Mitsuba's command
/// line with `-D resx=.. -D resy=.. -D spp=..`).
#[derive(Clone, Copy, Debug)]
pub struct SceneSize {
    pub width: usize,
    pub height: usize,
    pub spp: usize,
}

fn vec3(v: [f32; 3]) -> String {
    format!("{}, {}, {}", v[0], v[1], v[2])
}

/// The scene XML for `cfg`'s cube view.
pub(crate) fn scene_xml(cfg: &RenderConfig, size: SceneSize) -> String {
    let cam = &cfg.camera;
    let light = &cfg.light;
    let towards_scene = light.direction.map(|c| -c);
    let irradiance = std::f32::consts::PI * light.intensity;
    let mut xml = String::new();
    let _ = write!(
        xml,
        r#"<scene version="3.0.0">
    <!-- Written by `xylem export --format mitsuba`: the cube as `xylem render` shows it. -->
    <default name="spp" value="{spp}"/>
    <default name="resx" value="{w}"/>
    <default name="resy" value="{h}"/>
    <integrator type="direct"/>
    <sensor type="perspective">
        <float name="fov" value="{fov}"/>
        <string name="fov_axis" value="y"/>
        <transform name="to_world">
            <lookat origin="{eye}" target="{target}" up="{up}"/>
        </transform>
        <sampler type="independent">
            <integer name="sample_count" value="$spp"/>
        </sampler>
        <film type="hdrfilm">
            <integer name="width" value="$resx"/>
            <integer name="height" value="$resy"/>
        </film>
    </sensor>
    <emitter type="directional">
        <vector name="direction" value="{dir}"/>
        <rgb name="irradiance" value="{irradiance}"/>
    </emitter>
    <emitter type="constant">
        <rgb name="radiance" value="{ambient}"/>
    </emitter>
    <shape type="cube">
        <transform name="to_world">
            <scale value="0.5"/>
        </transform>
        <bsdf type="diffuse">
            <texture type="volume" name="reflectance">
                <volume type="gridvolume" name="volume">
                    <string name="filename" value="{file}"/>
                    <boolean name="use_grid_bbox" value="true"/>
                </volume>
            </texture>
        </bsdf>
    </shape>
</scene>
"#,
        spp = size.spp,
        w = size.width,
        h = size.height,
        fov = cam.fov_deg,
        eye = vec3(cam.eye),
        target = vec3(cam.target),
        up = vec3(cam.up),
        dir = vec3(towards_scene),
        ambient = light.ambient,
        file = VOLUME_FILE,
    );
    xml
}

/// Writes `dir/color.vol` (`linear_colour` must already be linear RGB in [0, 1]) and
/// `dir/scene.xml`.
pub fn write_scene(
    dir: &Path,
    linear_colour: &Volume,
    cfg: &RenderConfig,
    size: SceneSize,
) -> Result<()> {
    write_vol(&dir.join(VOLUME_FILE), linear_colour)?;
    write_bytes_atomic(&dir.join(SCENE_FILE), scene_xml(cfg, size).as_bytes())
}
