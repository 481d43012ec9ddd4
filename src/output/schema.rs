//! MCAP schema data: one self-contained `FileDescriptorSet` per message type.
//!
//! `build.rs` stores one set holding every schema file plus its imports. A schema record
//! must hold the file that defines its message and that file's transitive imports, each
//! exactly once (a duplicated file makes Python's `mcap-protobuf-support` refuse it), so
//! the set is cut per message here.

use std::collections::{BTreeMap, BTreeSet};
use std::sync::{Mutex, OnceLock};

use prost::Message;
use prost_types::{FileDescriptorProto, FileDescriptorSet};

use crate::error::{Error, Result};

/// Every schema file and its imports, topologically sorted (imports first), as written by
/// `build.rs`.
pub const ALL_DESCRIPTORS: &[u8] =
    include_bytes!(concat!(env!("OUT_DIR"), "/bridgetwin_descriptors.bin"));

/// Encoded `FileDescriptorSet` for the top-level message `full_name` (e.g.
/// `bridgetwin.v1.AxleLoads`): its file and transitive imports, in dependency order.
/// Cut once per process and message: a run registers its channels twice (the estimate's
/// sizing, then the file), a sweep once per run, and decoding the whole set cost about
/// 1 ms each time.
pub fn self_contained_descriptor_set(full_name: &str) -> Result<Vec<u8>> {
    static CUT: OnceLock<Mutex<BTreeMap<String, Vec<u8>>>> = OnceLock::new();
    let cut = CUT.get_or_init(Default::default);
    // A poisoned lock only means another thread panicked mid-insert: the map holds
    // finished sets, still valid.
    let known = cut
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .get(full_name)
        .cloned();
    if let Some(data) = known {
        return Ok(data);
    }
    let data = cut_descriptor_set(full_name)?;
    let mut map = cut.lock().unwrap_or_else(|e| e.into_inner());
    map.insert(full_name.to_owned(), data.clone());
    Ok(data)
}

fn cut_descriptor_set(full_name: &str) -> Result<Vec<u8>> {
    static ALL: OnceLock<std::result::Result<FileDescriptorSet, prost::DecodeError>> =
        OnceLock::new();
    let all = ALL.get_or_init(|| FileDescriptorSet::decode(ALL_DESCRIPTORS));
    let all = all.as_ref().map_err(|e| schema_error(full_name, e))?;
    let defining = all
        .file
        .iter()
        .find(|f| defines_message(f, full_name))
        .ok_or_else(|| schema_error(full_name, "no schema file defines this message"))?;

    let mut needed = BTreeSet::new();
    let mut stack = vec![defining.name().to_owned()];
    while let Some(name) = stack.pop() {
        if !needed.insert(name.clone()) {
            continue;
        }
        let file = all
            .file
            .iter()
            .find(|f| f.name() == name)
            .ok_or_else(|| schema_error(full_name, format!("import {name} is missing")))?;
        stack.extend(file.dependency.iter().cloned());
    }
    // Filtering keeps the topological order of the full set.
    let file = (all.file.iter())
        .filter(|f| needed.contains(f.name()))
        .cloned()
        .collect();
    Ok(FileDescriptorSet { file }.encode_to_vec())
}

fn defines_message(file: &FileDescriptorProto, full_name: &str) -> bool {
    let relative = if file.package().is_empty() {
        Some(full_name)
    } else {
        full_name
            .strip_prefix(file.package())
            .and_then(|rest| rest.strip_prefix('.'))
    };
    relative.is_some_and(|rest| {
        // Nested types (`Outer.Inner`) live in their top-level message's file.
        let top = rest.split('.').next().unwrap_or(rest);
        file.message_type.iter().any(|m| m.name() == top)
    })
}

fn schema_error(full_name: &str, reason: impl std::fmt::Display) -> Error {
    Error::Output {
        path: format!("schema {full_name}"),
        reason: reason.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file_names(bytes: &[u8]) -> Vec<String> {
        FileDescriptorSet::decode(bytes)
            .unwrap()
            .file
            .iter()
            .map(|f| f.name().to_owned())
            .collect()
    }

    #[test]
    fn set_holds_defining_file_and_imports_once_in_order() {
        let names = file_names(&self_contained_descriptor_set("bridgetwin.v1.AxleLoads").unwrap());
        assert_eq!(
            names,
            [
                "google/protobuf/timestamp.proto",
                "bridgetwin/v1/vehicles.proto"
            ]
        );
        let names = file_names(&self_contained_descriptor_set("foxglove.Log").unwrap());
        assert_eq!(
            names,
            ["google/protobuf/timestamp.proto", "foxglove/Log.proto"]
        );
    }

    #[test]
    fn unknown_message_is_an_error() {
        assert!(self_contained_descriptor_set("bridgetwin.v1.Nope").is_err());
        // A package prefix alone must not match.
        assert!(self_contained_descriptor_set("bridgetwin.v1").is_err());
    }
}
