//! Two series compared through their centred second moments: the Pearson correlation (do
//! they rise and fall together?) and the least-squares slope of one on the other (by how
//! much?). Used for cube-edge profiles, ring images and pore-density curves alike, so every
//! figure that calls itself a correlation guards flat series the same way.

/// Variance sum under which a series counts as flat (constant up to rounding).
const FLAT: f64 = 1e-20;

/// Pearson correlation of two series over their common length (0 if either is flat).
pub fn pearson(a: &[f32], b: &[f32]) -> f32 {
    match centred_sums(a, b) {
        Some(s) if s.aa > FLAT && s.bb > FLAT => (s.ab / (s.aa * s.bb).sqrt()) as f32,
        _ => 0.0,
    }
}

/// Least-squares slope of series `a` on the `reference` series over their common length (0
/// if the reference is flat).
pub fn slope(a: &[f32], reference: &[f32]) -> f32 {
    match centred_sums(a, reference) {
        Some(s) if s.bb > FLAT => (s.ab / s.bb) as f32,
        _ => 0.0,
    }
}

/// Sums of the centred products of two series over their common length.
struct CentredSums {
    ab: f64,
    aa: f64,
    bb: f64,
}

fn centred_sums(a: &[f32], b: &[f32]) -> Option<CentredSums> {
    let n = a.len().min(b.len());
    if n == 0 {
        return None;
    }
    let mean = |v: &[f32]| v[..n].iter().map(|&x| x as f64).sum::<f64>() / n as f64;
    let (ma, mb) = (mean(a), mean(b));
    let mut s = CentredSums {
        ab: 0.0,
        aa: 0.0,
        bb: 0.0,
    };
    for (&x, &y) in a[..n].iter().zip(&b[..n]) {
        let (da, db) = (x as f64 - ma, y as f64 - mb);
        s.ab += da * db;
        s.aa += da * da;
        s.bb += db * db;
    }
    Some(s)
}
