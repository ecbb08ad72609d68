//! A CPU to pin a thread to, written as its number or -1 for none.

use serde::de::Error;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<usize>, D::Error> {
    match i64::deserialize(d)? {
        -1 => Ok(None),
        c if c >= 0 => usize::try_from(c).map(Some).map_err(D::Error::custom),
        c => Err(D::Error::custom(format!("a CPU number or -1 (not pinned) is needed, got {c}"))),
    }
}

pub fn serialize<S: Serializer>(cpu: &Option<usize>, s: S) -> Result<S::Ok, S::Error> {
    cpu.map_or(-1, |c| c as i64).serialize(s)
}

#[cfg(test)]
mod tests {
    use serde::{Deserialize, Serialize};

    #[derive(Debug, Deserialize, Serialize, PartialEq)]
    struct Pin {
        #[serde(with = "super")]
        cpu: Option<usize>,
    }

    #[test]
    fn minus_one_is_not_pinned_and_other_negatives_are_refused() {
        assert_eq!(toml::from_str::<Pin>("cpu = -1").expect("none"), Pin { cpu: None });
        assert_eq!(toml::from_str::<Pin>("cpu = 3").expect("three"), Pin { cpu: Some(3) });
        assert!(toml::from_str::<Pin>("cpu = -2").expect_err("-2").to_string().contains("-1"));
        assert_eq!(toml::to_string(&Pin { cpu: None }).expect("writes").trim(), "cpu = -1");
    }
}
