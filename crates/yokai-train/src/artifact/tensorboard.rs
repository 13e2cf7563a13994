//! TensorBoard event files (`events.out.tfevents.*`) beside a run's `metrics.jsonl`, so a
//! run can be watched with `tensorboard --logdir runs/`.
//!
//! The format is TensorFlow's: a file of TFRecords (length, masked CRC-32C of the length,
//! bytes, masked CRC-32C of the bytes), each record one `Event` protocol buffer. The
//! messages are declared here with `prost` (the standard Rust protobuf crate) instead of
//! taking a TensorBoard crate: the ones on crates.io pull in old image and protobuf stacks
//! or download TensorFlow's sources at build time, and the four messages a scalar log
//! needs are a few lines each. Field numbers are those of TensorFlow's `event.proto` and
//! `summary.proto`.
//!
//! A resumed run appends a new file that starts with a `SessionLog` START at the resumed
//! step: TensorBoard then drops the earlier files' points past that step, as the run's
//! `metrics.jsonl` drops its lines past the checkpoint.

use prost::Message;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

/// `tensorflow.Event`: one record of an event file.
#[derive(Clone, PartialEq, Message)]
pub struct Event {
    /// Seconds since the Unix epoch.
    #[prost(double, tag = "1")]
    pub wall_time: f64,
    #[prost(int64, tag = "2")]
    pub step: i64,
    #[prost(oneof = "EventWhat", tags = "3, 5, 6")]
    pub what: Option<EventWhat>,
}

/// What an [`Event`] carries.
#[derive(Clone, PartialEq, prost::Oneof)]
pub enum EventWhat {
    /// The first record of every file: `brain.Event:2`.
    #[prost(string, tag = "3")]
    FileVersion(String),
    #[prost(message, tag = "5")]
    Summary(Summary),
    #[prost(message, tag = "6")]
    SessionLog(SessionLog),
}

/// `tensorflow.Summary`: the values logged at one step.
#[derive(Clone, PartialEq, Message)]
pub struct Summary {
    #[prost(message, repeated, tag = "1")]
    pub value: Vec<SummaryValue>,
}

/// `tensorflow.Summary.Value` with a scalar (`simple_value`).
#[derive(Clone, PartialEq, Message)]
pub struct SummaryValue {
    #[prost(string, tag = "1")]
    pub tag: String,
    #[prost(float, optional, tag = "2")]
    pub simple_value: Option<f32>,
}

/// `tensorflow.SessionLog`; status 1 is START.
#[derive(Clone, PartialEq, Message)]
pub struct SessionLog {
    #[prost(int32, tag = "1")]
    pub status: i32,
}

const SESSION_START: i32 = 1;

/// The CRC TFRecord stores: CRC-32C, rotated and offset so that a CRC of CRCs stays apart.
fn masked_crc(bytes: &[u8]) -> u32 {
    let crc = crc32c::crc32c(bytes);
    crc.rotate_right(15).wrapping_add(0xa282_ead8)
}

/// Frame `data` as one TFRecord.
fn record(data: &[u8]) -> Vec<u8> {
    let len = (data.len() as u64).to_le_bytes();
    let mut out = Vec::with_capacity(data.len() + 16);
    out.extend_from_slice(&len);
    out.extend_from_slice(&masked_crc(&len).to_le_bytes());
    out.extend_from_slice(data);
    out.extend_from_slice(&masked_crc(data).to_le_bytes());
    out
}

/// Why an event file does not read back.
#[derive(Debug, thiserror::Error)]
pub enum EventFileError {
    #[error("record {index} at byte {offset}: {problem}")]
    Damaged {
        index: usize,
        offset: usize,
        problem: &'static str,
    },
    #[error("record {index}: not an Event: {source}")]
    Decode {
        index: usize,
        #[source]
        source: prost::DecodeError,
    },
}

/// Every event in the bytes of an event file, each record's CRCs checked.
pub fn read_events(bytes: &[u8]) -> Result<Vec<Event>, EventFileError> {
    let mut events = Vec::new();
    let mut at = 0;
    while at < bytes.len() {
        let index = events.len();
        let damaged = |problem| EventFileError::Damaged {
            index,
            offset: at,
            problem,
        };
        let head = bytes.get(at..at + 12).ok_or_else(|| damaged("cut short"))?;
        let len_bytes: [u8; 8] = head[..8].try_into().expect("8 bytes");
        let len_crc = u32::from_le_bytes(head[8..12].try_into().expect("4 bytes"));
        if masked_crc(&len_bytes) != len_crc {
            return Err(damaged("length CRC does not match"));
        }
        let len = usize::try_from(u64::from_le_bytes(len_bytes))
            .map_err(|_| damaged("length too large"))?;
        let start = at + 12;
        let end = start
            .checked_add(len)
            .filter(|e| e + 4 <= bytes.len())
            .ok_or_else(|| damaged("cut short"))?;
        let data = &bytes[start..end];
        let data_crc = u32::from_le_bytes(bytes[end..end + 4].try_into().expect("4 bytes"));
        if masked_crc(data) != data_crc {
            return Err(damaged("data CRC does not match"));
        }
        events
            .push(Event::decode(data).map_err(|source| EventFileError::Decode { index, source })?);
        at = end + 4;
    }
    Ok(events)
}

/// Writes one event file in a run directory.
pub struct EventWriter {
    path: PathBuf,
    out: BufWriter<File>,
}

impl EventWriter {
    /// A new event file in `dir`, named as TensorFlow names them
    /// (`events.out.tfevents.<seconds>.<host>.<pid>.<n>`, `n` keeping names apart), that
    /// starts with the file version and, when `resumed_at` is given, a session START at
    /// that step.
    pub fn create(dir: &Path, resumed_at: Option<u64>) -> std::io::Result<EventWriter> {
        let now = now();
        let host = std::fs::read_to_string("/etc/hostname")
            .ok()
            .map(|h| h.trim().to_string())
            .filter(|h| !h.is_empty() && !h.contains(['/', '\\']))
            .unwrap_or_else(|| "localhost".into());
        let stem = format!(
            "events.out.tfevents.{}.{host}.{}",
            now as u64,
            std::process::id()
        );
        let (path, file) = (0..)
            .map(|n| dir.join(format!("{stem}.{n}")))
            .find_map(
                |path| match File::options().write(true).create_new(true).open(&path) {
                    Ok(file) => Some(Ok((path, file))),
                    Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => None,
                    Err(e) => Some(Err(e)),
                },
            )
            .expect("some name is free")?;
        let mut writer = EventWriter {
            path,
            out: BufWriter::new(file),
        };
        writer.write(&Event {
            wall_time: now,
            step: 0,
            what: Some(EventWhat::FileVersion("brain.Event:2".into())),
        })?;
        if let Some(step) = resumed_at {
            writer.write(&Event {
                wall_time: now,
                step: step as i64,
                what: Some(EventWhat::SessionLog(SessionLog {
                    status: SESSION_START,
                })),
            })?;
        }
        writer.out.flush()?;
        Ok(writer)
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Log `scalars` (tag, value) at `step`, flushed so that TensorBoard sees them at once.
    pub fn scalars(&mut self, step: u64, scalars: &[(String, f64)]) -> std::io::Result<()> {
        let value = scalars
            .iter()
            .map(|(tag, v)| SummaryValue {
                tag: tag.clone(),
                simple_value: Some(*v as f32),
            })
            .collect();
        self.write(&Event {
            wall_time: now(),
            step: step as i64,
            what: Some(EventWhat::Summary(Summary { value })),
        })?;
        self.out.flush()
    }

    fn write(&mut self, event: &Event) -> std::io::Result<()> {
        self.out.write_all(&record(&event.encode_to_vec()))
    }
}

fn now() -> f64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0.0, |d| d.as_secs_f64())
}

/// The numbers of a JSON object as TensorBoard tags: top-level numbers under `prefix/`,
/// and the numbers of a nested object under its own name (`games/reward`). Fields in
/// `skip`, nulls, strings and arrays are left out.
pub fn scalars_of(value: &serde_json::Value, prefix: &str, skip: &[&str]) -> Vec<(String, f64)> {
    let mut out = Vec::new();
    let Some(object) = value.as_object() else {
        return out;
    };
    for (key, v) in object {
        if skip.contains(&key.as_str()) {
            continue;
        }
        match v {
            serde_json::Value::Number(n) => {
                out.extend(n.as_f64().map(|x| (format!("{prefix}/{key}"), x)));
            }
            serde_json::Value::Object(inner) => out.extend(
                inner
                    .iter()
                    .filter_map(|(k, x)| Some((format!("{key}/{k}"), x.as_f64()?))),
            ),
            _ => {}
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn events_read_back_with_their_steps_tags_and_values() {
        let dir = tempfile::tempdir().unwrap();
        let mut w = EventWriter::create(dir.path(), None).unwrap();
        w.scalars(
            2048,
            &[("games/reward".into(), 1.5), ("train/lr".into(), 0.003)],
        )
        .unwrap();
        w.scalars(4096, &[("games/reward".into(), -2.0)]).unwrap();
        let name = w.path().file_name().unwrap().to_string_lossy().to_string();
        assert!(name.starts_with("events.out.tfevents."), "{name}");
        let events = read_events(&std::fs::read(w.path()).unwrap()).unwrap();
        assert_eq!(events.len(), 3);
        assert_eq!(
            events[0].what,
            Some(EventWhat::FileVersion("brain.Event:2".into()))
        );
        let Some(EventWhat::Summary(s)) = &events[1].what else {
            panic!("not a summary: {:?}", events[1]);
        };
        assert_eq!(events[1].step, 2048);
        assert_eq!(s.value.len(), 2);
        assert_eq!(s.value[0].tag, "games/reward");
        assert_eq!(s.value[0].simple_value, Some(1.5));
        assert_eq!(s.value[1].simple_value, Some(0.003));
        assert_eq!(events[2].step, 4096);
    }

    #[test]
    fn a_resumed_file_starts_a_session_at_its_step_and_names_stay_apart() {
        let dir = tempfile::tempdir().unwrap();
        let a = EventWriter::create(dir.path(), None).unwrap();
        let b = EventWriter::create(dir.path(), Some(10_240)).unwrap();
        assert_ne!(a.path(), b.path());
        let events = read_events(&std::fs::read(b.path()).unwrap()).unwrap();
        assert_eq!(events.len(), 2);
        assert_eq!(events[1].step, 10_240);
        assert_eq!(
            events[1].what,
            Some(EventWhat::SessionLog(SessionLog { status: 1 }))
        );
    }

    #[test]
    fn damage_is_named_by_record() {
        let mut bytes = record(&Event::default().encode_to_vec());
        bytes.extend(record(
            &Event {
                step: 7,
                ..Event::default()
            }
            .encode_to_vec(),
        ));
        assert_eq!(read_events(&bytes).unwrap().len(), 2);
        let n = bytes.len();
        bytes[n - 6] ^= 1;
        let err = read_events(&bytes).unwrap_err().to_string();
        assert!(err.starts_with("record 1 at byte"), "{err}");
        assert!(err.contains("data CRC"), "{err}");
        let err = read_events(&bytes[..n - 3]).unwrap_err().to_string();
        assert!(err.contains("cut short"), "{err}");
    }

    #[test]
    fn scalars_are_the_numbers_of_an_object_and_of_its_objects() {
        let v = serde_json::json!({
            "update": 3, "sps": 10.0, "games": {"reward": 2.5, "length": 20},
            "note": "x", "missing": null
        });
        let mut s = scalars_of(&v, "train", &["update"]);
        s.sort_by(|a, b| a.0.cmp(&b.0));
        assert_eq!(
            s,
            vec![
                ("games/length".to_string(), 20.0),
                ("games/reward".to_string(), 2.5),
                ("train/sps".to_string(), 10.0),
            ]
        );
    }
}
