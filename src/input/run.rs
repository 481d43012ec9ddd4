//! A run read back from its MCAP file, or from the hourly parts of a split run joined in
//! time order: every topic (or the chosen ones) as a [`Table`], the metadata records,
//! the attachments, and what damage cut the reading short.

use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

use mcap::records::Record;

use super::decode::Decoder;
use super::stream::{read_records, Damage, Flow};
use super::table::{Table, TableBuilder};
use crate::error::{Error, Result};

/// Which topics to read.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ReadOptions {
    /// Topic names or patterns where `*` stands for any run of characters, `/` included
    /// (`/sensors/*`). `None`: every topic. A name without `*` that no part holds is an
    /// error naming the topics there are.
    pub topics: Option<Vec<String>>,
}

/// One topic of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct TopicData {
    pub schema: String,
    /// The channel metadata (`unit`, `sample_rate_hz`, `position_m`, ...).
    pub metadata: BTreeMap<String, String>,
    pub table: Table,
}

/// One file read.
#[derive(Debug, Clone, PartialEq)]
pub struct PartRead {
    pub path: PathBuf,
    /// The `split` metadata's part number (`None`: not a part of a split run).
    pub part: Option<u64>,
    pub messages: u64,
    /// Why the file was read only up to some point.
    pub damage: Option<Damage>,
}

/// What [`read_run`] returns.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RunData {
    /// Every topic read, by name.
    pub topics: BTreeMap<String, TopicData>,
    /// The metadata records of the first part (`bridgetwin`, `scenario`, `bridge_model`);
    /// `split` holds the first part's.
    pub metadata: BTreeMap<String, BTreeMap<String, String>>,
    /// The attachments of the first part (`scenario.toml`, `road_profile.csv`).
    pub attachments: BTreeMap<String, Vec<u8>>,
    /// Unix-epoch ns of the run's t = 0 (the `bridgetwin` record's `start_time`, else the
    /// first log time): `time_s` counts from here.
    pub start_time_ns: u64,
    /// The files in the order read (time order).
    pub parts: Vec<PartRead>,
    /// Topics skipped because their schema is not one of the output contract's.
    pub undecoded: BTreeMap<String, String>,
}

impl RunData {
    /// The damage found, with the file it is in.
    pub fn damage(&self) -> impl Iterator<Item = (&Path, &Damage)> {
        self.parts
            .iter()
            .filter_map(|p| Some((p.path.as_path(), p.damage.as_ref()?)))
    }

    /// The resolved scenario (the `scenario` metadata record's TOML).
    pub fn scenario_toml(&self) -> Option<&str> {
        self.metadata
            .get("scenario")?
            .get("toml")
            .map(String::as_str)
    }
}

/// Whether `topic` matches `pattern` (`*`: any run of characters).
pub fn topic_matches(pattern: &str, topic: &str) -> bool {
    let mut pieces = pattern.split('*');
    let first = pieces.next().unwrap_or("");
    let Some(mut rest) = topic.strip_prefix(first) else {
        return false;
    };
    let pieces: Vec<&str> = pieces.collect();
    let Some((last, middle)) = pieces.split_last() else {
        return rest.is_empty();
    };
    for piece in middle {
        match rest.find(piece) {
            Some(i) => rest = &rest[i + piece.len()..],
            None => return false,
        }
    }
    rest.len() >= last.len() && rest.ends_with(last)
}

/// Reads one run from `paths`: one file, or the parts of a split run in any order (they
/// are put in order of their `split` part number, else their first log time). Parts of
/// different runs are refused. A damaged or cut-short file is read up to the damage (see
/// [`RunData::damage`]); a file that is no MCAP at all is an error naming it.
pub fn read_run(paths: &[PathBuf], options: &ReadOptions) -> Result<RunData> {
    if paths.is_empty() {
        return Err(Error::File {
            path: String::new(),
            reason: "no file to read (an empty list, or a pattern that matched nothing)".into(),
        });
    }
    let mut heads = paths
        .iter()
        .map(|p| head(p).map(|h| (p.clone(), h)))
        .collect::<Result<Vec<_>>>()?;
    heads.sort_by(|a, b| {
        let key = |h: &Head| (h.part, h.first_log_time_ns);
        key(&a.1).cmp(&key(&b.1)).then_with(|| a.0.cmp(&b.0))
    });
    check_one_run(&heads)?;
    let mut reader = Reader::new(options);
    for (path, head) in &heads {
        reader.part(path, head)?;
    }
    reader.finish()
}

/// What the records before the first message say about a file.
#[derive(Debug, Clone, Default)]
struct Head {
    part: Option<u64>,
    first_log_time_ns: Option<u64>,
    /// `bridgetwin` metadata: seed and start time, which name the run.
    run: Option<(String, String)>,
}

fn head(path: &Path) -> Result<Head> {
    let mut head = Head::default();
    read_records(path, |record| {
        match record {
            Record::Metadata(m) if m.name == "split" => {
                head.part = m.metadata.get("part").and_then(|p| p.parse().ok());
            }
            Record::Metadata(m) if m.name == "bridgetwin" => {
                let get = |k: &str| m.metadata.get(k).cloned().unwrap_or_default();
                head.run = Some((get("seed"), get("start_time")));
            }
            Record::Message { header, .. } => {
                head.first_log_time_ns = Some(header.log_time);
                return Ok(Flow::Stop);
            }
            _ => {}
        }
        Ok(Flow::Continue)
    })?;
    Ok(head)
}

fn check_one_run(heads: &[(PathBuf, Head)]) -> Result<()> {
    let Some((first_path, first)) = heads.first() else {
        return Ok(());
    };
    for pair in heads.windows(2) {
        let (path, head) = &pair[1];
        if head.run != first.run {
            let show = |h: &Head| match &h.run {
                Some((seed, start)) => format!("seed {seed}, start {start}"),
                None => "no bridgetwin metadata".into(),
            };
            return Err(Error::File {
                path: path.display().to_string(),
                reason: format!(
                    "not a part of the same run as {} ({} there, {} here)",
                    first_path.display(),
                    show(first),
                    show(head)
                ),
            });
        }
        if head.part.is_some() && head.part == pair[0].1.part {
            return Err(Error::File {
                path: path.display().to_string(),
                reason: format!(
                    "part {} is given twice (also {})",
                    head.part.unwrap_or_default(),
                    pair[0].0.display()
                ),
            });
        }
    }
    Ok(())
}

/// A channel of the part being read.
struct Channel {
    topic: String,
    decoder: Option<Decoder>,
    wanted: bool,
}

struct Reader<'a> {
    options: &'a ReadOptions,
    builders: BTreeMap<String, (String, BTreeMap<String, String>, TableBuilder)>,
    run: RunData,
    first_part: bool,
    first_log_time_ns: Option<u64>,
    /// Every topic any part declared (for the error on a name no part holds).
    declared: BTreeMap<String, ()>,
}

impl<'a> Reader<'a> {
    fn new(options: &'a ReadOptions) -> Self {
        Reader {
            options,
            builders: BTreeMap::new(),
            run: RunData::default(),
            first_part: true,
            first_log_time_ns: None,
            declared: BTreeMap::new(),
        }
    }

    fn wanted(&self, topic: &str) -> bool {
        match &self.options.topics {
            None => true,
            Some(patterns) => patterns.iter().any(|p| topic_matches(p, topic)),
        }
    }

    fn part(&mut self, path: &Path, head: &Head) -> Result<()> {
        let mut schemas: HashMap<u16, String> = HashMap::new();
        let mut channels: HashMap<u16, Channel> = HashMap::new();
        let first_part = self.first_part;
        self.first_part = false;
        let pass = read_records(path, |record| {
            match record {
                Record::Schema { header, .. } => {
                    schemas.insert(header.id, header.name);
                }
                Record::Channel(c) => {
                    if channels.contains_key(&c.id) {
                        // The summary repeats every channel.
                        return Ok(Flow::Continue);
                    }
                    let schema = schemas.get(&c.schema_id).cloned().unwrap_or_default();
                    let wanted = self.wanted(&c.topic);
                    let decoder = Decoder::for_schema(&schema);
                    self.declared.insert(c.topic.clone(), ());
                    if wanted && decoder.is_none() {
                        self.run.undecoded.insert(c.topic.clone(), schema.clone());
                    }
                    if wanted && decoder.is_some() {
                        self.builders.entry(c.topic.clone()).or_insert_with(|| {
                            (schema, c.metadata.clone(), TableBuilder::default())
                        });
                    }
                    channels.insert(
                        c.id,
                        Channel {
                            topic: c.topic,
                            decoder,
                            wanted,
                        },
                    );
                }
                Record::Message { header, data } => {
                    let first = self.first_log_time_ns.get_or_insert(header.log_time);
                    *first = (*first).min(header.log_time);
                    let Some(channel) = channels.get(&header.channel_id) else {
                        return Err(format!(
                            "message {} is on channel {}, which no record declared",
                            header.sequence, header.channel_id
                        ));
                    };
                    if let (true, Some(decoder)) = (channel.wanted, channel.decoder) {
                        if let Some((_, _, table)) = self.builders.get_mut(&channel.topic) {
                            decoder
                                .decode(&data, header.log_time, table)
                                .map_err(|e| format!("{}: {e}", channel.topic))?;
                        }
                    }
                }
                Record::Metadata(m) if first_part => {
                    self.run.metadata.entry(m.name).or_insert(m.metadata);
                }
                Record::Attachment { header, data, .. } if first_part => {
                    self.run
                        .attachments
                        .entry(header.name)
                        .or_insert_with(|| data.into_owned());
                }
                _ => {}
            }
            Ok(Flow::Continue)
        })?;
        self.run.parts.push(PartRead {
            path: path.to_path_buf(),
            part: head.part,
            messages: pass.messages,
            damage: pass.damage().cloned(),
        });
        Ok(())
    }

    fn finish(mut self) -> Result<RunData> {
        if let Some(patterns) = &self.options.topics {
            let missing: Vec<&String> = patterns
                .iter()
                .filter(|p| !p.contains('*') && !self.declared.contains_key(p.as_str()))
                .collect();
            if let Some(name) = missing.first() {
                let there: Vec<&String> = self.declared.keys().collect();
                return Err(Error::invalid(
                    "topics",
                    name,
                    format!("is not a topic of this run; its topics: {there:?}"),
                ));
            }
        }
        self.run.start_time_ns = self
            .run
            .metadata
            .get("bridgetwin")
            .and_then(|m| m.get("start_time"))
            .and_then(|t| chrono::DateTime::parse_from_rfc3339(t).ok())
            .and_then(|t| u64::try_from(t.timestamp_nanos_opt()?).ok())
            .or(self.first_log_time_ns)
            .unwrap_or(0);
        for (topic, (schema, metadata, builder)) in std::mem::take(&mut self.builders) {
            let mut table = builder.build();
            if table.rows == 0 {
                if let Some(decoder) = Decoder::for_schema(&schema) {
                    table = decoder.empty_table(metadata.get("unit").map(String::as_str));
                }
            }
            table.finish(self.run.start_time_ns);
            self.run.topics.insert(
                topic,
                TopicData {
                    schema,
                    metadata,
                    table,
                },
            );
        }
        Ok(self.run)
    }
}

#[cfg(test)]
mod tests {
    use super::topic_matches;

    #[test]
    fn patterns_match_runs_of_characters() {
        assert!(topic_matches("/sensors/*", "/sensors/accel/A1"));
        assert!(topic_matches("/sensors/accel/A1", "/sensors/accel/A1"));
        assert!(!topic_matches("/sensors/accel/A1", "/sensors/accel/A10"));
        assert!(topic_matches("/*/accel/*", "/preview/accel/A1"));
        assert!(topic_matches("*A1", "/truth/sensors/A1"));
        assert!(!topic_matches("*A1", "/truth/sensors/A10"));
        assert!(topic_matches("*", "/events"));
        assert!(!topic_matches("/wim/*x", "/wim/W1"));
        assert!(topic_matches("/a*b*c", "/abbc"));
        assert!(!topic_matches("/a*bc*bc", "/abc"));
    }
}
