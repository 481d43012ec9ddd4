//! Input: bridgetwin runs read back into columns. The layer above the output: it sees the
//! records, the generated protobuf types and the topic names, never the scenario or the
//! time loop.
//!
//! - [`read_records`]: one pass over an MCAP file that nothing in the file can crash
//!   (lengths checked against the file's size before anything is allocated, the lengths
//!   inside each record against the record before it is parsed, chunk CRCs checked
//!   before their records are handed on); damage ends the pass with a
//!   [`Damage`] that says where the intact part ends. `inspect`, `simulate --from` and
//!   the Python package read through it.
//! - [`read_run`]: a run (one file, or the hourly parts of a split run in time order) as
//!   one [`Table`] per topic, with its metadata and attachments.

mod chunks;
mod decode;
mod record_lengths;
mod run;
mod stream;
mod table;

pub use decode::{block_value_name, Decoder};
pub use run::{read_run, topic_matches, PartRead, ReadOptions, RunData, TopicData};
pub use stream::{read_records, read_records_with, record_limit_bytes, Damage, End, Flow, Pass};
pub use table::{Column, Table, TableBuilder, Values};
