//! Range checks shared by the procedural model's part configs (intervals, colours, sizes in
//! mm), each naming the key and the expected form.

use crate::config::Checker;
use crate::error::Result;

/// `[low, high]` with lo <= low < high <= hi.
pub(crate) fn check_interval(
    check: &Checker,
    key: &str,
    v: [f32; 2],
    lo: f32,
    hi: f32,
    meaning: &str,
) -> Result<()> {
    let [a, b] = v;
    if a.is_finite() && b.is_finite() && lo <= a && a < b && b <= hi {
        Ok(())
    } else {
        Err(check.error(
            key,
            format!("= [{a}, {b}]: expected [low, high] {meaning} with {lo} <= low < high <= {hi}"),
        ))
    }
}

/// The `years` key of a part laid out over growth years: an interval within 0..=10 000
/// (`meaning` says what the years are the times of, e.g. "ring times in years").
pub(crate) fn check_years(check: &Checker, years: [f32; 2], meaning: &str) -> Result<()> {
    check_interval(check, "years", years, 0.0, 10_000.0, meaning)
}

/// A display-referred colour: three values in [0, 1].
pub(crate) fn check_colour(check: &Checker, key: &str, c: [f32; 3]) -> Result<()> {
    if c.iter().all(|v| v.is_finite() && (0.0..=1.0).contains(v)) {
        Ok(())
    } else {
        Err(check.error(
            key,
            format!("= {c:?}: expected a colour [r, g, b] with values in [0, 1]"),
        ))
    }
}

/// Sizes in mm: every component finite, > 0 and at most `hi`.
pub(crate) fn check_sizes<const N: usize>(
    check: &Checker,
    key: &str,
    v: [f32; N],
    hi: f32,
    meaning: &str,
) -> Result<()> {
    if v.iter().all(|x| x.is_finite() && *x > 0.0 && *x <= hi) {
        Ok(())
    } else {
        Err(check.error(
            key,
            format!("= {v:?}: expected {meaning} in mm, each > 0 and <= {hi}"),
        ))
    }
}
