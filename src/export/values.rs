//! What an exported volume's values are, and how each format wants them.
//!
//! Colour volumes hold display sRGB in [0, 1] (what the photos and PNGs hold), but the NCA
//! may step slightly outside (see `synth`'s value range). Renderers (Mitsuba, OpenVDB
//! consumers such as Blender) integrate light and expect *linear* RGB; viewers of images and
//! scalar data (NRRD in VTK/Slicer, NumPy) show the values as they are, so those keep display
//! sRGB. Either way an exported colour is clamped to [0, 1] and the number of clamped values
//! is reported. A 3-channel volume is only taken for colour unasked if it looks like colour. Data volumes (growth field, fibre directions, extra NCA channels) are written
//! untouched.

use std::borrow::Cow;

use crate::error::{Result, XylemError};
use crate::render::shading::srgb_to_linear;
use crate::volume::Volume;

/// The meaning of a volume's values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Values {
    /// RGB colour, display sRGB in [0, 1] (3 channels).
    Colour,
    /// Any other data, written exactly as it is.
    Data,
}

/// How a format stores colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    /// Display sRGB, as xylem holds it.
    DisplaySrgb,
    /// Linear RGB (renderers).
    Linear,
}

/// More than this fraction of values outside [0, 1] means the data is probably not colour
/// (a unit fibre direction has a third of its components below 0; trained NCA volumes
/// have a few in a million outside).
const MAX_OUTSIDE_FRACTION: f64 = 0.01;

/// A volume ready to be written, and how many values were clamped into [0, 1].
pub struct Prepared<'a> {
    pub volume: Cow<'a, Volume>,
    pub clamped: usize,
}

/// Checks that `volume` can be exported as `values` and converts it to `encoding`.
///
/// `what` names the input in errors (usually its path).
pub fn prepare<'a>(
    volume: &'a Volume,
    values: Values,
    encoding: Encoding,
    what: &str,
) -> Result<Prepared<'a>> {
    if values == Values::Data {
        return Ok(Prepared {
            volume: Cow::Borrowed(volume),
            clamped: 0,
        });
    }
    check_colour(volume, what)?;
    let clamped = outside_unit(volume);
    if clamped == 0 && encoding == Encoding::DisplaySrgb {
        return Ok(Prepared {
            volume: Cow::Borrowed(volume),
            clamped,
        });
    }
    let convert = |v: f32| match encoding {
        Encoding::DisplaySrgb => v.clamp(0.0, 1.0),
        Encoding::Linear => srgb_to_linear(v),
    };
    let mut out = volume.clone();
    out.data.iter_mut().for_each(|v| *v = convert(*v));
    Ok(Prepared {
        volume: Cow::Owned(out),
        clamped,
    })
}

/// Values outside [0, 1]: what clamping changes, and what says a volume may not be colour.
fn outside_unit(volume: &Volume) -> usize {
    volume
        .data
        .iter()
        .filter(|v| !(0.0..=1.0).contains(*v))
        .count()
}

/// A colour volume has 3 finite channels.
fn check_colour(volume: &Volume, what: &str) -> Result<()> {
    if volume.channels != 3 {
        return Err(XylemError::input(
            what,
            format!(
                "a colour volume has 3 channels (RGB), this one has {}; export it as data \
                 ($values data) to write the values as they are",
                volume.channels
            ),
        ));
    }
    if let Some(v) = volume.data.iter().find(|v| !v.is_finite()) {
        return Err(XylemError::input(
            what,
            format!("colour value {v} is not finite"),
        ));
    }
    Ok(())
}

/// Guards a guess: a 3-channel volume taken for colour without being told should look like
/// colour, or clamping would silently destroy it (a fibre direction). Called when the user
/// did not say what the values are.
pub fn check_looks_like_colour(volume: &Volume, what: &str) -> Result<()> {
    let fraction = outside_unit(volume) as f64 / volume.data.len().max(1) as f64;
    if fraction > MAX_OUTSIDE_FRACTION {
        return Err(XylemError::input(
            what,
            format!(
                "{:.1} % of the values lie outside [0, 1], so this may not be colour (a fibre \
                 direction?): say what it is, $values data to write the values as they \
                 are or $values colour to clamp them to [0, 1]",
                100.0 * fraction
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rgb(values: Vec<f32>) -> Volume {
        Volume::from_data([values.len() / 3, 1, 1], 3, values).unwrap()
    }

    #[test]
    fn colour_is_clamped_and_linearised_and_counted() {
        let v = rgb(vec![-0.01, 0.5, 1.02, 0.0, 1.0, 0.2]);
        let display = prepare(&v, Values::Colour, Encoding::DisplaySrgb, "v").unwrap();
        assert_eq!(display.clamped, 2);
        assert_eq!(display.volume.data, vec![0.0, 0.5, 1.0, 0.0, 1.0, 0.2]);
        let linear = prepare(&v, Values::Colour, Encoding::Linear, "v").unwrap();
        assert!((linear.volume.data[1] - 0.214).abs() < 1e-3);
        assert_eq!(linear.volume.data[2], 1.0);
    }

    #[test]
    fn data_is_untouched_and_directions_are_not_colour() {
        let fibre = rgb(vec![0.0, -1.0, 0.0, 0.6, -0.8, 0.0]);
        let same = prepare(&fibre, Values::Data, Encoding::Linear, "f").unwrap();
        assert_eq!(same.volume.data, fibre.data);
        let err = check_looks_like_colour(&fibre, "f.npy")
            .expect_err("a direction field does not look like colour")
            .to_string();
        assert!(
            err.contains("f.npy") && err.contains("`values` data"),
            "{err}"
        );
        let colour = rgb(vec![0.0, 0.5, 1.0, 0.2, 0.3, 0.4]);
        assert!(check_looks_like_colour(&colour, "c").is_ok());
        let twelve = Volume::zeros([1, 1, 1], 12);
        assert!(prepare(&twelve, Values::Colour, Encoding::Linear, "s").is_err());
    }
}
