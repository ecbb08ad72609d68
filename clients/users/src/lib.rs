//! The users file: names and argon2id password hashes (see README.md).

use std::io::Write as _;
use std::path::Path;

use argon2::{Argon2, PasswordHash, PasswordHasher as _, PasswordVerifier as _};
use serde::{Deserialize, Serialize};

/// One user: a name and the PHC string of their password's hash.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct User {
    pub name: String,
    pub hash: String,
}

/// The users of a rig, as in the file.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Users {
    #[serde(default, rename = "user")]
    pub users: Vec<User>,
}

/// Why the users file or a new user was refused.
#[derive(Debug, thiserror::Error)]
pub enum UsersError {
    #[error("reading {path}: {source}")]
    Read { path: String, source: std::io::Error },
    #[error("writing {path}: {source}")]
    Write { path: String, source: std::io::Error },
    #[error("{path}: {message}")]
    Parse { path: String, message: String },
    #[error("user[{index}].name {name:?}: {why}")]
    BadName { index: usize, name: String, why: &'static str },
    #[error("user[{index}].hash is not an argon2 PHC string: {why}")]
    BadHash { index: usize, why: String },
    #[error("user {name:?} already exists")]
    Exists { name: String },
    #[error("the password is empty")]
    EmptyPassword,
    #[error("hashing the password: {0}")]
    Hash(String),
}

/// Names are what an operator types: 1–64 of `A-Z a-z 0-9 _ - .`.
fn check_name(name: &str) -> Result<(), &'static str> {
    if name.is_empty() || name.len() > 64 {
        return Err("must be 1 to 64 characters");
    }
    if !name.chars().all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.')) {
        return Err("may hold only letters, digits, '_', '-' and '.'");
    }
    Ok(())
}

impl Users {
    /// Parse and check a users file's text (`path` names it in errors).
    pub fn parse(text: &str, path: &str) -> Result<Self, UsersError> {
        let users: Users = toml::from_str(text)
            .map_err(|e| UsersError::Parse { path: path.into(), message: e.message().to_owned() })?;
        users.check()?;
        Ok(users)
    }

    /// Read and check `path`.
    pub fn load(path: &Path) -> Result<Self, UsersError> {
        let shown = path.display().to_string();
        let text = std::fs::read_to_string(path)
            .map_err(|source| UsersError::Read { path: shown.clone(), source })?;
        Self::parse(&text, &shown)
    }

    fn check(&self) -> Result<(), UsersError> {
        for (index, u) in self.users.iter().enumerate() {
            check_name(&u.name).map_err(|why| UsersError::BadName { index, name: u.name.clone(), why })?;
            if self.users[..index].iter().any(|v| v.name == u.name) {
                return Err(UsersError::BadName { index, name: u.name.clone(), why: "appears twice" });
            }
            PasswordHash::new(&u.hash).map_err(|e| UsersError::BadHash { index, why: e.to_string() })?;
        }
        Ok(())
    }

    /// Add `name` with `password` (hashed with a fresh random salt).
    pub fn add(&mut self, name: &str, password: &str) -> Result<(), UsersError> {
        let index = self.users.len();
        check_name(name).map_err(|why| UsersError::BadName { index, name: name.into(), why })?;
        if self.users.iter().any(|u| u.name == name) {
            return Err(UsersError::Exists { name: name.into() });
        }
        if password.is_empty() {
            return Err(UsersError::EmptyPassword);
        }
        let hash = Argon2::default()
            .hash_password(password.as_bytes())
            .map_err(|e| UsersError::Hash(e.to_string()))?;
        self.users.push(User { name: name.into(), hash: hash.to_string() });
        Ok(())
    }

    /// True if `name` is a user and `password` is theirs. Slow on purpose
    /// (argon2): never call it on a latency-sensitive thread.
    pub fn verify(&self, name: &str, password: &str) -> bool {
        let Some(user) = self.users.iter().find(|u| u.name == name) else {
            return false;
        };
        PasswordHash::new(&user.hash)
            .is_ok_and(|h| Argon2::default().verify_password(password.as_bytes(), &h).is_ok())
    }

    /// Write to `path` (mode 0600) through a temporary file, so a reader
    /// never sees half a file.
    pub fn save(&self, path: &Path) -> Result<(), UsersError> {
        use std::os::unix::fs::OpenOptionsExt as _;
        let shown = path.display().to_string();
        let werr = |source| UsersError::Write { path: shown.clone(), source };
        let text = toml::to_string(self).map_err(|e| UsersError::Hash(e.to_string()))?;
        let tmp = path.with_extension("tmp");
        let mut f = std::fs::OpenOptions::new()
            .write(true)
            .create(true)
            .truncate(true)
            .mode(0o600)
            .open(&tmp)
            .map_err(werr)?;
        f.write_all(b"# upm users: argon2id hashes, never a password. `upm users add` adds one.\n")
            .and_then(|()| f.write_all(text.as_bytes()))
            .and_then(|()| f.sync_all())
            .map_err(werr)?;
        std::fs::rename(&tmp, path).map_err(werr)
    }
}

/// Add `name` to the users file at `path` (created if missing).
pub fn add_user(path: &Path, name: &str, password: &str) -> Result<(), UsersError> {
    let mut users = if path.exists() { Users::load(path)? } else { Users::default() };
    users.add(name, password)?;
    users.save(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_user_added_verifies_and_the_file_holds_no_password() -> Result<(), UsersError> {
        let dir = std::env::temp_dir().join(format!("upm-users-{}", std::process::id()));
        std::fs::create_dir_all(&dir).map_err(|source| UsersError::Write { path: "dir".into(), source })?;
        let path = dir.join("users.toml");
        let _ = std::fs::remove_file(&path);
        add_user(&path, "robot", "s3cret-pass")?;
        add_user(&path, "op.1", "other")?;
        let text =
            std::fs::read_to_string(&path).map_err(|source| UsersError::Read { path: "f".into(), source })?;
        assert!(!text.contains("s3cret-pass"), "the password is in the file");
        let users = Users::load(&path)?;
        assert!(users.verify("robot", "s3cret-pass"));
        assert!(!users.verify("robot", "s3cret-pasS"));
        assert!(!users.verify("nobody", "s3cret-pass"));
        assert!(users.verify("op.1", "other"));
        assert!(matches!(add_user(&path, "robot", "x"), Err(UsersError::Exists { .. })));
        let _ = std::fs::remove_dir_all(&dir);
        Ok(())
    }

    #[test]
    fn bad_files_are_refused_naming_the_entry() {
        let err = |t: &str| Users::parse(t, "u.toml").map(|_| ()).map_err(|e| e.to_string()).err();
        let e = err("[[user]]\nname = \"a b\"\nhash = \"x\"\n");
        assert!(e.as_deref().is_some_and(|e| e.starts_with("user[0].name")), "{e:?}");
        let e = err("[[user]]\nname = \"a\"\nhash = \"not-phc\"\n");
        assert!(e.as_deref().is_some_and(|e| e.starts_with("user[0].hash")), "{e:?}");
        let e = err(
            "[[user]]\nname = \"a\"\nhash = \"$argon2id$v=19$m=19456,t=2,p=1$c2FsdHNhbHQ$aGFzaGhhc2hoYXNoaGFzaGhhc2hoYXNo\"\n[[user]]\nname = \"a\"\nhash = \"$argon2id$v=19$m=19456,t=2,p=1$c2FsdHNhbHQ$aGFzaGhhc2hoYXNoaGFzaGhhc2hoYXNo\"\n",
        );
        assert!(e.as_deref().is_some_and(|e| e.contains("appears twice")), "{e:?}");
        let e = err("[[user]]\nname = \"a\"\n");
        assert!(e.as_deref().is_some_and(|e| e.contains("hash")), "{e:?}");
        assert!(matches!(Users::default().add("x", ""), Err(UsersError::EmptyPassword)));
    }
}
