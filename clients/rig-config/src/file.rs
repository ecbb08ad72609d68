use std::path::Path;

use serde::de::DeserializeOwned;

use crate::error::{ConfigError, one_line};

/// Parse a whole TOML document into `T`; errors name the field
/// (`motion.tick_hz: invalid type …`) and `shown` (the file).
pub fn parse_toml<T: DeserializeOwned>(text: &str, shown: &str) -> Result<T, ConfigError> {
    let de = toml::Deserializer::parse(text)
        .map_err(|e| ConfigError::Parse { path: shown.into(), message: one_line(&e.to_string()) })?;
    serde_path_to_error::deserialize(de).map_err(|e| {
        let field = e.path().to_string();
        let message = one_line(&e.into_inner().to_string());
        ConfigError::Parse {
            path: shown.into(),
            message: if field == "." { message } else { format!("{field}: {message}") },
        }
    })
}

/// Read and parse a whole TOML file into `T` (see [`parse_toml`]).
pub fn load_toml<T: DeserializeOwned>(path: &Path) -> Result<T, ConfigError> {
    let shown = path.display().to_string();
    let text =
        std::fs::read_to_string(path).map_err(|source| ConfigError::Read { path: shown.clone(), source })?;
    parse_toml(&text, &shown)
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
        let shown = path.display().to_string();
        let text = std::fs::read_to_string(path)
            .map_err(|source| ConfigError::Read { path: shown.clone(), source })?;
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
        serde_path_to_error::deserialize(value.clone()).map_err(|e| {
            let field = e.path().to_string();
            let message = one_line(&e.into_inner().to_string());
            let at = if field == "." { name.to_owned() } else { format!("{name}.{field}") };
            ConfigError::Parse { path: self.shown.clone(), message: format!("{at}: {message}") }
        })
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
