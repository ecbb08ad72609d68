//! One TOML table read into several types: some keys into fields of their
//! own, the rest into one struct (what serde's `flatten` would do, which
//! cannot be combined with `deny_unknown_fields`). A custom `Deserialize`
//! hands its `MapAccess` to [`read_shared`], which gives the caller's keys
//! to the caller and reads the others into the struct.

use serde::Deserialize;
use serde::de::{DeserializeOwned, Error, MapAccess};

use crate::error::one_line;

/// The keys not taken by the caller, read into `T`; the error names the
/// key within the table (`mu_static: invalid type …`).
fn read_rest<T: DeserializeOwned, E: Error>(rest: toml::Table) -> Result<T, E> {
    serde_path_to_error::deserialize(toml::Value::Table(rest)).map_err(|e| {
        let path = e.path().to_string();
        let message = one_line(&e.into_inner().to_string());
        if path == "." { E::custom(message) } else { E::custom(format!("{path}: {message}")) }
    })
}

/// `T` written back as a table, for the caller to add its own keys to.
pub fn write_rest<T: serde::Serialize, E: serde::ser::Error>(value: &T) -> Result<toml::Table, E> {
    toml::Table::try_from(value).map_err(E::custom)
}

/// The keys struct `T` reads, as its `Deserialize` names them.
pub fn keys_of<T: DeserializeOwned>() -> &'static [&'static str] {
    let mut keys: &'static [&'static str] = &[];
    let _ = T::deserialize(KeysOf(&mut keys));
    keys
}

/// A deserializer that only notes which fields a struct asks for.
struct KeysOf<'a>(&'a mut &'static [&'static str]);

#[derive(Debug)]
struct Noted;

impl core::fmt::Display for Noted {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("keys noted")
    }
}

impl std::error::Error for Noted {}

impl Error for Noted {
    fn custom<M: core::fmt::Display>(_: M) -> Self {
        Noted
    }
}

impl<'de> serde::Deserializer<'de> for KeysOf<'_> {
    type Error = Noted;

    fn deserialize_any<V: serde::de::Visitor<'de>>(self, _: V) -> Result<V::Value, Noted> {
        Err(Noted)
    }

    fn deserialize_struct<V: serde::de::Visitor<'de>>(
        self,
        _: &'static str,
        fields: &'static [&'static str],
        _: V,
    ) -> Result<V::Value, Noted> {
        *self.0 = fields;
        Err(Noted)
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf
        option unit unit_struct newtype_struct seq tuple tuple_struct map enum identifier
        ignored_any
    }
}

/// A table's key, refused unless it is one of `keys` (the error then
/// names it where it stands, and lists them all).
struct KnownKey<'a>(&'a [&'static str]);

impl<'de> serde::de::DeserializeSeed<'de> for KnownKey<'_> {
    type Value = String;

    fn deserialize<D: serde::Deserializer<'de>>(self, d: D) -> Result<String, D::Error> {
        let key = String::deserialize(d)?;
        if self.0.contains(&key.as_str()) {
            return Ok(key);
        }
        let expected: Vec<String> = self.0.iter().map(|k| format!("`{k}`")).collect();
        Err(D::Error::custom(format!("unknown field `{key}`, expected one of {}", expected.join(", "))))
    }
}

/// Walk a table: the keys in `own` go to `take` (which reads the value
/// with `next_value`, so its errors name the key), the others, which must
/// be `T`'s, are read into `T` at the end.
pub fn read_shared<'de, M, T, F>(mut m: M, own: &[&'static str], mut take: F) -> Result<T, M::Error>
where
    M: MapAccess<'de>,
    T: DeserializeOwned,
    F: FnMut(&str, &mut M) -> Result<(), M::Error>,
{
    let keys: Vec<&'static str> = keys_of::<T>().iter().chain(own).copied().collect();
    let mut rest = toml::Table::new();
    while let Some(key) = m.next_key_seed(KnownKey(&keys))? {
        if own.contains(&key.as_str()) {
            take(&key, &mut m)?;
        } else {
            let value: toml::Value = m.next_value()?;
            rest.insert(key, value);
        }
    }
    read_rest(rest)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(serde::Deserialize)]
    #[allow(dead_code)] // only its keys are read
    struct Two {
        alpha: f64,
        #[serde(rename = "beta_mm")]
        beta: f64,
    }

    #[test]
    fn a_structs_keys_are_its_file_names() {
        assert_eq!(keys_of::<Two>(), &["alpha", "beta_mm"]);
    }
}
