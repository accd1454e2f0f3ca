//! TensorBoard event files beside `metrics.csv`: every numeric column of every row as a
//! scalar (the row's sample count is the step), and the run's config as text, so that
//! `tensorboard --logdir runs/` shows a sweep's runs live. The format is TensorFlow's
//! `Event` protobuf in TFRecord framing; the few messages are declared here for `prost`,
//! and the framing's checksums are CRC-32C (`crc32c`). No TensorBoard crate is both
//! maintained and small (docs/architecture.md).
//!
//! One file per run folder. A resumed run rewrites it from the rows metrics.csv keeps,
//! then appends: the curves continue without the killed run's duplicate steps.

use crate::error::TrainError;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::time::{SystemTime, UNIX_EPOCH};

use prost::Message;

use crate::metrics::IterationMetrics;

/// tensorflow/core/util/event.proto: `Event`, with the fields written here.
#[derive(Clone, PartialEq, Message)]
struct Event {
    #[prost(double, tag = "1")]
    wall_time: f64,
    #[prost(int64, tag = "2")]
    step: i64,
    #[prost(string, optional, tag = "3")]
    file_version: Option<String>,
    #[prost(message, optional, tag = "5")]
    summary: Option<Summary>,
}

/// tensorflow/core/framework/summary.proto.
#[derive(Clone, PartialEq, Message)]
struct Summary {
    #[prost(message, repeated, tag = "1")]
    value: Vec<SummaryValue>,
}

#[derive(Clone, PartialEq, Message)]
struct SummaryValue {
    #[prost(string, tag = "1")]
    tag: String,
    #[prost(float, optional, tag = "2")]
    simple_value: Option<f32>,
    #[prost(message, optional, tag = "8")]
    tensor: Option<TensorProto>,
    #[prost(message, optional, tag = "9")]
    metadata: Option<SummaryMetadata>,
}

#[derive(Clone, PartialEq, Message)]
struct SummaryMetadata {
    #[prost(message, optional, tag = "1")]
    plugin_data: Option<PluginData>,
}

#[derive(Clone, PartialEq, Message)]
struct PluginData {
    #[prost(string, tag = "1")]
    plugin_name: String,
}

/// tensorflow/core/framework/tensor.proto: a scalar string tensor.
#[derive(Clone, PartialEq, Message)]
struct TensorProto {
    #[prost(int32, tag = "1")]
    dtype: i32,
    #[prost(message, optional, tag = "2")]
    tensor_shape: Option<TensorShape>,
    #[prost(bytes = "vec", repeated, tag = "8")]
    string_val: Vec<Vec<u8>>,
}

#[derive(Clone, PartialEq, Message)]
struct TensorShape {}

/// `DataType::DT_STRING`.
const DT_STRING: i32 = 7;

/// TFRecord's checksum: CRC-32C, rotated and offset.
fn masked_crc(bytes: &[u8]) -> u32 {
    let crc = crc32c::crc32c(bytes);
    crc.rotate_right(15).wrapping_add(0xa282_ead8)
}

/// An open event file.
pub struct EventWriter {
    path: PathBuf,
    file: BufWriter<File>,
}

fn now() -> f64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0.0, |d| d.as_secs_f64())
}

fn io(path: &Path, e: std::io::Error) -> TrainError {
    TrainError::io(path, e)
}

impl EventWriter {
    /// A new event file in `dir` holding the config (as text) and `rows`, replacing the
    /// folder's earlier event files once it is complete.
    pub fn create(
        dir: &Path,
        config_text: &str,
        rows: &[IterationMetrics],
    ) -> Result<Self, TrainError> {
        let name = format!("events.out.tfevents.{:.0}.logo", now());
        let path = dir.join(&name);
        let tmp = dir.join(format!("{name}.tmp.{}", std::process::id()));
        let file = File::create(&tmp).map_err(|e| io(&tmp, e))?;
        let mut writer = Self {
            path: tmp.clone(),
            file: BufWriter::new(file),
        };
        writer.write(&Event {
            wall_time: now(),
            file_version: Some("brain.Event:2".into()),
            ..Event::default()
        })?;
        writer.write(&Event {
            wall_time: now(),
            step: 0,
            summary: Some(Summary {
                value: vec![text("config", config_text)],
            }),
            ..Event::default()
        })?;
        for row in rows {
            writer.append(row)?;
        }
        writer.file.flush().map_err(|e| io(&tmp, e))?;
        std::fs::rename(&tmp, &path).map_err(|e| io(&path, e))?;
        writer.path = path.clone();
        for entry in std::fs::read_dir(dir).map_err(|e| io(dir, e))?.flatten() {
            let other = entry.path();
            let file_name = entry.file_name().to_string_lossy().into_owned();
            if other != path && file_name.starts_with("events.out.tfevents.") {
                std::fs::remove_file(&other).map_err(|e| io(&other, e))?;
            }
        }
        Ok(writer)
    }

    /// Appends `row` and flushes, so that a reader sees it at once.
    pub fn append(&mut self, row: &IterationMetrics) -> Result<(), TrainError> {
        let value = scalars(row)
            .into_iter()
            .map(|(tag, v)| SummaryValue {
                tag,
                simple_value: Some(v as f32),
                ..SummaryValue::default()
            })
            .collect();
        self.write(&Event {
            wall_time: now(),
            step: row.samples as i64,
            summary: Some(Summary { value }),
            ..Event::default()
        })?;
        self.file.flush().map_err(|e| io(&self.path, e))
    }

    fn write(&mut self, event: &Event) -> Result<(), TrainError> {
        let data = event.encode_to_vec();
        let length = (data.len() as u64).to_le_bytes();
        let mut record = Vec::with_capacity(data.len() + 16);
        record.extend_from_slice(&length);
        record.extend_from_slice(&masked_crc(&length).to_le_bytes());
        record.extend_from_slice(&data);
        record.extend_from_slice(&masked_crc(&data).to_le_bytes());
        self.file.write_all(&record).map_err(|e| io(&self.path, e))
    }
}

/// A text summary (TensorBoard's text plugin).
fn text(tag: &str, content: &str) -> SummaryValue {
    SummaryValue {
        tag: tag.into(),
        tensor: Some(TensorProto {
            dtype: DT_STRING,
            tensor_shape: Some(TensorShape {}),
            string_val: vec![content.as_bytes().to_vec()],
        }),
        metadata: Some(SummaryMetadata {
            plugin_data: Some(PluginData {
                plugin_name: "text".into(),
            }),
        }),
        ..SummaryValue::default()
    }
}

/// Every numeric, finite column of `row`, by its metrics.csv name (the iteration and
/// sample counts included; the stop reasons, which are words, left out).
pub fn scalars(row: &IterationMetrics) -> Vec<(String, f64)> {
    let value = serde_json::to_value(row).expect("a metrics row serialises");
    let serde_json::Value::Object(fields) = value else {
        unreachable!("a struct serialises to an object")
    };
    fields
        .into_iter()
        .filter_map(|(name, v)| v.as_f64().filter(|v| v.is_finite()).map(|v| (name, v)))
        .collect()
}
