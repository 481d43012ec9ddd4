//! Any text given as a scenario: parsing and resolving must give a scenario or an error
//! naming what is wrong, never a panic.
#![no_main]

use bridgetwin::scenario::Scenario;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    // The CLI refuses non-UTF-8 files before parsing; the parser only ever sees text.
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(scenario) = Scenario::from_toml(text, "fuzz.toml") {
        // Resolving checks every bound and builds the models' inputs: an error is fine,
        // a panic is a bug. (Simulating is not fuzzed: a legal scenario may run for hours.)
        let _ = scenario.resolve();
    }
});
