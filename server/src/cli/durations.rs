//! The serve command's duration flags, each bounded: a timer set further out than the clock
//! can count panics on every connection, so each flag takes a range a person can mean and says
//! which when given anything else.

use crate::transport::MAX_TIMEOUT;

/// Whole seconds for a connection timeout: 1 up to [`MAX_TIMEOUT`].
pub(super) fn timeout_seconds(text: &str) -> Result<u64, String> {
    let max = MAX_TIMEOUT.as_secs();
    match text.trim().parse::<u64>() {
        Ok(seconds) if (1..=max).contains(&seconds) => Ok(seconds),
        _ => Err(format!("{text:?} is not a timeout of 1 to {max} seconds; give whole seconds")),
    }
}

/// A lease long enough for one heartbeat round trip, and at most an hour.
pub(super) fn lease_seconds(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(seconds) if (0.5..=3600.0).contains(&seconds) => Ok(seconds),
        _ => Err(format!("{text:?} is not a lease of 0.5 to 3600 seconds")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn timeouts_are_whole_seconds_up_to_an_hour() {
        assert_eq!(timeout_seconds("30"), Ok(30));
        assert_eq!(timeout_seconds("3600"), Ok(3600));
        for wrong in ["0", "3601", "18446744073709551615", "18446744073709551616", "-1", "1.5", ""]
        {
            let said = timeout_seconds(wrong).unwrap_err();
            assert!(said.contains("1 to 3600 seconds"), "{wrong}: {said}");
        }
    }

    #[test]
    fn leases_are_half_a_second_to_an_hour() {
        assert_eq!(lease_seconds("0.5"), Ok(0.5));
        for wrong in ["0.4", "3600.5", "NaN", "inf", "-1", "1e300"] {
            assert!(lease_seconds(wrong).is_err(), "{wrong}");
        }
    }
}
