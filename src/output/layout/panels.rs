//! Foxglove panel configurations, as Foxglove's layout files spell them: a panel id is
//! `<Type>!<name>`, its title sits under `foxglovePanelTitle`, and the `layout` key holds
//! the mosaic tree (`first`, `second`, `direction`, `splitPercentage`). Keys are those the
//! Plot (`paths` of `value`, `enabled`, `timestampMethod`, `label`; `xAxisVal`;
//! `min/maxXValue`, `min/maxYValue`), Log (`RosOut`: `topicToRender`, `minLogLevel`),
//! Table (`topicPath`) and 3D (`cameraState`, `followTf`, `topics`) panels read.

use serde_json::{json, Map, Value};

/// The key of a panel's own title in its configuration.
pub const TITLE_KEY: &str = "foxglovePanelTitle";

/// One series of a Plot panel.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Foxglove message path: `/topic.field`, filters and modifiers included.
    pub path: String,
    pub label: String,
    pub enabled: bool,
}

impl Series {
    pub fn new(path: String, label: String) -> Self {
        Series {
            path,
            label,
            enabled: true,
        }
    }
}

/// The x axis of a Plot panel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum XAxis {
    /// Log time, over the whole file, synced with the other time plots.
    Time,
    /// Log time over a fixed range (s since the start of the file), not synced.
    TimeRange(f64, f64),
    /// The array index of the latest message (a shape along the bridge).
    Index,
}

/// A Plot panel.
#[derive(Debug, Clone, PartialEq)]
pub struct Plot {
    pub title: String,
    pub series: Vec<Series>,
    pub x: XAxis,
    /// A fixed y range (min, max), in the plotted unit.
    pub y_range: Option<(f64, f64)>,
}

impl Plot {
    pub fn config(&self) -> Value {
        let paths: Vec<Value> = self
            .series
            .iter()
            .map(|s| {
                json!({
                    "value": s.path,
                    "enabled": s.enabled,
                    "timestampMethod": "receiveTime",
                    "label": s.label,
                })
            })
            .collect();
        let mut config = json!({
            TITLE_KEY: self.title,
            "paths": paths,
            "showXAxisLabels": true,
            "showYAxisLabels": true,
            "showLegend": true,
            "legendDisplay": "floating",
            "showPlotValuesInLegend": false,
            "isSynced": matches!(self.x, XAxis::Time),
            "xAxisVal": match self.x {
                XAxis::Index => "index",
                XAxis::Time | XAxis::TimeRange(..) => "timestamp",
            },
            "sidebarDimension": 240,
        });
        let object = config.as_object_mut();
        if let Some(object) = object {
            if let XAxis::TimeRange(lo, hi) = self.x {
                object.insert("minXValue".into(), json!(lo));
                object.insert("maxXValue".into(), json!(hi));
            }
            if let Some((lo, hi)) = self.y_range {
                object.insert("minYValue".into(), json!(lo));
                object.insert("maxYValue".into(), json!(hi));
            }
        }
        config
    }
}

/// The Log panel on `topic` (`foxglove.Log`), every level shown.
pub fn log_panel(title: &str, topic: &str) -> Value {
    json!({
        TITLE_KEY: title,
        "topicToRender": topic,
        "minLogLevel": 1,
        "searchTerms": [],
    })
}

/// A Table panel of the latest message on `topic`.
pub fn table_panel(title: &str, topic: &str) -> Value {
    json!({ TITLE_KEY: title, "topicPath": topic })
}

/// A 3D panel showing `topic` in frame `frame`, the camera looking at `target` (m, in
/// that frame) from `distance_m` on the -y side, 18 degrees above the horizontal: the
/// bridge's x runs left to right and the deck's sag shows in profile.
pub fn three_d_panel(
    title: &str,
    topic: &str,
    frame: &str,
    target: [f64; 3],
    distance_m: f64,
) -> Value {
    json!({
        TITLE_KEY: title,
        "cameraState": {
            "distance": distance_m,
            "perspective": true,
            "phi": 72.0,
            "thetaOffset": 0.0,
            "target": [0.0, 0.0, 0.0],
            "targetOffset": target,
            "targetOrientation": [0.0, 0.0, 0.0, 1.0],
            "fovy": 45.0,
            "near": 0.5,
            "far": 5000.0,
        },
        "followMode": "follow-pose",
        "followTf": frame,
        "scene": {},
        "transforms": {},
        "topics": { topic: { "visible": true } },
        "layers": {},
    })
}

/// A mosaic node: panels `ids` side by side (`direction` "row") or stacked ("column"),
/// each given the same share.
pub fn split(ids: &[Value], direction: &str) -> Value {
    let weighted: Vec<(Value, f64)> = ids.iter().map(|id| (id.clone(), 1.0)).collect();
    split_weighted(&weighted, direction)
}

/// As [`split`], each node given a share proportional to its weight.
pub fn split_weighted(nodes: &[(Value, f64)], direction: &str) -> Value {
    match nodes {
        [] => Value::Null,
        [(one, _)] => one.clone(),
        [(first, weight), rest @ ..] => {
            let total: f64 = nodes.iter().map(|(_, w)| w).sum();
            json!({
                "first": first,
                "second": split_weighted(rest, direction),
                "direction": direction,
                "splitPercentage": 100.0 * weight / total,
            })
        }
    }
}

/// A whole layout file: panel configurations by id and the mosaic tree.
pub fn layout_file(config_by_id: Map<String, Value>, mosaic: Value) -> Value {
    json!({
        "configById": config_by_id,
        "globalVariables": {},
        "userNodes": {},
        "playbackConfig": { "speed": 1.0 },
        "layout": mosaic,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plot_config_has_the_keys_foxglove_reads() {
        let plot = Plot {
            title: "Shape".into(),
            series: vec![Series::new(
                "/truth/bridge.deflection_m[:]".into(),
                "w".into(),
            )],
            x: XAxis::Index,
            y_range: Some((-0.005, 0.001)),
        };
        let c = plot.config();
        assert_eq!(c["xAxisVal"], "index");
        assert_eq!(c["isSynced"], false);
        assert_eq!(c["minYValue"], -0.005);
        assert_eq!(c["paths"][0]["value"], "/truth/bridge.deflection_m[:]");
        assert_eq!(c["paths"][0]["enabled"], true);
        assert_eq!(c["paths"][0]["timestampMethod"], "receiveTime");
        assert_eq!(c[TITLE_KEY], "Shape");
        let timed = Plot {
            x: XAxis::TimeRange(1.0, 9.0),
            y_range: None,
            ..plot
        };
        let c = timed.config();
        assert_eq!(
            (c["minXValue"].as_f64(), c["maxXValue"].as_f64()),
            (Some(1.0), Some(9.0))
        );
        assert!(c.get("minYValue").is_none());
    }

    #[test]
    fn split_shares_evenly() {
        let ids = [json!("a"), json!("b"), json!("c")];
        let tree = split(&ids, "column");
        assert_eq!(tree["first"], "a");
        assert!((tree["splitPercentage"].as_f64().unwrap() - 100.0 / 3.0).abs() < 1e-12);
        assert_eq!(tree["second"]["first"], "b");
        assert_eq!(tree["second"]["second"], "c");
        assert_eq!(tree["second"]["splitPercentage"], 50.0);
        assert_eq!(split(&ids[..1], "row"), json!("a"));
    }
}
