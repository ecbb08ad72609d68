use serde::{Deserialize, Serialize};

/// `[service]`: which rig a process belongs to.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq, Eq)]
#[serde(default, deny_unknown_fields)]
pub struct ServiceSection {
    /// iceoryx2 prefix: one per rig, so rigs (and tests) never see each other.
    pub prefix: String,
}

impl Default for ServiceSection {
    fn default() -> Self {
        Self { prefix: "upm_".into() }
    }
}

impl ServiceSection {
    /// The prefix, after `--prefix` overrides it, checked.
    pub fn prefix_or(&self, over: Option<&str>) -> Result<String, String> {
        let prefix = over.unwrap_or(&self.prefix);
        if prefix.is_empty() || !prefix.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-') {
            return Err(format!(
                "service.prefix {prefix:?} must be non-empty ASCII letters, digits, '_' or '-'"
            ));
        }
        Ok(prefix.to_owned())
    }
}
