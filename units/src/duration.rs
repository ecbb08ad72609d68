//! Durations the code keeps in integer nanoseconds, written in the file as
//! ms (a float) or µs (an integer).

use serde::de::Error;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// The longest duration a file may write: about 11.6 days.
const MAX_MS: f64 = 1e9;

/// Nanoseconds in the code, milliseconds (finite, 0 ≤ ms < 10⁹) in the file.
pub mod ms_as_ns {
    use super::*;

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
        let ms = f64::deserialize(d)?;
        if ms.is_finite() && (0.0..MAX_MS).contains(&ms) {
            Ok((ms * 1e6).round() as u64)
        } else {
            Err(D::Error::custom(format!("a number of milliseconds in [0, 1e9) is needed, got {ms}")))
        }
    }

    pub fn serialize<S: Serializer>(ns: &u64, s: S) -> Result<S::Ok, S::Error> {
        (*ns as f64 / 1e6).serialize(s)
    }
}

/// Nanoseconds in the code, microseconds (an integer) in the file.
pub mod us_as_ns {
    use super::*;

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<u64, D::Error> {
        let us = u64::deserialize(d)?;
        us.checked_mul(1000)
            .ok_or_else(|| D::Error::custom(format!("{us} µs does not fit in 64-bit nanoseconds")))
    }

    pub fn serialize<S: Serializer>(ns: &u64, s: S) -> Result<S::Ok, S::Error> {
        (ns / 1000).serialize(s)
    }
}

#[cfg(test)]
mod tests {
    use serde::{Deserialize, Serialize};

    #[derive(Debug, Deserialize, Serialize, PartialEq)]
    struct Times {
        #[serde(rename = "age_ms", with = "super::ms_as_ns")]
        age_ns: u64,
        #[serde(rename = "poll_us", with = "super::us_as_ns")]
        poll_ns: u64,
    }

    #[test]
    fn durations_read_into_nanoseconds_and_back() {
        let t: Times = toml::from_str("age_ms = 0.5\npoll_us = 250\n").expect("parses");
        assert_eq!(t, Times { age_ns: 500_000, poll_ns: 250_000 });
        let again: Times = toml::from_str(&toml::to_string(&t).expect("writes")).expect("reads back");
        assert_eq!(again, t);
    }

    #[test]
    fn a_duration_that_is_not_one_is_refused() {
        for bad in ["age_ms = -1.0", "age_ms = nan", "age_ms = inf", "age_ms = 1e12"] {
            let text = format!("{bad}\npoll_us = 1\n");
            let e = toml::from_str::<Times>(&text).expect_err(bad).to_string();
            assert!(e.contains("milliseconds"), "{bad}: {e}");
        }
        let e = toml::from_str::<Times>("age_ms = 1\npoll_us = 18446744073709552\n").expect_err("overflow");
        assert!(e.to_string().contains("does not fit"), "{e}");
    }
}
