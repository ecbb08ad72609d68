use std::path::Path;

use serde::de::DeserializeOwned;

use crate::error::{ConfigError, one_line};

/// Parse a whole TOML document into `T`; errors name the field
/// (`motion.tick_hz: invalid type …`) and `shown` (the file).
pub fn parse_toml<T: DeserializeOwned>(text: &str, shown: &str) -> Result<T, ConfigError> {
    let de = toml::Deserializer::parse(text)
        .map_err(|e| ConfigError::Parse { path: shown.into(), message: one_line(&e.to_string()) })?;
    serde_path_to_error::deserialize(de).map_err(|e| field_error(e, None, shown))
}

/// Read and parse a whole TOML file into `T` (see [`parse_toml`]).
pub fn load_toml<T: DeserializeOwned>(path: &Path) -> Result<T, ConfigError> {
    let (text, shown) = read(path)?;
    parse_toml(&text, &shown)
}

/// The file's text and how errors name it.
fn read(path: &Path) -> Result<(String, String), ConfigError> {
    let shown = path.display().to_string();
    match std::fs::read_to_string(path) {
        Ok(text) => Ok((text, shown)),
        Err(source) => Err(ConfigError::Read { path: shown, source }),
    }
}

/// A deserialisation error as one line naming the field, within `section`
/// if given (`vision.noise_mm: invalid type …`).
fn field_error<E: ToString>(
    e: serde_path_to_error::Error<E>,
    section: Option<&str>,
    shown: &str,
) -> ConfigError {
    let field = e.path().to_string();
    let message = one_line(&e.into_inner().to_string());
    let at = match (section, field.as_str()) {
        (None, ".") => return ConfigError::Parse { path: shown.into(), message },
        (None, _) => field,
        (Some(name), ".") => name.to_owned(),
        (Some(name), _) => format!("{name}.{field}"),
    };
    ConfigError::Parse { path: shown.into(), message: format!("{at}: {message}") }
}

/// A rig config file, parsed as TOML but not yet interpreted.
#[derive(Debug, Clone, Default)]
pub struct RigFile {
    /// How errors name the file ("built-in defaults" without one).
    shown: String,
    table: toml::Table,
}

impl RigFile {
    /// Parse TOML text; `shown` names the file in errors.
    pub fn parse(text: &str, shown: &str) -> Result<Self, ConfigError> {
        let table = text
            .parse::<toml::Table>()
            .map_err(|e| ConfigError::Parse { path: shown.into(), message: one_line(&e.to_string()) })?;
        Ok(Self { shown: shown.into(), table })
    }

    pub fn load(path: &Path) -> Result<Self, ConfigError> {
        let (text, shown) = read(path)?;
        Self::parse(&text, &shown)
    }

    /// The file `--config` names, or the built-in defaults without one.
    pub fn load_or_default(path: Option<&Path>) -> Result<Self, ConfigError> {
        match path {
            Some(p) => Self::load(p),
            None => Ok(Self { shown: "built-in defaults".into(), table: toml::Table::new() }),
        }
    }

    /// How errors name this file.
    pub fn shown(&self) -> &str {
        &self.shown
    }

    /// Section `[name]`, or its default when the file has none. Errors name
    /// the field with its section (`vision.noise_mm: invalid type …`).
    pub fn section<T: DeserializeOwned + Default>(&self, name: &str) -> Result<T, ConfigError> {
        let Some(value) = self.table.get(name) else { return Ok(T::default()) };
        serde_path_to_error::deserialize(value.clone()).map_err(|e| field_error(e, Some(name), &self.shown))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ServiceSection;

    #[test]
    fn a_missing_section_is_its_default_and_other_sections_are_not_read() {
        let f = RigFile::parse("[sim]\nwhatever = 3\n", "t.toml").expect("parses");
        assert_eq!(f.section::<ServiceSection>("service").expect("default"), ServiceSection::default());
    }

    #[test]
    fn errors_name_the_file_section_and_field() {
        let f = RigFile::parse("[service]\nprefix = 3\n", "t.toml").expect("parses");
        let e = f.section::<ServiceSection>("service").expect_err("wrong type").to_string();
        assert!(e.starts_with("t.toml: service.prefix: invalid type"), "{e}");
        let f = RigFile::parse("[service]\nprefx = \"a\"\n", "t.toml").expect("parses");
        let e = f.section::<ServiceSection>("service").expect_err("unknown").to_string();
        assert!(e.starts_with("t.toml: service.prefx: unknown field `prefx`"), "{e}");
        let e = RigFile::parse("[service\n", "t.toml").expect_err("not TOML").to_string();
        assert!(e.starts_with("t.toml: ") && !e.contains('\n'), "{e}");
    }
}
