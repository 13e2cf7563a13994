//! The file format of checkpoints and policy files: a JSON header plus named binary
//! sections, each with a checksum, written atomically.
//!
//! Layout: `YOKAI-TRAIN\n`, format version (u32 LE), header length (u64 LE) and header
//! JSON, section count (u32), then per section: name length (u16) and name, data length
//! (u64), FNV-1a 64 checksum of the data (u64), data. A truncated or altered file is
//! reported with the file and the part that is wrong, never loaded.

use std::io::Write;
use std::path::{Path, PathBuf};

const MAGIC: &[u8] = b"YOKAI-TRAIN\n";
const VERSION: u32 = 1;

/// A file that cannot be read as a checkpoint or policy, with where and why.
#[derive(Debug, thiserror::Error)]
pub enum FileError {
    #[error("{path}: {message}")]
    Io { path: PathBuf, message: String },
    #[error("{path} is not a Yōkai checkpoint or policy file (it does not start with the format's magic bytes)")]
    NotOurs { path: PathBuf },
    #[error("{path} has format version {found}; this build reads version {VERSION}")]
    Version { path: PathBuf, found: u32 },
    #[error("{path} is corrupt: {what}")]
    Corrupt { path: PathBuf, what: String },
    #[error("{path} has no `{section}` section")]
    Missing { path: PathBuf, section: String },
}

/// A header and named sections, in memory.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Container {
    pub header: String,
    pub sections: Vec<(String, Vec<u8>)>,
}

fn fnv1a(data: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in data {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

impl Container {
    pub fn section(&self, path: &Path, name: &str) -> Result<&[u8], FileError> {
        self.sections
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, d)| d.as_slice())
            .ok_or_else(|| FileError::Missing {
                path: path.to_path_buf(),
                section: name.to_string(),
            })
    }

    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::new();
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&VERSION.to_le_bytes());
        out.extend_from_slice(&(self.header.len() as u64).to_le_bytes());
        out.extend_from_slice(self.header.as_bytes());
        out.extend_from_slice(&(self.sections.len() as u32).to_le_bytes());
        for (name, data) in &self.sections {
            out.extend_from_slice(&(name.len() as u16).to_le_bytes());
            out.extend_from_slice(name.as_bytes());
            out.extend_from_slice(&(data.len() as u64).to_le_bytes());
            out.extend_from_slice(&fnv1a(data).to_le_bytes());
            out.extend_from_slice(data);
        }
        out
    }

    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<Container, FileError> {
        let corrupt = |what: &str| FileError::Corrupt {
            path: path.to_path_buf(),
            what: what.to_string(),
        };
        if !bytes.starts_with(MAGIC) {
            return Err(FileError::NotOurs {
                path: path.to_path_buf(),
            });
        }
        let mut at = MAGIC.len();
        let mut take = |n: usize, what: &str| -> Result<&[u8], FileError> {
            if bytes.len() - at < n {
                return Err(corrupt(&format!("truncated in {what}")));
            }
            let s = &bytes[at..at + n];
            at += n;
            Ok(s)
        };
        let u32_of = |s: &[u8]| u32::from_le_bytes(s.try_into().expect("4 bytes"));
        let u64_of = |s: &[u8]| u64::from_le_bytes(s.try_into().expect("8 bytes"));
        let version = u32_of(take(4, "the version")?);
        if version != VERSION {
            return Err(FileError::Version {
                path: path.to_path_buf(),
                found: version,
            });
        }
        let len = u64_of(take(8, "the header length")?) as usize;
        let header = std::str::from_utf8(take(len.min(bytes.len()), "the header")?)
            .map_err(|_| corrupt("the header is not UTF-8"))?
            .to_string();
        let count = u32_of(take(4, "the section count")?);
        let mut sections = Vec::new();
        for i in 0..count {
            let n = u16::from_le_bytes(take(2, "a section name")?.try_into().expect("2")) as usize;
            let name = String::from_utf8_lossy(take(n, "a section name")?).to_string();
            let len = u64_of(take(8, &format!("section `{name}`"))?) as usize;
            let sum = u64_of(take(8, &format!("section `{name}`"))?);
            let data = take(len.min(bytes.len()), &format!("section `{name}` (#{i})"))?;
            if fnv1a(data) != sum {
                return Err(corrupt(&format!("section `{name}` fails its checksum")));
            }
            sections.push((name, data.to_vec()));
        }
        Ok(Container { header, sections })
    }

    pub fn read(path: &Path) -> Result<Container, FileError> {
        let bytes = std::fs::read(path).map_err(|e| FileError::Io {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
        Container::from_bytes(&bytes, path)
    }

    /// Write to a temporary file beside `path`, flush it to disk, then rename it over
    /// `path`: a crash at any point leaves either the old file or the new one, whole.
    pub fn write_atomic(&self, path: &Path) -> Result<(), FileError> {
        let io = |e: std::io::Error| FileError::Io {
            path: path.to_path_buf(),
            message: e.to_string(),
        };
        let tmp = path.with_extension("tmp");
        {
            let mut f = std::fs::File::create(&tmp).map_err(io)?;
            f.write_all(&self.to_bytes()).map_err(io)?;
            f.sync_all().map_err(io)?;
        }
        std::fs::rename(&tmp, path).map_err(io)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Container {
        Container {
            header: "{\"a\":1}".into(),
            sections: vec![("model".into(), vec![1, 2, 3]), ("state".into(), vec![])],
        }
    }

    #[test]
    fn round_trip() {
        let c = sample();
        assert_eq!(
            Container::from_bytes(&c.to_bytes(), Path::new("x")).unwrap(),
            c
        );
    }

    #[test]
    fn every_truncation_and_any_flipped_data_byte_is_an_error() {
        let bytes = sample().to_bytes();
        for n in 0..bytes.len() {
            assert!(
                Container::from_bytes(&bytes[..n], Path::new("x")).is_err(),
                "{n}"
            );
        }
        let mut bad = bytes.clone();
        // The last section (`state`, empty) takes 2 + 5 + 8 + 8 bytes; `model`'s 3 data
        // bytes come just before it.
        let at = bad.len() - 23 - 2;
        bad[at] ^= 0xff;
        let e = Container::from_bytes(&bad, Path::new("ckpt")).unwrap_err();
        assert!(e.to_string().contains("ckpt is corrupt"), "{e}");
        let e = Container::from_bytes(b"hello", Path::new("f")).unwrap_err();
        assert!(matches!(e, FileError::NotOurs { .. }));
    }
}
