//! What each column of `metrics.csv` means and which way is better. The numbers alone say
//! nothing to someone who has not read `src/metrics/`: `ring_ncc` wants to be high, `swd`
//! low, and `aniso` is only good next to `aniso_ref`. The meanings follow docs/DESIGN.md
//! ("Comparison metrics").

/// Which way a metric improves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Better {
    Higher,
    Lower,
    /// Closest to the value in the named column of the same row (the reference's value).
    CloserTo(&'static str),
    /// Not a score: a property of the reference image, shown for comparison.
    Reference,
}

impl Better {
    /// A short mark for the column header (none for the reference's value).
    pub(crate) fn arrow(self) -> &'static str {
        match self {
            Better::Higher => "\u{2191}",
            Better::Lower => "\u{2193}",
            Better::CloserTo(_) => "\u{2248}ref",
            Better::Reference => "",
        }
    }

    /// The rule in words, for the legend.
    pub fn words(self) -> String {
        match self {
            Better::Higher => "higher is better".into(),
            Better::Lower => "lower is better".into(),
            Better::CloserTo(column) => format!("closer to {column} is better"),
            Better::Reference => "the reference's own value (not a score)".into(),
        }
    }
}

/// One metric column.
#[derive(Clone, Copy, Debug)]
pub(crate) struct MetricInfo {
    pub name: &'static str,
    pub better: Better,
    pub perfect: &'static str,
    pub meaning: &'static str,
}

/// Every metric `xylem compare` writes (`metrics::METRIC_NAMES`), in that order.
pub(crate) const METRICS: [MetricInfo; 12] = [
    MetricInfo {
        name: "ring_ncc",
        better: Better::Higher,
        perfect: "1",
        meaning: "ring alignment: correlation of the band-passed lightness (difference of \
                  Gaussians, 2 and 16 px), best over shifts of up to 3 px",
    },
    MetricInfo {
        name: "orient",
        better: Better::Higher,
        perfect: "1",
        meaning: "grain-direction agreement: mean cos(2 \u{0394}\u{03b8}) of the structure \
                  tensors, weighted towards pixels oriented in both images",
    },
    MetricInfo {
        name: "swd",
        better: Better::Lower,
        perfect: "0",
        meaning: "texture distance: sliced Wasserstein distance between 5x5 Lab patches at \
                  two scales, blind to flips (pores, streaks and speckle, not placement)",
    },
    MetricInfo {
        name: "swd_L",
        better: Better::Lower,
        perfect: "0",
        meaning: "the same on lightness patches only",
    },
    MetricInfo {
        name: "swd_chroma",
        better: Better::Lower,
        perfect: "0",
        meaning: "the same on colour (a, b) patches only: colour speckle",
    },
    MetricInfo {
        name: "dE_mean",
        better: Better::Lower,
        perfect: "0",
        meaning: "CIE76 \u{0394}E between the mean Lab colours",
    },
    MetricInfo {
        name: "dE_std",
        better: Better::Lower,
        perfect: "0",
        meaning: "distance between the Lab standard deviations (contrast and colour spread)",
    },
    MetricInfo {
        name: "style",
        better: Better::Lower,
        perfect: "0",
        meaning: "the NCA's style loss (default config, fixed projections) against the \
                  reference's statistics",
    },
    MetricInfo {
        name: "aniso",
        better: Better::CloserTo("aniso_ref"),
        perfect: "aniso_ref",
        meaning: "pore-scale anisotropy of the candidate, 0 to 1 (dots 0, dashes towards 1)",
    },
    MetricInfo {
        name: "aniso_ref",
        better: Better::Reference,
        perfect: "",
        meaning: "pore-scale anisotropy of the reference image",
    },
    MetricInfo {
        name: "speckle",
        better: Better::CloserTo("speckle_ref"),
        perfect: "speckle_ref",
        meaning: "pixel-scale speckle of the candidate: checkerboard over neighbour-difference \
                  energy (smooth detail near 0, white noise 1, checkerboard 2)",
    },
    MetricInfo {
        name: "speckle_ref",
        better: Better::Reference,
        perfect: "",
        meaning: "pixel-scale speckle of the reference image",
    },
];

/// The legend entry of a column, if it is a known metric.
pub(crate) fn metric_info(name: &str) -> Option<&'static MetricInfo> {
    METRICS.iter().find(|m| m.name == name)
}

/// Marks a method whose row is the sample's own truth (the procedural model a synthetic
/// sample was made from): it shows each metric's ceiling and is not ranked.
pub(crate) const TRUTH_MARK: &str = "(truth)";

/// Whether a `method` cell names the truth rather than a candidate.
pub(crate) fn is_truth_method(method: &str) -> bool {
    method.trim_end().ends_with(TRUTH_MARK)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::METRIC_NAMES;

    #[test]
    fn every_metric_has_a_legend_entry_in_order() {
        let names: Vec<&str> = METRICS.iter().map(|m| m.name).collect();
        assert_eq!(names, METRIC_NAMES);
        for m in METRICS {
            if let Better::CloserTo(column) = m.better {
                assert!(metric_info(column).is_some(), "{}", m.name);
            }
        }
    }

    #[test]
    fn truth_rows_are_recognised() {
        assert!(is_truth_method("procedural (truth)"));
        assert!(!is_truth_method("procedural"));
    }
}
