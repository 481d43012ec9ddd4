//! The `bridgetwin` metadata record of a run says which software wrote it: the version and
//! the source revision of the build (`git describe`, from build.rs), or the revision given
//! at run time in `BRIDGETWIN_RUN_REVISION`.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

/// The `bridgetwin` metadata record of a default run of 1 s, with `env` set.
fn bridgetwin_metadata(dir: &Path, env: Option<&str>) -> BTreeMap<String, String> {
    let out = dir.join("run.mcap");
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_bridgetwin"));
    cmd.args([
        "simulate",
        "--duration-s",
        "1",
        "--force",
        "--quiet",
        "--out",
    ])
    .arg(&out)
    .env_remove("BRIDGETWIN_RUN_REVISION");
    if let Some(revision) = env {
        cmd.env("BRIDGETWIN_RUN_REVISION", revision);
    }
    assert!(cmd.status().unwrap().success());
    let bytes = std::fs::read(&out).unwrap();
    let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
    for index in &summary.metadata_indexes {
        let m = mcap::read::metadata(&bytes, index).unwrap();
        if m.name == "bridgetwin" {
            return m.metadata;
        }
    }
    panic!("no bridgetwin metadata record");
}

/// `git describe --always --dirty --abbrev=12` of this checkout, if git is here.
fn describe() -> Option<String> {
    let out = Command::new("git")
        .args(["describe", "--always", "--dirty", "--abbrev=12"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

#[test]
fn a_run_records_the_builds_revision_or_the_one_given_at_run_time() {
    let dir = tempfile::tempdir().unwrap();
    let built = bridgetwin_metadata(dir.path(), None);
    assert_eq!(built["version"], env!("CARGO_PKG_VERSION"));
    let revision = &built["git_revision"];
    match describe() {
        // The build ran in this checkout: the same commit (the dirty flag may differ if
        // files changed since the build).
        Some(now) => {
            let commit = |r: &str| r.trim_end_matches("-dirty").to_string();
            assert_eq!(commit(revision), commit(&now), "{revision} vs {now}");
        }
        None => eprintln!("git not available: revision {revision} not compared"),
    }
    let given = bridgetwin_metadata(dir.path(), Some("v1.2.3-test"));
    assert_eq!(given["git_revision"], "v1.2.3-test");
}
