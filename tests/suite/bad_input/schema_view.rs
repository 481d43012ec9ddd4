//! The bad-input catalogue against the scenario's JSON Schema: every case whose scenario
//! is wrong key by key (a type, an unknown key or name, a missing key, a bound) must be
//! rejected by the schema too, at the field the CLI names, so that an editor flags it
//! before a run. The cases the schema accepts are listed below with the reason: their
//! error depends on other keys, on a file, or on the physics, which no schema states.

use crate::scenario_schema::schema;

/// Cases whose scenario the schema accepts, and why only the loader can reject them.
pub const SCHEMA_ACCEPTS: &[(&str, &str)] = &[
    // The bound is another key's value (the span, the approach, the solver rate, the
    // kind of sensor, a preset, the other band limit).
    ("sensor beyond the span", "the bound is bridge.span_m"),
    (
        "settlement where there is no support",
        "the supports' positions follow from bridge.spans_m",
    ),
    (
        "bearing degradation of a rigid support",
        "the bound is bridge.supports' kind",
    ),
    (
        "settlement without its size",
        "which key is needed depends on kind",
    ),
    ("scour on a modal model", "the bound is bridge.model's kind"),
    (
        "load cell off a support",
        "the supports' positions follow from bridge.spans_m",
    ),
    (
        "inclinometer preset on an accelerometer",
        "the preset's kind must match the sensor's kind",
    ),
    (
        "stiffness region beyond the span",
        "the bound is bridge.span_m",
    ),
    (
        "damage region beyond the span",
        "the bound is bridge.span_m",
    ),
    (
        "WIM station before the approach",
        "the bound is road.approach_m",
    ),
    (
        "approach shorter than the wheelbase",
        "the bound is the vehicle's wheelbase",
    ),
    (
        "car without its parameters",
        "which keys are needed depends on whether a preset gives them",
    ),
    (
        "trigger with generated traffic",
        "the trigger needs the absence of another key ([traffic])",
    ),
    (
        "overlapping axles",
        "the bound is the car's wheelbase (half of it)",
    ),
    (
        "a load model as vehicles",
        "whether a preset has vehicle models is the preset's data, and the refused value is the default",
    ),
    (
        "centre of gravity outside the wheelbase",
        "the bound is the preset's wheelbase",
    ),
    ("ISO 8608 band inverted", "n1 < n2 relates two keys"),
    (
        "modal model with more modes than its mesh has DOFs to spare",
        "the bound is 2 x bridge.model.modes",
    ),
    (
        "model whose memory estimate is above the limit",
        "the memory estimate multiplies modes and elements",
    ),
    (
        "time step too coarse for the sensor rates",
        "sensor rates are bounded by 1/dt",
    ),
    (
        "sensor rate above the solver rate",
        "the bound is 1/solver.dt_s",
    ),
    (
        "clocked sensor at the solver rate",
        "the bound is half of 1/solver.dt_s",
    ),
    (
        "ambient band above the Nyquist frequency",
        "the bound is 1/(2 solver.dt_s)",
    ),
    (
        "axle-load rate does not divide the solver rate",
        "divisibility by 1/solver.dt_s",
    ),
    (
        "bridge-state rate above the solver rate",
        "divisibility by 1/solver.dt_s",
    ),
    (
        "too many steps: dt = 10 us over 1e6 s",
        "the step count is duration_s / dt_s",
    ),
    (
        "gauge depth on an accelerometer",
        "allowed or not by the sensor's kind",
    ),
    (
        "accelerometer preset on a strain gauge",
        "allowed or not by the sensor's kind",
    ),
    (
        "rate not supported by the preset",
        "the bound is the preset's highest rate",
    ),
    (
        "moving force: spacings do not match loads",
        "one count follows another",
    ),
    (
        "half car without preset and fields",
        "required unless the preset gives them",
    ),
    (
        "ISO 8608 without class or G_d",
        "one of two keys is required",
    ),
    (
        "damage on a modal model",
        "allowed or not by the bridge model's kind",
    ),
    // Across items or tables: unique ids, references, a sum.
    ("duplicate sensor id", "uniqueness of a key across items"),
    (
        "WIM stations with the same id",
        "uniqueness of a key across items",
    ),
    (
        "two vehicles with the same id",
        "uniqueness of a key across items",
    ),
    (
        "sensor on an unknown DAQ node",
        "a reference to another table's ids",
    ),
    ("class shares not summing to 1", "a sum over a table"),
    // Derived from several keys by the physics or the numerics.
    (
        "span absurdly small (f1 overflows)",
        "f1 follows from span, EI and mass",
    ),
    (
        "elastic support 1e300 times stiffer than a rigid one needs",
        "the bound is 1e10 x the girder's EI / L^3, from bridge.flexural_rigidity_n_m2 and spans_m",
    ),
    (
        "EI off by 90 orders of magnitude",
        "f1 follows from span, EI and mass",
    ),
    (
        "mass per length absurdly small",
        "f1 follows from span, EI and mass",
    ),
    (
        "speed so low that the default duration exceeds 30 days",
        "the default duration follows from speed and road",
    ),
    (
        "too many steps: dt = 1 ns over the default duration",
        "the default duration follows from speed and road",
    ),
    (
        "sensor rate far below the solver rate (anti-alias kernel too long)",
        "the anti-alias kernel length follows from both rates",
    ),
    (
        "sensor noise density overflowing",
        "the per-sample sigma follows from density and rate",
    ),
    // Values a JSON Schema has no keyword for.
    (
        "dt not a whole number of nanoseconds",
        "multipleOf 1e-9 is not exact in binary floating point",
    ),
    (
        "start_time beyond 64-bit nanoseconds",
        "the date-time format bounds no year",
    ),
    (
        "start_time before 1970",
        "the date-time format bounds no year",
    ),
    // The error is in a file the scenario names.
    ("road CSV missing", "a file's existence"),
    ("road CSV non-numeric elevation", "a file's contents"),
    ("road CSV NaN x", "a file's contents"),
    ("road CSV x not increasing", "a file's contents"),
    ("road CSV row with a missing field", "a file's contents"),
    ("road CSV header without x_m", "a file's contents"),
    (
        "road CSV too short for the run",
        "a file's contents against the run's length",
    ),
    (
        "temperature CSV with a word for a value",
        "a file's contents",
    ),
    ("temperature CSV with the wrong header", "a file's contents"),
    ("temperature CSV going back in time", "a file's contents"),
    ("temperature CSV missing", "a file's existence"),
];

/// Cases the schema rejects for the CLI's reason in other words.
pub const SAME_CAUSE_OTHER_WORDS: &[(&str, &str)] = &[
    (
        "empty file",
        "the schema: `bridge` is required; the CLI: the file is empty",
    ),
    (
        "whitespace only",
        "the schema: `bridge` is required; the CLI: the file is empty",
    ),
    (
        "composition with no cars",
        "the schema: `cars` needs one item; the CLI: the train has neither a preset nor a car \
         (an absent `cars` and an empty one read alike)",
    ),
];

/// A case as the check needs it: name, scenario bytes (if any), expected stderr parts.
pub struct CaseView<'a> {
    pub name: &'a str,
    pub scenario: Option<&'a [u8]>,
    pub expect: &'a [String],
}

/// Checks every case; returns the report of those that disagree with the schema.
pub fn disagreements(cases: &[CaseView<'_>], valid_scenario: &str) -> Vec<String> {
    let validator = schema::validator();
    let mut report = Vec::new();
    for case in cases {
        let listed = SCHEMA_ACCEPTS.iter().find(|(name, _)| *name == case.name);
        // Arguments, a missing file, invalid UTF-8 or TOML syntax: nothing a schema sees.
        let text = case.scenario.and_then(|b| std::str::from_utf8(b).ok());
        let json = text.and_then(schema::toml_to_json);
        let (Some(text), Some(json)) = (text, json) else {
            if listed.is_some() {
                report.push(format!(
                    "`{}` is listed but has no TOML scenario",
                    case.name
                ));
            }
            continue;
        };
        // The output-path cases run a valid scenario.
        if text == valid_scenario {
            continue;
        }
        let paths = schema::error_paths(&validator, &json);
        let other_words = SAME_CAUSE_OTHER_WORDS.iter().any(|(n, _)| *n == case.name);
        match (listed, paths.is_empty()) {
            (Some(_), true) => {}
            (Some((_, why)), false) => report.push(format!(
                "`{}` is listed as accepted ({why}) but the schema rejects it at {paths:?}: \
                 take it off the list",
                case.name
            )),
            (None, true) => report.push(format!(
                "`{}`: the schema accepts it (the CLI expects {:?})",
                case.name, case.expect
            )),
            (None, false) => {
                // The same reason: the CLI's message names what the schema points at.
                // The CLI names listed items by index and id (`sensors.2[A3]`), the
                // schema by index alone.
                let named = paths.iter().any(|p| {
                    let value = offending_value(&json, p);
                    case.expect
                        .iter()
                        .any(|e| names_error(&without_ids(e), p, value.as_deref()))
                });
                if !named && !other_words {
                    report.push(format!(
                        "`{}`: the schema rejects it at {paths:?}, not where the CLI points \
                         ({:?})",
                        case.name, case.expect
                    ));
                }
            }
        }
    }
    for (name, _) in SCHEMA_ACCEPTS.iter().chain(SAME_CAUSE_OTHER_WORDS) {
        if !cases.iter().any(|c| c.name == *name) {
            report.push(format!(
                "`{name}` is listed but is no case of the catalogue"
            ));
        }
    }
    report
}

/// `expected` without the ids the CLI adds after a list index: `sensors.2[A3].rate_hz`
/// -> `sensors.2.rate_hz`.
fn without_ids(expected: &str) -> String {
    let mut out = String::with_capacity(expected.len());
    let mut rest = expected;
    while let Some(open) = rest.find('[') {
        let after_index = rest[..open].ends_with(|c: char| c.is_ascii_digit());
        match rest[open..].find(']') {
            Some(close) if after_index => {
                out.push_str(&rest[..open]);
                rest = &rest[open + close + 1..];
            }
            _ => {
                out.push_str(&rest[..=open]);
                rest = &rest[open + 1..];
            }
        }
    }
    out.push_str(rest);
    out
}

/// The value at a dotted path of the scenario, as text (`mems_fancy`), if it is a
/// string or a number.
fn offending_value(json: &serde_json::Value, path: &str) -> Option<String> {
    let mut node = json;
    for segment in path.split('.') {
        node = match segment.parse::<usize>() {
            Ok(i) => node.get(i)?,
            Err(_) => node.get(segment)?,
        };
    }
    match node {
        serde_json::Value::String(s) => Some(s.clone()),
        serde_json::Value::Number(n) => Some(n.to_string()),
        _ => None,
    }
}

/// Whether the CLI's expected message part `expected` names the schema error at `path`
/// (with `value` there): the whole path (`bridge.span_m = 0 must ...`); its parent and
/// the key as serde writes a missing or unknown one (`bridge: missing field `span_m``);
/// or the offending name itself (`unknown variant `mems_fancy``, a class `hovercraft`).
fn names_error(expected: &str, path: &str, value: Option<&str>) -> bool {
    let (parent, key) = path.rsplit_once('.').unwrap_or(("", path));
    let quoted = |word: &str| expected.contains(&format!("`{word}`"));
    names_word(expected, path)
        || ((parent.is_empty() || names_word(expected, parent)) && quoted(key))
        || value.is_some_and(quoted)
        || expected == key
}

/// Whether `expected` has `word` as a whole path: `bridge.span_m` in `bridge.span_m = 0`,
/// not in `bridge.span_m_extra` or `x.bridge.span_m`.
fn names_word(expected: &str, word: &str) -> bool {
    let joins = |c: Option<char>| c.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '.');
    expected.match_indices(word).any(|(at, _)| {
        let before = expected[..at].chars().next_back();
        let after = expected[at + word.len()..].chars().next();
        !joins(before) && !joins(after)
    })
}
