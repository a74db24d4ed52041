//! Numbers as a reader takes them in: the metrics are f32 estimates whose fourth digit is
//! noise, so the report shows three significant digits, and never more digits than that in
//! plain notation (a column of "12300000" would claim a precision it does not have).

/// `x` with `digits` significant digits (at least 1). Plain notation from 0.001 up to but
/// not including 1000, scientific (`1.23e4`, `4.56e-5`) outside that range; trailing zeros
/// are kept because they state the precision. Non-finite values read `NaN`, `inf`, `-inf`.
pub fn significant(x: f64, digits: usize) -> String {
    if x.is_nan() {
        return "NaN".into();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf" } else { "-inf" }.into();
    }
    if x == 0.0 {
        return "0".into();
    }
    let digits = digits.max(1);
    // The exponent of the *rounded* value decides the notation, so 0.9996 becomes "1.00",
    // not "0.100e1" or "1.000".
    let scientific = format!("{:.*e}", digits - 1, x);
    let Some((mantissa, exponent)) = scientific.split_once('e') else {
        return scientific;
    };
    let Ok(exponent) = exponent.parse::<i32>() else {
        return scientific;
    };
    if (-3..3).contains(&exponent) {
        let decimals = (digits as i32 - 1 - exponent).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        format!("{mantissa}e{exponent}")
    }
}

/// The value as shown with `digits` significant digits, read back: what a reader compares
/// when looking for the best cell, so that two cells that read the same rank the same.
pub(crate) fn as_shown(x: f64, digits: usize) -> f64 {
    significant(x, digits).parse().unwrap_or(x)
}

/// A wall time as people say it: `0.421 s`, `12.3 s`, `3 min 05 s`, `2 h 07 min`.
pub(crate) fn duration(seconds: f64) -> String {
    if !seconds.is_finite() || seconds < 0.0 {
        return "n/a".into();
    }
    if seconds < 60.0 {
        // "0.007 s", not "0.00700 s": a duration's trailing zeros add nothing.
        let mut text = significant(seconds, 3);
        if text.contains('.') && !text.contains('e') {
            text = text.trim_end_matches('0').trim_end_matches('.').to_string();
        }
        return format!("{text} s");
    }
    let whole = seconds.round() as u64;
    if whole < 3600 {
        format!("{} min {:02} s", whole / 60, whole % 60)
    } else {
        format!("{} h {:02} min", whole / 3600, (whole % 3600) / 60)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn three_significant_digits_in_plain_notation_between_a_thousandth_and_a_thousand() {
        let cases = [
            (0.46323064, "0.463"),
            (-0.0989294, "-0.0989"),
            (2.7923944, "2.79"),
            (49.804382, "49.8"),
            (600.0, "600"),
            (0.1, "0.100"),
            (1.0, "1.00"),
            (0.0012345, "0.00123"),
            (0.0, "0"),
        ];
        for (x, want) in cases {
            assert_eq!(significant(x, 3), want, "{x}");
        }
    }

    #[test]
    fn rounding_up_to_the_next_decade_changes_the_notation() {
        assert_eq!(significant(0.9996, 3), "1.00");
        assert_eq!(significant(999.6, 3), "1.00e3");
        assert_eq!(significant(0.00099996, 3), "0.00100");
    }

    #[test]
    fn very_large_and_small_values_are_scientific() {
        assert_eq!(significant(12345.0, 3), "1.23e4");
        assert_eq!(significant(0.000045678, 3), "4.57e-5");
        assert_eq!(significant(-1.5e-7, 2), "-1.5e-7");
        assert_eq!(significant(f64::NAN, 3), "NaN");
        assert_eq!(significant(f64::NEG_INFINITY, 3), "-inf");
    }

    #[test]
    fn one_digit_gives_tick_labels() {
        assert_eq!(significant(0.01, 1), "0.01");
        assert_eq!(significant(100.0, 1), "100");
        assert_eq!(significant(1000.0, 1), "1e3");
        assert_eq!(significant(1e-4, 1), "1e-4");
    }

    #[test]
    fn durations_read_as_people_say_them() {
        let said = [
            (0.4213, "0.421 s"),
            (0.007, "0.007 s"),
            (2.0, "2 s"),
            (12.34, "12.3 s"),
            (185.2, "3 min 05 s"),
            (7634.0, "2 h 07 min"),
            (f64::NAN, "n/a"),
        ];
        for (seconds, want) in said {
            assert_eq!(duration(seconds), want, "{seconds} s");
        }
    }
}
