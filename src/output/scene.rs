//! The 3D scene on `/scene` (`foxglove.SceneUpdate`, `docs/output.md` section 14), built
//! from the records alone: the deck follows the latest deflected shape (exaggerated by the
//! manifest's factor), the vehicles stand on it at their axles' positions, the sensors
//! and the supports sit where the manifest puts them.
//!
//! Frame `bridge`: x along the bridge axis from the left support (m), y across it (lane 0
//! on the +y side), z up. Every update is the whole scene (all entities replaced), so a
//! viewer that seeks, or a live subscriber that joins late, needs no earlier message.

use super::proto::foxglove::{
    line_primitive, scene_entity_deletion, Color, CubePrimitive, CylinderPrimitive, KeyValuePair,
    LinePrimitive, Point3, Pose, Quaternion, SceneEntity, SceneEntityDeletion, SceneUpdate,
    SpherePrimitive, TextPrimitive, TriangleListPrimitive, Vector3,
};
use super::timestamp_from_ns;
use crate::base::units::GRAVITY_M_S2;
use crate::record::{AxleState, RunManifest, SceneInfo, SensorKind};

/// Drawn heights are rounded to this step (m), a power of two so that the rounded value
/// is exact and its low mantissa bits are zero: the changing heights are most of a
/// scene's bytes after compression, and rounding them cuts the file's growth by about
/// four (under 1 mm in the drawing, a few micrometres of true deflection).
pub const DRAWN_Z_STEP_M: f64 = 1.0 / 1024.0;

/// The frame every entity is drawn in.
pub const SCENE_FRAME: &str = "bridge";

/// Width of one lane (m): the usual 3.5 m of a motorway lane.
pub const LANE_WIDTH_M: f64 = 3.5;

/// Vehicles with an axle this far (in spans) before the bridge or after it are drawn:
/// the approach and exit in view of a camera framing the bridge.
const VEHICLE_WINDOW_SPANS: f64 = 0.5;
/// Body length ahead of the front axle and behind the last one (m): the records carry
/// the axles only, so the body is drawn with a nominal overhang.
const OVERHANG_M: f64 = 1.0;
const WHEEL_DIAMETER_M: f64 = 0.9;
const VEHICLE_WIDTH_M: f64 = 2.4;
/// Gross weights below this are drawn as cars (lower bodies), N: the 3.5 t limit of a
/// light vehicle.
const CAR_LIMIT_N: f64 = 3500.0 * GRAVITY_M_S2;
const CAR_BODY_HEIGHT_M: f64 = 1.0;
const TRUCK_BODY_HEIGHT_M: f64 = 2.6;
const SENSOR_DIAMETER_M: f64 = 0.5;
const SUPPORT_HEIGHT_M: f64 = 1.5;

const DECK: Color = rgba(0.62, 0.62, 0.60, 1.0);
const UNDEFLECTED: Color = rgba(0.35, 0.60, 0.95, 0.9);
const SUPPORT: Color = rgba(0.25, 0.25, 0.25, 1.0);
const BODY: Color = rgba(0.95, 0.65, 0.15, 0.9);
const WHEEL: Color = rgba(0.10, 0.10, 0.10, 1.0);
const WHEEL_LIFTED: Color = rgba(0.90, 0.10, 0.10, 1.0);
const LABEL: Color = rgba(0.95, 0.95, 0.95, 1.0);
const WIM_STRIP: Color = rgba(0.95, 0.85, 0.10, 1.0);

const fn rgba(r: f64, g: f64, b: f64, a: f64) -> Color {
    Color { r, g, b, a }
}

/// The colour of a sensor of `kind`.
fn sensor_color(kind: SensorKind) -> Color {
    match kind {
        SensorKind::Accelerometer => rgba(0.90, 0.30, 0.20, 1.0),
        SensorKind::Strain => rgba(0.20, 0.70, 0.30, 1.0),
        SensorKind::Displacement => rgba(0.20, 0.40, 0.90, 1.0),
        SensorKind::Inclinometer => rgba(0.85, 0.60, 0.10, 1.0),
        SensorKind::LoadCell => rgba(0.55, 0.25, 0.75, 1.0),
        SensorKind::Thermometer => rgba(0.95, 0.55, 0.65, 1.0),
    }
}

/// What the scene needs from the manifest, kept by the recorder.
pub(super) struct SceneGeometry {
    pub info: SceneInfo,
    span_m: f64,
    /// Abscissae of the supports (the two ends of a simple span).
    support_position_m: Vec<f64>,
    deck_width_m: f64,
    node_position_m: Vec<f64>,
    /// (id, kind, position along the bridge) of every sensor.
    sensors: Vec<(String, SensorKind, f64)>,
    /// (id, position) of every WIM strip.
    wim: Vec<(String, f64)>,
}

impl SceneGeometry {
    /// The scene of `manifest`, if the run writes one.
    pub fn new(manifest: &RunManifest) -> Option<Self> {
        let info = manifest.scene?;
        Some(SceneGeometry {
            info,
            span_m: manifest.bridge.length_m,
            support_position_m: manifest.bridge.layout.as_ref().map_or_else(
                || vec![0.0, manifest.bridge.length_m],
                |g| g.support_position_m.clone(),
            ),
            deck_width_m: f64::from(info.lanes.max(1)) * LANE_WIDTH_M,
            node_position_m: manifest.bridge.shape_position_m.clone(),
            sensors: manifest
                .sensors
                .iter()
                // A sensor riding on a vehicle moves with it: the deck shows only its own.
                .filter(|s| s.vehicle.is_none())
                .map(|s| (s.id.clone(), s.kind, s.position_m))
                .collect(),
            wim: manifest
                .wim_stations
                .iter()
                .map(|w| (w.id.clone(), w.position_m))
                .collect(),
        })
    }

    /// The drawn height of the road at `x_m` (m): the exaggerated deflected shape on the
    /// bridge (downward positive in `deflection_m`, so drawn as -factor w), 0 off it.
    fn road_z_m(&self, deflection_m: &[f64], x_m: f64) -> f64 {
        if !(0.0..=self.span_m).contains(&x_m) {
            return 0.0;
        }
        self.drawn_z_m(interpolate(&self.node_position_m, deflection_m, x_m))
    }

    /// The drawn height of deflection `w_m`: -factor w, rounded to [`DRAWN_Z_STEP_M`].
    fn drawn_z_m(&self, w_m: f64) -> f64 {
        (-self.info.exaggeration * w_m / DRAWN_Z_STEP_M).round() * DRAWN_Z_STEP_M
    }

    /// y of the centre of lane `lane`: lane 0 on the +y edge of the deck.
    fn lane_y_m(&self, lane: u32) -> f64 {
        0.5 * self.deck_width_m - (f64::from(lane) + 0.5) * LANE_WIDTH_M
    }

    /// The whole scene at Unix-epoch time `time_ns`: `deflection_m` at the shape nodes,
    /// `axles` as in the latest `AxleLoads` record (sorted by vehicle, then axle).
    pub fn update(&self, time_ns: u64, deflection_m: &[f64], axles: &[AxleState]) -> SceneUpdate {
        let entity = |id: &str| SceneEntity {
            timestamp: Some(timestamp_from_ns(time_ns)),
            frame_id: SCENE_FRAME.into(),
            id: id.into(),
            ..Default::default()
        };
        let mut entities = vec![
            self.deck(entity("deck"), deflection_m),
            self.supports(entity("supports")),
            self.sensors(entity("sensors"), deflection_m),
        ];
        if !self.wim.is_empty() {
            entities.push(self.wim_strips(entity("wim")));
        }
        let window = VEHICLE_WINDOW_SPANS * self.span_m;
        let in_view = |x: f64| (-window..=self.span_m + window).contains(&x);
        for vehicle in axles.chunk_by(|a, b| a.vehicle_id == b.vehicle_id) {
            if vehicle.iter().any(|a| in_view(a.position_m)) {
                let id = format!("vehicle/{}", vehicle[0].vehicle_id);
                entities.push(self.vehicle(entity(&id), vehicle, deflection_m));
            }
        }
        SceneUpdate {
            deletions: vec![SceneEntityDeletion {
                timestamp: Some(timestamp_from_ns(time_ns)),
                r#type: scene_entity_deletion::Type::All as i32,
                id: String::new(),
            }],
            entities,
        }
    }

    /// The deck as a surface over the shape nodes, the undeflected line along its near
    /// edge for reference, and the factor.
    fn deck(&self, mut entity: SceneEntity, deflection_m: &[f64]) -> SceneEntity {
        let half = 0.5 * self.deck_width_m;
        let z: Vec<f64> = deflection_m.iter().map(|&w| self.drawn_z_m(w)).collect();
        let points = self
            .node_position_m
            .iter()
            .zip(&z)
            .flat_map(|(&x, &z)| [point(x, half, z), point(x, -half, z)])
            .collect();
        let segments = self.node_position_m.len().saturating_sub(1) as u32;
        let indices = (0..segments)
            .flat_map(|i| {
                let (a, b, c, d) = (2 * i, 2 * i + 1, 2 * i + 2, 2 * i + 3);
                [a, b, c, b, d, c]
            })
            .collect();
        entity.triangles.push(TriangleListPrimitive {
            pose: Some(identity()),
            points,
            color: Some(DECK),
            indices,
            ..Default::default()
        });
        let undeflected = vec![point(0.0, -half, 0.0), point(self.span_m, -half, 0.0)];
        entity.lines.push(line(undeflected, 0.05, UNDEFLECTED));
        let factor = self.info.exaggeration;
        entity.texts.push(text(
            point(0.5 * self.span_m, 0.0, TRUCK_BODY_HEIGHT_M + 2.5),
            format!(
                "deflection drawn x{factor} (expected peak {:.1} mm)",
                self.info.expected_peak_m * 1e3
            ),
            0.025 * self.span_m.clamp(20.0, 80.0),
        ));
        entity.metadata = vec![
            key_value("exaggeration", &format!("{factor}")),
            key_value("expected_peak_m", &format!("{}", self.info.expected_peak_m)),
            key_value(
                "drawn_z",
                "-exaggeration x deflection_m of /truth/bridge (downward positive), m",
            ),
        ];
        entity
    }

    /// A cone under each support (the two ends of a simple span).
    fn supports(&self, mut entity: SceneEntity) -> SceneEntity {
        for &x in &self.support_position_m {
            entity.cylinders.push(CylinderPrimitive {
                pose: Some(pose(point(x, 0.0, -0.5 * SUPPORT_HEIGHT_M), None)),
                size: Some(vector(SUPPORT_HEIGHT_M, SUPPORT_HEIGHT_M, SUPPORT_HEIGHT_M)),
                bottom_scale: 1.0,
                top_scale: 0.0,
                color: Some(SUPPORT),
            });
        }
        entity
    }

    /// A sphere under the deck's near edge at each sensor, coloured by kind, and its id.
    fn sensors(&self, mut entity: SceneEntity, deflection_m: &[f64]) -> SceneEntity {
        let y = -0.5 * self.deck_width_m;
        for (id, kind, x) in &self.sensors {
            let z = self.road_z_m(deflection_m, *x) - 0.5 * SENSOR_DIAMETER_M;
            entity.spheres.push(SpherePrimitive {
                pose: Some(pose(point(*x, y, z), None)),
                size: Some(vector(
                    SENSOR_DIAMETER_M,
                    SENSOR_DIAMETER_M,
                    SENSOR_DIAMETER_M,
                )),
                color: Some(sensor_color(*kind)),
            });
            entity
                .texts
                .push(text(point(*x, y - 0.6, z - 0.6), id.clone(), 0.4));
        }
        entity
    }

    /// A flat strip across the road at each WIM station.
    fn wim_strips(&self, mut entity: SceneEntity) -> SceneEntity {
        for (id, x) in &self.wim {
            entity.cubes.push(CubePrimitive {
                pose: Some(pose(point(*x, 0.0, 0.02), None)),
                size: Some(vector(0.5, self.deck_width_m, 0.04)),
                color: Some(WIM_STRIP),
            });
            entity.texts.push(text(
                point(*x, -0.5 * self.deck_width_m - 0.8, 0.5),
                format!("WIM {id}"),
                0.4,
            ));
        }
        entity
    }

    /// A box from the front axle to the last with a nominal overhang, a wheel pair at
    /// every axle (red while it has lost contact) and the vehicle's id.
    fn vehicle(
        &self,
        mut entity: SceneEntity,
        axles: &[AxleState],
        deflection: &[f64],
    ) -> SceneEntity {
        let (lo, hi) = axles.iter().fold((f64::MAX, f64::MIN), |(lo, hi), a| {
            (lo.min(a.position_m), hi.max(a.position_m))
        });
        let y = self.lane_y_m(axles[0].lane);
        let gross_n: f64 = axles.iter().map(|a| a.static_load_n).sum();
        let height = match gross_n < CAR_LIMIT_N {
            true => CAR_BODY_HEIGHT_M,
            false => TRUCK_BODY_HEIGHT_M,
        };
        let road: Vec<f64> = axles
            .iter()
            .map(|a| self.road_z_m(deflection, a.position_m))
            .collect();
        let road_mean = road.iter().sum::<f64>() / road.len().max(1) as f64;
        let bottom = road_mean + 0.8 * WHEEL_DIAMETER_M;
        let centre = point(0.5 * (lo + hi), y, bottom + 0.5 * height);
        entity.cubes.push(CubePrimitive {
            pose: Some(pose(centre, None)),
            size: Some(vector(hi - lo + 2.0 * OVERHANG_M, VEHICLE_WIDTH_M, height)),
            color: Some(BODY),
        });
        // The wheel's axis (local z) turned onto y: a quarter turn about x.
        let half_turn = std::f64::consts::FRAC_1_SQRT_2;
        let about_x = Quaternion {
            x: half_turn,
            y: 0.0,
            z: 0.0,
            w: half_turn,
        };
        for (a, z) in axles.iter().zip(road) {
            let at = point(a.position_m, y, z + 0.5 * WHEEL_DIAMETER_M);
            entity.cylinders.push(CylinderPrimitive {
                pose: Some(pose(at, Some(about_x))),
                size: Some(vector(WHEEL_DIAMETER_M, WHEEL_DIAMETER_M, VEHICLE_WIDTH_M)),
                bottom_scale: 1.0,
                top_scale: 1.0,
                color: Some(if a.in_contact { WHEEL } else { WHEEL_LIFTED }),
            });
        }
        let label = point(centre.x, centre.y, bottom + height + 0.6);
        entity
            .texts
            .push(text(label, format!("{}", axles[0].vehicle_id), 0.6));
        entity
    }
}

fn point(x: f64, y: f64, z: f64) -> Point3 {
    Point3 { x, y, z }
}

fn vector(x: f64, y: f64, z: f64) -> Vector3 {
    Vector3 { x, y, z }
}

fn identity() -> Pose {
    pose(point(0.0, 0.0, 0.0), None)
}

/// A pose at `at`, unrotated unless `orientation` is given (proto3 would default the
/// quaternion to all zeros, which is no rotation at all).
fn pose(at: Point3, orientation: Option<Quaternion>) -> Pose {
    Pose {
        position: Some(vector(at.x, at.y, at.z)),
        orientation: Some(orientation.unwrap_or(Quaternion {
            x: 0.0,
            y: 0.0,
            z: 0.0,
            w: 1.0,
        })),
    }
}

fn line(points: Vec<Point3>, thickness_m: f64, color: Color) -> LinePrimitive {
    LinePrimitive {
        r#type: line_primitive::Type::LineStrip as i32,
        pose: Some(identity()),
        thickness: thickness_m,
        scale_invariant: false,
        points,
        color: Some(color),
        ..Default::default()
    }
}

fn text(at: Point3, text: String, font_size_m: f64) -> TextPrimitive {
    TextPrimitive {
        pose: Some(pose(at, None)),
        billboard: true,
        font_size: font_size_m,
        scale_invariant: false,
        color: Some(LABEL),
        text,
    }
}

fn key_value(key: &str, value: &str) -> KeyValuePair {
    KeyValuePair {
        key: key.into(),
        value: value.into(),
    }
}

/// Linear interpolation of `ys` over the increasing `xs` at `x`, clamped to the ends.
pub(super) fn interpolate(xs: &[f64], ys: &[f64], x: f64) -> f64 {
    if xs.len() < 2 || ys.len() < xs.len() {
        return ys.first().copied().unwrap_or(0.0);
    }
    let i = xs.partition_point(|&v| v <= x).clamp(1, xs.len() - 1);
    let (x0, x1) = (xs[i - 1], xs[i]);
    let w = if x1 > x0 {
        ((x - x0) / (x1 - x0)).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ys[i - 1] * (1.0 - w) + ys[i] * w
}

#[cfg(test)]
mod tests {
    use super::*;

    fn geometry() -> SceneGeometry {
        let mut manifest = RunManifest::minimal();
        manifest.scene = Some(SceneInfo {
            every_shapes: 2,
            rate_hz: 10.0,
            exaggeration: 200.0,
            expected_peak_m: 0.004,
            lanes: 2,
        });
        SceneGeometry::new(&manifest).unwrap()
    }

    fn axle(vehicle_id: u32, axle_index: u32, position_m: f64, lane: u32) -> AxleState {
        AxleState {
            vehicle_id,
            axle_index,
            lane,
            position_m,
            force_n: 50e3,
            static_load_n: 50e3,
            in_contact: axle_index != 1,
            on_bridge: (0.0..=30.0).contains(&position_m),
        }
    }

    #[test]
    fn deck_follows_the_shape_times_the_factor_drawn_down() {
        let g = geometry();
        // Nodes at 0, 15, 30 m; 2 mm down at midspan.
        let scene = g.update(1, &[0.0, 0.002, 0.0], &[]);
        let deck = &scene.entities[0];
        assert_eq!(deck.id, "deck");
        let tri = &deck.triangles[0];
        // Two points per node (both edges), two triangles per segment.
        assert_eq!(tri.points.len(), 6);
        assert_eq!(tri.indices.len(), 12);
        // -200 x 2 mm, to the nearest 1/1024 m.
        assert_eq!(tri.points[2].z, (-0.4f64 * 1024.0).round() / 1024.0);
        assert_eq!(tri.points[2].x, 15.0);
        assert_eq!((tri.points[2].y, tri.points[3].y), (3.5, -3.5));
        let factor = deck.metadata.iter().find(|kv| kv.key == "exaggeration");
        assert_eq!(factor.map(|kv| kv.value.as_str()), Some("200"));
        assert!(
            deck.texts[0].text.contains("x200"),
            "{}",
            deck.texts[0].text
        );
        // The whole scene each time: everything earlier goes first.
        assert_eq!(scene.deletions.len(), 1);
        assert_eq!(
            scene.deletions[0].r#type,
            scene_entity_deletion::Type::All as i32
        );
    }

    #[test]
    fn vehicles_stand_on_the_deck_at_their_axles_in_their_lanes() {
        let g = geometry();
        let axles = [
            axle(3, 0, 16.0, 0),
            axle(3, 1, 11.0, 0),
            axle(4, 0, 40.0, 1),
            // Far out on the approach: not drawn.
            axle(5, 0, -80.0, 0),
        ];
        let scene = g.update(1, &[0.0, 0.002, 0.0], &axles);
        let ids: Vec<&str> = scene.entities.iter().map(|e| e.id.as_str()).collect();
        assert_eq!(
            ids,
            ["deck", "supports", "sensors", "vehicle/3", "vehicle/4"]
        );
        let v3 = &scene.entities[3];
        let body = &v3.cubes[0];
        let centre = body.pose.as_ref().unwrap().position.as_ref().unwrap();
        // From 11 - 1 to 16 + 1 m, in lane 0 (y = +1.75 on a 7 m deck).
        assert_eq!(body.size.as_ref().unwrap().x, 7.0);
        assert_eq!((centre.x, centre.y), (13.5, 1.75));
        let wheels: Vec<f64> = v3
            .cylinders
            .iter()
            .map(|c| c.pose.as_ref().unwrap().position.as_ref().unwrap().x)
            .collect();
        assert_eq!(wheels, [16.0, 11.0]);
        // Wheel 0 sits on the drawn deck at x = 16 m: w = 2 mm * 14/15, times -200, plus
        // the wheel radius.
        let z0 = v3.cylinders[0]
            .pose
            .as_ref()
            .unwrap()
            .position
            .as_ref()
            .unwrap()
            .z;
        let drawn = (-200.0 * 0.002 * 14.0 / 15.0 * 1024.0f64).round() / 1024.0;
        let expected = drawn + 0.5 * WHEEL_DIAMETER_M;
        assert!((z0 - expected).abs() < 1e-12, "{z0} vs {expected}");
        // The lifted wheel (axle 1) is red.
        assert_eq!(v3.cylinders[1].color, Some(WHEEL_LIFTED));
        let v4 = &scene.entities[4].cubes[0];
        let y4 = v4.pose.as_ref().unwrap().position.as_ref().unwrap().y;
        assert_eq!(y4, -1.75);
    }

    #[test]
    fn interpolation_clamps_at_the_ends() {
        let xs = [0.0, 10.0, 20.0];
        let ys = [0.0, 1.0, 0.0];
        assert_eq!(interpolate(&xs, &ys, 5.0), 0.5);
        assert_eq!(interpolate(&xs, &ys, 15.0), 0.5);
        assert_eq!(interpolate(&xs, &ys, -5.0), 0.0);
        assert_eq!(interpolate(&xs, &ys, 25.0), 0.0);
        assert_eq!(interpolate(&xs, &ys, 10.0), 1.0);
    }
}
