//! The file format of checkpoints and policy files: a JSON header plus named binary
//! sections, each with a checksum, written atomically.
//!
//! Layout: `YOKAI-TRAIN\n`, format version (u32 LE), header length (u64 LE), header JSON and
//! its FNV-1a 64 checksum (u64; from version 2), section count (u32), then per section: name
//! length (u16) and name, data length (u64), FNV-1a 64 checksum of the name and data (u64;
//! of the data alone in version 1), data,
//! and nothing after the last section. A truncated, extended or altered file is reported
//! with the file and the part that is wrong, never loaded. Version 1 files (no header
//! checksum) are still read.

use crate::error::FileError;
use std::io::Write;
use std::path::Path;
use yokai_engine::digest::{fnv1a, Fnv1a};

pub(crate) const MAGIC: &[u8] = b"YOKAI-TRAIN\n";
const VERSION: u32 = 2;
/// Versions this build reads.
const READABLE: [u32; 2] = [1, 2];

/// A header and named sections, in memory.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Container {
    pub header: String,
    pub sections: Vec<(String, Vec<u8>)>,
}

/// A section's checksum: of its name and data from version 2, of its data in version 1.
fn section_sum(version: u32, name: &[u8], data: &[u8]) -> u64 {
    if version >= 2 {
        Fnv1a::default().update(name).update(data).finish()
    } else {
        fnv1a(data)
    }
}

impl Container {
    /// The section `name`, if the file has one (for sections only some files hold).
    pub fn get(&self, name: &str) -> Option<&[u8]> {
        (self.sections.iter())
            .find(|(n, _)| n == name)
            .map(|(_, d)| d.as_slice())
    }

    /// The section `name`, which the file must hold.
    pub fn section(&self, path: &Path, name: &str) -> Result<&[u8], FileError> {
        self.get(name).ok_or_else(|| FileError::Missing {
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
        out.extend_from_slice(&fnv1a(self.header.as_bytes()).to_le_bytes());
        out.extend_from_slice(&(self.sections.len() as u32).to_le_bytes());
        for (name, data) in &self.sections {
            out.extend_from_slice(&(name.len() as u16).to_le_bytes());
            out.extend_from_slice(name.as_bytes());
            out.extend_from_slice(&(data.len() as u64).to_le_bytes());
            out.extend_from_slice(&section_sum(VERSION, name.as_bytes(), data).to_le_bytes());
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
        if !READABLE.contains(&version) {
            return Err(FileError::Version {
                path: path.to_path_buf(),
                found: version,
                reads: VERSION,
            });
        }
        let len = u64_of(take(8, "the header length")?) as usize;
        let header_bytes = take(len.min(bytes.len()), "the header")?;
        if version >= 2 && u64_of(take(8, "the header checksum")?) != fnv1a(header_bytes) {
            return Err(corrupt("the header fails its checksum"));
        }
        let header = std::str::from_utf8(header_bytes)
            .map_err(|_| corrupt("the header is not UTF-8"))?
            .to_string();
        let count = u32_of(take(4, "the section count")?);
        let mut sections = Vec::new();
        for i in 0..count {
            let n = u16::from_le_bytes(take(2, "a section name")?.try_into().expect("2")) as usize;
            let name_bytes = take(n, "a section name")?;
            let name = String::from_utf8_lossy(name_bytes).to_string();
            let len = u64_of(take(8, &format!("section `{name}`"))?) as usize;
            let sum = u64_of(take(8, &format!("section `{name}`"))?);
            let data = take(len.min(bytes.len()), &format!("section `{name}` (#{i})"))?;
            if section_sum(version, name_bytes, data) != sum {
                return Err(corrupt(&format!("section `{name}` fails its checksum")));
            }
            sections.push((name, data.to_vec()));
        }
        if at != bytes.len() {
            return Err(corrupt(&format!(
                "{} bytes after the last section",
                bytes.len() - at
            )));
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

    /// Every single-byte change anywhere in the file — header, lengths, names, data — and
    /// every byte appended is refused: no altered file loads.
    #[test]
    fn any_changed_or_appended_byte_is_an_error() {
        let bytes = sample().to_bytes();
        for at in MAGIC.len()..bytes.len() {
            let mut bad = bytes.clone();
            bad[at] ^= 0x01;
            assert!(
                Container::from_bytes(&bad, Path::new("x")).is_err(),
                "byte {at}"
            );
        }
        let mut longer = bytes.clone();
        longer.push(0);
        let e = Container::from_bytes(&longer, Path::new("x")).unwrap_err();
        assert!(
            e.to_string().contains("1 bytes after the last section"),
            "{e}"
        );
    }

    /// Files written by version 1 (no header checksum) still read.
    #[test]
    fn version_one_files_still_read() {
        let c = sample();
        let mut v1 = Vec::new();
        v1.extend_from_slice(MAGIC);
        v1.extend_from_slice(&1u32.to_le_bytes());
        v1.extend_from_slice(&(c.header.len() as u64).to_le_bytes());
        v1.extend_from_slice(c.header.as_bytes());
        v1.extend_from_slice(&(c.sections.len() as u32).to_le_bytes());
        for (name, data) in &c.sections {
            v1.extend_from_slice(&(name.len() as u16).to_le_bytes());
            v1.extend_from_slice(name.as_bytes());
            v1.extend_from_slice(&(data.len() as u64).to_le_bytes());
            v1.extend_from_slice(&fnv1a(data).to_le_bytes());
            v1.extend_from_slice(data);
        }
        assert_eq!(Container::from_bytes(&v1, Path::new("old")).unwrap(), c);
        let mut v3 = c.to_bytes();
        v3[MAGIC.len()] = 3;
        let e = Container::from_bytes(&v3, Path::new("new")).unwrap_err();
        assert!(matches!(e, FileError::Version { found: 3, .. }), "{e}");
    }
}
