//! Compiles `schemas/**/*.proto` with the pure-Rust `protox` compiler (no system `protoc`)
//! and generates the Rust types with `prost-build`.
//!
//! Outputs in `OUT_DIR`:
//! - `bridgetwin_descriptors.bin`: the encoded `FileDescriptorSet` of every schema file and
//!   its imports (`google/protobuf/timestamp.proto`), topologically ordered; `sink` cuts
//!   one self-contained set per message out of it for the MCAP schema records.
//! - `bridgetwin.v1.rs`, `foxglove.rs`: the generated messages.

use std::path::{Path, PathBuf};

const SCHEMA_DIR: &str = "schemas";

fn main() -> Result<(), Box<dyn std::error::Error>> {
    println!("cargo:rerun-if-changed={SCHEMA_DIR}");
    git_revision();
    let mut proto_files = Vec::new();
    collect_protos(Path::new(SCHEMA_DIR), &mut proto_files)?;
    // Sorted so that the descriptor set, hence the MCAP bytes, never depend on readdir order.
    proto_files.sort();

    let mut compiler = protox::Compiler::new([SCHEMA_DIR])?;
    compiler
        .include_imports(true)
        .include_source_info(false)
        .open_files(&proto_files)?;

    let out_dir = PathBuf::from(std::env::var("OUT_DIR")?);
    std::fs::write(
        out_dir.join("bridgetwin_descriptors.bin"),
        compiler.encode_file_descriptor_set(),
    )?;

    // Code generation gets the source info too: it turns the .proto comments (with their
    // units) into doc comments. google.protobuf types map to prost-types (extern paths);
    // their descriptors stay in the set because prost-build inspects them.
    compiler.include_source_info(true);
    prost_build::Config::new()
        .enable_type_names()
        // BTreeMap: encoding a `map<>` field iterates it, so a HashMap would make the
        // output bytes differ between runs.
        .btree_map(["."])
        .compile_fds(compiler.file_descriptor_set())?;
    Ok(())
}

/// Sets `BRIDGETWIN_GIT_REVISION` for the crate: the value given at build time if any
/// (builds from a source archive), else `git describe --always --dirty --abbrev=12` of the
/// source tree, else nothing (the crate then says "unknown"). Rerun when HEAD moves (a
/// commit, a checkout) or a source file changes (the tree turns dirty). Not on a change of
/// the index: `git status` and other tools rewrite it without changing anything, and each
/// rewrite would rebuild the whole crate (four minutes in CI).
fn git_revision() {
    println!("cargo:rerun-if-env-changed=BRIDGETWIN_GIT_REVISION");
    if std::env::var_os("BRIDGETWIN_GIT_REVISION").is_some() {
        return;
    }
    let git = |args: &[&str]| {
        std::process::Command::new("git")
            .args(args)
            .output()
            .ok()
            .filter(|out| out.status.success())
            .and_then(|out| String::from_utf8(out.stdout).ok())
            .map(|text| text.trim().to_string())
    };
    if let Some(path) = git(&["rev-parse", "--git-path", "HEAD"]) {
        println!("cargo:rerun-if-changed={path}");
    }
    for sources in ["src", "Cargo.toml", "build.rs"] {
        println!("cargo:rerun-if-changed={sources}");
    }
    if let Some(head_ref) = git(&["symbolic-ref", "-q", "HEAD"]) {
        if let Some(path) = git(&["rev-parse", "--git-path", &head_ref]) {
            println!("cargo:rerun-if-changed={path}");
        }
    }
    if let Some(revision) = git(&["describe", "--always", "--dirty", "--abbrev=12"]) {
        println!("cargo:rustc-env=BRIDGETWIN_GIT_REVISION={revision}");
    }
}

fn collect_protos(dir: &Path, out: &mut Vec<PathBuf>) -> std::io::Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let path = entry?.path();
        if path.is_dir() {
            collect_protos(&path, out)?;
        } else if path.extension().is_some_and(|e| e == "proto") {
            out.push(path);
        }
    }
    Ok(())
}
