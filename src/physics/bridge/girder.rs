//! The girder's layout: spans, overhangs and the support at each span end.
//!
//! Abscissae run from the girder's left end (the tip of the left overhang, or the first
//! support when there is none), so a single simply supported span keeps x = 0 at its left
//! support. The beam carries only vertical loads, so a pinned and a roller support act
//! alike (w = 0); a fixed support also clamps the slope; an elastic one is a vertical and a
//! rotational spring (bearings, flexible piers).

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// Most spans a girder may have.
pub const MAX_SPANS: usize = 50;

/// A support at a span end.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Support {
    /// w = 0, free rotation.
    Pinned,
    /// w = 0, free rotation (a sliding bearing: no axial restraint, which a beam under
    /// vertical loads does not feel).
    Roller,
    /// w = 0 and slope = 0 (clamped, monolithic with a stiff pier or abutment).
    Fixed,
    /// Springs: a bearing's vertical stiffness, a pier's rotational restraint.
    #[schemars(
        description = "Springs: a bearing's vertical stiffness (N/m), a pier's rotational restraint (N m/rad)."
    )]
    Elastic {
        /// Vertical stiffness (N/m), >= 0.
        #[schemars(range(min = 0))]
        vertical_n_m: f64,
        /// Rotational stiffness (N m/rad), >= 0 (default 0: free rotation).
        #[serde(default)]
        #[schemars(range(min = 0))]
        rotational_n_m_rad: f64,
    },
}

impl Support {
    /// True when the support holds w = 0 rigidly.
    pub fn rigid_vertical(&self) -> bool {
        !matches!(self, Support::Elastic { .. })
    }

    /// True when the support holds the slope at zero rigidly.
    pub fn rigid_rotation(&self) -> bool {
        matches!(self, Support::Fixed)
    }

    /// (vertical N/m, rotational N m/rad) springs of an elastic support; zeros otherwise.
    pub fn springs(&self) -> (f64, f64) {
        match *self {
            Support::Elastic {
                vertical_n_m,
                rotational_n_m_rad,
            } => (vertical_n_m, rotational_n_m_rad),
            _ => (0.0, 0.0),
        }
    }

    /// Whether the support restrains vertical motion at all (rigidly or by a spring).
    fn restrains_vertical(&self) -> bool {
        self.rigid_vertical() || self.springs().0 > 0.0
    }

    /// Whether the support restrains rotation at all.
    fn restrains_rotation(&self) -> bool {
        self.rigid_rotation() || self.springs().1 > 0.0
    }

    /// Short name for messages.
    pub fn name(&self) -> &'static str {
        match self {
            Support::Pinned => "pinned",
            Support::Roller => "roller",
            Support::Fixed => "fixed",
            Support::Elastic { .. } => "elastic",
        }
    }
}

/// Spans, overhangs and supports of a straight girder.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Girder {
    /// Span lengths, left to right (m); may be empty for a single support carrying
    /// overhangs (a cantilever).
    pub spans_m: Vec<f64>,
    /// One support per span end: `spans_m.len() + 1` of them.
    pub supports: Vec<Support>,
    /// Free overhang beyond the first support (m, 0 for none).
    pub overhang_left_m: f64,
    /// Free overhang beyond the last support (m, 0 for none).
    pub overhang_right_m: f64,
}

/// One piece of the girder between two of its key points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PieceKind {
    /// A span between supports `index` and `index + 1`.
    Span(usize),
    /// The left overhang (its support at its right end).
    OverhangLeft,
    /// The right overhang (its support at its left end).
    OverhangRight,
}

/// A span or an overhang, with its abscissae.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Piece {
    pub kind: PieceKind,
    pub start_m: f64,
    pub end_m: f64,
}

impl Piece {
    pub fn length_m(&self) -> f64 {
        self.end_m - self.start_m
    }
}

impl Girder {
    /// One simply supported span (pinned and roller), no overhangs.
    pub fn simply_supported(span_m: f64) -> Self {
        Girder {
            spans_m: vec![span_m],
            supports: vec![Support::Pinned, Support::Roller],
            overhang_left_m: 0.0,
            overhang_right_m: 0.0,
        }
    }

    /// True for one span on a pinned or roller support at each end, without overhangs:
    /// the layout the closed forms of the simple beam (and the paper) describe.
    pub fn is_simple_span(&self) -> bool {
        self.spans_m.len() == 1
            && self.overhang_left_m == 0.0
            && self.overhang_right_m == 0.0
            && self
                .supports
                .iter()
                .all(|s| matches!(s, Support::Pinned | Support::Roller))
    }

    /// Total length, overhangs included (m).
    pub fn length_m(&self) -> f64 {
        self.overhang_left_m + self.spans_m.iter().sum::<f64>() + self.overhang_right_m
    }

    /// Abscissa of each support (m from the left end).
    pub fn support_positions_m(&self) -> Vec<f64> {
        let mut x = self.overhang_left_m;
        let mut out = vec![x];
        for span in &self.spans_m {
            x += span;
            out.push(x);
        }
        out
    }

    /// The spans and overhangs in order from the left end.
    pub fn pieces(&self) -> Vec<Piece> {
        let supports = self.support_positions_m();
        let mut out = Vec::new();
        if self.overhang_left_m > 0.0 {
            out.push(Piece {
                kind: PieceKind::OverhangLeft,
                start_m: 0.0,
                end_m: supports[0],
            });
        }
        for (i, pair) in supports.windows(2).enumerate() {
            out.push(Piece {
                kind: PieceKind::Span(i),
                start_m: pair[0],
                end_m: pair[1],
            });
        }
        if self.overhang_right_m > 0.0 {
            let last = supports[supports.len() - 1];
            out.push(Piece {
                kind: PieceKind::OverhangRight,
                start_m: last,
                end_m: last + self.overhang_right_m,
            });
        }
        out
    }

    /// The longest span (m), or the longest overhang of a cantilever.
    pub fn longest_span_m(&self) -> f64 {
        self.spans_m
            .iter()
            .copied()
            .chain([self.overhang_left_m, self.overhang_right_m])
            .fold(0.0, f64::max)
    }

    /// Checks every field; `path` prefixes the field names (e.g. "bridge").
    pub fn validate(&self, path: &str) -> Result<()> {
        if self.spans_m.len() > MAX_SPANS {
            return Err(Error::invalid(
                format!("{path}.spans_m"),
                self.spans_m.len(),
                format!("at most {MAX_SPANS} spans"),
            ));
        }
        for (i, &l) in self.spans_m.iter().enumerate() {
            if !(l.is_finite() && l > 0.0) {
                return Err(Error::invalid(
                    format!("{path}.spans_m.{i}"),
                    l,
                    "must be a finite length > 0",
                ));
            }
        }
        if self.supports.len() != self.spans_m.len() + 1 {
            return Err(Error::invalid(
                format!("{path}.supports"),
                self.supports.len(),
                format!(
                    "needs one support per span end: {} for {} span(s)",
                    self.spans_m.len() + 1,
                    self.spans_m.len()
                ),
            ));
        }
        for (i, s) in self.supports.iter().enumerate() {
            let (kv, kr) = s.springs();
            for (name, k) in [("vertical_n_m", kv), ("rotational_n_m_rad", kr)] {
                if !(k.is_finite() && k >= 0.0) {
                    return Err(Error::invalid(
                        format!("{path}.supports.{i}.{name}"),
                        k,
                        "must be a finite stiffness >= 0",
                    ));
                }
            }
        }
        self.validate_overhangs(path)?;
        self.check_not_a_mechanism(path)
    }

    fn validate_overhangs(&self, path: &str) -> Result<()> {
        let first = self.spans_m.first().copied();
        let last = self.spans_m.last().copied();
        for (name, a, neighbour) in [
            ("overhang_left_m", self.overhang_left_m, first),
            ("overhang_right_m", self.overhang_right_m, last),
        ] {
            if !(a.is_finite() && a >= 0.0) {
                return Err(Error::invalid(
                    format!("{path}.{name}"),
                    a,
                    "must be a finite length >= 0",
                ));
            }
            if let Some(span) = neighbour {
                if a > span {
                    return Err(Error::invalid(
                        format!("{path}.{name}"),
                        a,
                        format!("must not be longer than its span ({span} m)"),
                    ));
                }
            }
        }
        if self.length_m() <= 0.0 {
            return Err(Error::invalid(
                format!("{path}.spans_m"),
                "[]",
                "a girder without spans needs an overhang (a cantilever)",
            ));
        }
        Ok(())
    }

    /// The rigid-body motions of a beam are w = a + b x. Each support that restrains
    /// vertical motion (rigidly or by a spring) imposes a + b x_s = 0, each that restrains
    /// rotation imposes b = 0: the girder stands when two vertical restraints at
    /// different places, or one vertical and one rotational restraint, remain.
    fn check_not_a_mechanism(&self, path: &str) -> Result<()> {
        let vertical = self
            .supports
            .iter()
            .filter(|s| s.restrains_vertical())
            .count();
        let rotational = self.supports.iter().any(|s| s.restrains_rotation());
        if vertical >= 2 || (vertical == 1 && rotational) {
            return Ok(());
        }
        let described: Vec<String> = self
            .supports
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let (kv, kr) = s.springs();
                match s {
                    Support::Elastic { .. } => format!("{i}: elastic ({kv} N/m, {kr} N m/rad)"),
                    _ => format!("{i}: {}", s.name()),
                }
            })
            .collect();
        Err(Error::invalid(
            format!("{path}.supports"),
            format!("[{}]", described.join(", ")),
            "leave the girder a mechanism (it could move as a rigid body): it needs two \
             supports that carry vertical load, or one that also restrains rotation",
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn girder(spans: &[f64], supports: &[Support]) -> Girder {
        Girder {
            spans_m: spans.to_vec(),
            supports: supports.to_vec(),
            overhang_left_m: 0.0,
            overhang_right_m: 0.0,
        }
    }

    #[test]
    fn pieces_and_supports_follow_the_spans() {
        let mut g = girder(&[20.0, 30.0], &[Support::Pinned; 3]);
        g.overhang_left_m = 5.0;
        g.overhang_right_m = 2.0;
        assert_eq!(g.length_m(), 57.0);
        assert_eq!(g.support_positions_m(), vec![5.0, 25.0, 55.0]);
        let pieces = g.pieces();
        assert_eq!(pieces.len(), 4);
        assert_eq!(pieces[0].kind, PieceKind::OverhangLeft);
        assert_eq!((pieces[2].start_m, pieces[2].end_m), (25.0, 55.0));
        assert_eq!(pieces[3].kind, PieceKind::OverhangRight);
        assert!(!g.is_simple_span());
        assert!(Girder::simply_supported(30.0).is_simple_span());
    }

    #[test]
    fn mechanisms_are_refused_naming_the_supports() {
        let free = Support::Elastic {
            vertical_n_m: 0.0,
            rotational_n_m_rad: 0.0,
        };
        let msg = girder(&[30.0], &[Support::Pinned, free])
            .validate("bridge")
            .unwrap_err()
            .to_string();
        assert!(
            msg.contains("bridge.supports") && msg.contains("1: elastic"),
            "{msg}"
        );
        // A cantilever stands on one fixed support.
        let mut cantilever = girder(&[], &[Support::Fixed]);
        cantilever.overhang_right_m = 10.0;
        cantilever.validate("bridge").unwrap();
        cantilever.supports = vec![Support::Pinned];
        assert!(cantilever.validate("bridge").is_err());
        // One spring under each end carries the girder.
        let spring = Support::Elastic {
            vertical_n_m: 1e8,
            rotational_n_m_rad: 0.0,
        };
        girder(&[30.0], &[spring, spring])
            .validate("bridge")
            .unwrap();
    }

    #[test]
    fn bad_layouts_name_the_field_and_value() {
        let cases: Vec<(Girder, &str)> = vec![
            (
                girder(&[30.0, -2.0], &[Support::Pinned; 3]),
                "bridge.spans_m.1",
            ),
            (
                girder(&[30.0, 20.0], &[Support::Pinned; 2]),
                "bridge.supports",
            ),
            (
                girder(
                    &[30.0],
                    &[
                        Support::Pinned,
                        Support::Elastic {
                            vertical_n_m: f64::NAN,
                            rotational_n_m_rad: 0.0,
                        },
                    ],
                ),
                "bridge.supports.1.vertical_n_m",
            ),
            (
                Girder {
                    overhang_right_m: 31.0,
                    ..Girder::simply_supported(30.0)
                },
                "bridge.overhang_right_m",
            ),
        ];
        for (g, field) in cases {
            let msg = g.validate("bridge").unwrap_err().to_string();
            assert!(msg.contains(field), "{field}: {msg}");
        }
    }
}
