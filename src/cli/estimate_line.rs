//! The estimate line `simulate` and `scenario check` print before a run, and the time
//! texts of the progress bar.

use crate::app::estimate::RunEstimate;
use crate::base::units::bytes_text;

/// One line: steps, messages, bytes and files, and the wall time on this machine with
/// how it was measured, e.g.
/// `estimate: 9 701 steps (9.7 s simulated), 37 117 messages, 1.4 MiB in 1 file; about
/// 0.05 s here (3.4 us per step, 0.6 us per message, timed over 2 425 steps)`.
pub fn estimate_line(e: &RunEstimate) -> String {
    let t = &e.timing;
    let files = match e.files {
        1 => "1 file".to_string(),
        n => format!("{} files", grouped(n)),
    };
    format!(
        "estimate: {} steps ({} simulated), {} messages, {} in {files}; about {} here \
         ({} per step, {} per message, timed over {} steps)",
        grouped(e.steps),
        duration_text(e.duration_s),
        grouped(e.messages),
        bytes_text(e.bytes),
        duration_text(t.wall_s),
        seconds_text(t.step_s),
        seconds_text(t.message_s),
        grouped(t.burst_steps),
    )
}

/// `37 117`, `1 000 000 001`: digits in groups of three.
pub fn grouped(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(' ');
        }
        out.push(c);
    }
    out
}

/// A duration for people: `0.05 s`, `9.7 s`, `4 min 10 s`, `1 h 25 min`, `11 d 14 h`.
pub fn duration_text(s: f64) -> String {
    if !s.is_finite() || s < 0.0 {
        return "?".into();
    }
    if s < 1.0 {
        return format!("{s:.2} s");
    }
    if s < 60.0 {
        return format!("{s:.1} s");
    }
    let whole = s.round() as u64;
    let (d, h, m, sec) = (
        whole / 86_400,
        whole / 3600 % 24,
        whole / 60 % 60,
        whole % 60,
    );
    match (d, h) {
        (0, 0) => format!("{m} min {sec} s"),
        (0, _) => format!("{h} h {m} min"),
        _ => format!("{d} d {h} h"),
    }
}

/// A short time: `850 ns`, `3.4 us`, `1.2 ms`, `0.53 s`.
fn seconds_text(s: f64) -> String {
    match s {
        s if s < 1e-6 => format!("{:.0} ns", s * 1e9),
        s if s < 1e-3 => format!("{:.1} us", s * 1e6),
        s if s < 1.0 => format!("{:.1} ms", s * 1e3),
        s => format!("{s:.2} s"),
    }
}

/// The time left of a run at `step` of `steps`, `elapsed_s` after its loop started:
/// before the loop has gone a second, what the estimate left (`estimate_s` less the
/// time gone); after, the loop's own pace so far (the estimate is then only a start).
pub fn time_left_s(step: u64, steps: u64, elapsed_s: f64, estimate_s: f64) -> f64 {
    let left = steps.saturating_sub(step) as f64;
    if step == 0 || elapsed_s < 1.0 {
        return (estimate_s - elapsed_s).max(0.0);
    }
    left * elapsed_s / step as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_read_as_people_write_them() {
        assert_eq!(grouped(0), "0");
        assert_eq!(grouped(999), "999");
        assert_eq!(grouped(37_117), "37 117");
        assert_eq!(grouped(1_000_000_001), "1 000 000 001");
        assert_eq!(duration_text(0.049), "0.05 s");
        assert_eq!(duration_text(9.7), "9.7 s");
        assert_eq!(duration_text(250.0), "4 min 10 s");
        assert_eq!(duration_text(5100.0), "1 h 25 min");
        assert_eq!(duration_text(1e6), "11 d 13 h");
        assert_eq!(seconds_text(3.4e-6), "3.4 us");
        assert_eq!(seconds_text(5e-7), "500 ns");
    }

    #[test]
    fn the_time_left_follows_the_estimate_then_the_pace() {
        assert_eq!(time_left_s(0, 100, 0.0, 50.0), 50.0);
        assert_eq!(time_left_s(10, 100, 0.5, 50.0), 49.5);
        // After a second the pace decides: 10 % in 2 s leaves 18 s.
        assert_eq!(time_left_s(10, 100, 2.0, 50.0), 18.0);
        assert_eq!(time_left_s(100, 100, 20.0, 50.0), 0.0);
    }
}
