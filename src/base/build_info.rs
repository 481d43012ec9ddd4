//! What the build knows about itself, stored in every run's `bridgetwin` metadata.

/// The source revision this binary was built from (`git describe --always --dirty`, set
/// by `build.rs`), or "unknown" when built outside a git checkout.
pub const GIT_REVISION: &str = match option_env!("BRIDGETWIN_GIT_REVISION") {
    Some(revision) => revision,
    None => "unknown",
};

/// The environment variable that, at run time, replaces the revision written into a run:
/// to regenerate a dataset byte for byte with a build from another revision (and for the
/// pinned output hashes of the test suite, which must not change with every commit).
pub const REVISION_OVERRIDE_VAR: &str = "BRIDGETWIN_RUN_REVISION";

/// The revision a run records: [`REVISION_OVERRIDE_VAR`] if set, else [`GIT_REVISION`].
pub fn run_revision() -> String {
    std::env::var(REVISION_OVERRIDE_VAR).unwrap_or_else(|_| GIT_REVISION.to_string())
}
