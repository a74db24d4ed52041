//! The base colour as a solid texture: the growth field sampled at a point, coloured by the
//! fitted bars, in white-balanced or real colour.

use glam::Vec3;

use super::base_colour::BaseColour;
use super::grain_shaded_texture::GrainShaded;
use super::growth::GrowthField;
use crate::frame::Face;
use crate::texture::SolidTexture;

/// Which colours a [`BaseColourTexture`] returns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColourSpace {
    /// White-balanced, no face offsets: what the NCA is conditioned on.
    WhiteBalanced,
    /// Real colour as seen on a face (its offset and white balance) or, with `None`, in a cut
    /// or volume: the ground colour on which the NCA paints.
    Real(Option<Face>),
    /// [`ColourSpace::Real`] shifted to the photos' mean colour (`BaseColour::mean_shift`):
    /// the base colour on its own as a prediction of the photos (faces, cuts, sheets,
    /// renders, metrics).
    Shown(Option<Face>),
}

/// The base colour as a solid texture: field + bars -> RGB (3 channels).
#[derive(Clone, Debug)]
pub struct BaseColourTexture {
    pub field: GrowthField,
    pub colour: BaseColour,
    pub space: ColourSpace,
}

impl BaseColourTexture {
    pub fn new(field: GrowthField, colour: BaseColour, space: ColourSpace) -> Self {
        Self {
            field,
            colour,
            space,
        }
    }
}

/// The base colour as a photo shows it: on `fitted_face` (a face the colour was fitted to)
/// with that face's white balance and offset; elsewhere (`None`: held-out faces, cuts,
/// renders) at the sample's white balance, seen with its grain shading.
pub(crate) fn base_colour_as_seen(
    field: &GrowthField,
    colour: BaseColour,
    fitted_face: Option<Face>,
) -> Box<dyn SolidTexture> {
    match fitted_face {
        Some(f) => Box::new(BaseColourTexture::new(
            field.clone(),
            colour,
            ColourSpace::Shown(Some(f)),
        )),
        None => {
            let wb = colour.white_balance.clone();
            let plain = BaseColourTexture::new(field.clone(), colour, ColourSpace::Shown(None));
            Box::new(GrainShaded::new(plain, Some(&wb)))
        }
    }
}

impl SolidTexture for BaseColourTexture {
    fn channels(&self) -> usize {
        3
    }

    fn eval(&self, p: Vec3, out: &mut [f32]) {
        let rgb = self.colour.colour(&self.field.sample(p));
        let rgb = match self.space {
            ColourSpace::WhiteBalanced => rgb,
            ColourSpace::Real(face) => self.colour.to_real(rgb, face),
            ColourSpace::Shown(face) => self.colour.to_shown(rgb, face),
        };
        out.copy_from_slice(&rgb);
    }
}
