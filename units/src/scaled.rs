//! Fields written in the file scaled by a constant: mm for m, degrees for
//! rad, ms for s.

use serde::de::DeserializeOwned;
use serde::{Deserializer, Serialize, Serializer};

/// A value made of `f64`s that can be scaled as one.
pub trait Scaled: Sized + Serialize + DeserializeOwned {
    /// Each number through `f`.
    fn map_each(&self, f: &impl Fn(f64) -> f64) -> Self;
}

impl Scaled for f64 {
    fn map_each(&self, f: &impl Fn(f64) -> f64) -> Self {
        f(*self)
    }
}

// serde implements arrays for fixed lengths only.
macro_rules! arrays {
    ($($n:literal),*) => {$(
        impl Scaled for [f64; $n] {
            fn map_each(&self, f: &impl Fn(f64) -> f64) -> Self {
                self.map(f)
            }
        }
    )*};
}
arrays!(2, 3, 4);

impl<T: Scaled> Scaled for Vec<T> {
    fn map_each(&self, f: &impl Fn(f64) -> f64) -> Self {
        self.iter().map(|x| x.map_each(f)).collect()
    }
}

impl<T: Scaled> Scaled for Option<T> {
    fn map_each(&self, f: &impl Fn(f64) -> f64) -> Self {
        self.as_ref().map(|x| x.map_each(f))
    }
}

fn read<'de, D: Deserializer<'de>, T: Scaled>(d: D, code_per_file: f64) -> Result<T, D::Error> {
    Ok(T::deserialize(d)?.map_each(&|x| x * code_per_file))
}

fn write<S: Serializer, T: Scaled>(v: &T, s: S, read: f64, write: f64) -> Result<S::Ok, S::Error> {
    v.map_each(&|x| written(x, read, write)).serialize(s)
}

/// `x` in the file's unit, chosen among the neighbours of `x · write` so
/// that it reads back as exactly `x` where one does: a config `upm run`
/// writes for its children then runs them on the same numbers.
fn written(x: f64, read: f64, write: f64) -> f64 {
    let w = x * write;
    let (mut up, mut down) = (w, w);
    for _ in 0..4 {
        for c in [up, down] {
            if c * read == x {
                return c;
            }
        }
        (up, down) = (up.next_up(), down.next_down());
    }
    w
}

macro_rules! unit {
    ($name:ident, $read:expr, $write:expr, $doc:literal) => {
        #[doc = $doc]
        pub mod $name {
            use super::Scaled;
            use serde::{Deserializer, Serializer};

            pub fn deserialize<'de, D: Deserializer<'de>, T: Scaled>(d: D) -> Result<T, D::Error> {
                super::read(d, $read)
            }

            pub fn serialize<S: Serializer, T: Scaled>(v: &T, s: S) -> Result<S::Ok, S::Error> {
                super::write(v, s, $read, $write)
            }
        }
    };
}

// The factors are those of `x * 1e-3` and `f64::to_radians`, so a value
// reads bit for bit as the code computed it from the file's before.
unit!(mm, 1e-3, 1e3, "Metres in the code, millimetres in the file.");
unit!(
    deg,
    core::f64::consts::PI / 180.0,
    180.0 / core::f64::consts::PI,
    "Radians in the code, degrees in the file."
);
unit!(ms_as_s, 1e-3, 1e3, "Seconds in the code, milliseconds in the file.");

#[cfg(test)]
mod tests {
    use serde::{Deserialize, Serialize};

    #[derive(Debug, Deserialize, Serialize, PartialEq)]
    struct Fields {
        #[serde(rename = "gap_mm", with = "super::mm")]
        gap: f64,
        #[serde(rename = "mount_mm", with = "super::mm")]
        mount: [f64; 3],
        #[serde(rename = "yaw_deg", with = "super::deg")]
        yaw: f64,
        #[serde(rename = "latency_ms", with = "super::ms_as_s")]
        latency: f64,
    }

    #[test]
    fn the_file_writes_units_the_code_reads_si() {
        let text = "gap_mm = 2.5\nmount_mm = [1, 2.0, 1600.0]\nyaw_deg = 90.0\nlatency_ms = 40.0\n";
        let f: Fields = toml::from_str(text).expect("parses");
        assert_eq!(f.gap, 2.5e-3);
        assert_eq!(f.mount, [1e-3, 2e-3, 1.6]);
        assert_eq!(f.yaw, 90f64.to_radians());
        assert_eq!(f.latency, 0.04);
        let back: Fields = toml::from_str(&toml::to_string(&f).expect("writes")).expect("reads back");
        assert_eq!(back, f);
    }

    #[test]
    fn what_is_written_reads_back_bit_for_bit() {
        // -1.5° is the camera's default tilt: its radians times 180/π are
        // -1.5000000000000002, which would read back one bit off.
        let mut misses = 0;
        for i in -20_000..20_000 {
            let x = f64::from(i) * 7.3e-4;
            for (read, write) in [(1e-3, 1e3), (core::f64::consts::PI / 180.0, 180.0 / core::f64::consts::PI)]
            {
                let code = x * read;
                misses += usize::from(super::written(code, read, write) * read != code);
            }
        }
        assert_eq!(misses, 0);
        assert_eq!(
            super::written(
                (-1.5f64).to_radians(),
                core::f64::consts::PI / 180.0,
                180.0 / core::f64::consts::PI
            ),
            -1.5
        );
    }
}
