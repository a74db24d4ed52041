//! What the growth field knows about one point (G, the stem and knot times, the dominant
//! strand): the input of everything that colours the wood.

/// Which strand's own time field is smallest at a point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Strand {
    Stem,
    Knot(usize),
}

/// Everything the field knows about a point, for colouring.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FieldSample {
    /// G (years).
    pub g: f32,
    /// Stem time t_s (years), before knots.
    pub stem: f32,
    /// The dominant strand.
    pub strand: Strand,
    /// Smallest knot time (years; infinite without knots).
    pub knot_time: f32,
    /// The point lies in a knot (dominated by it) and was laid down after that knot died.
    pub in_dead_knot: bool,
}
