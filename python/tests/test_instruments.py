"""Instruments that see the vehicles, read by the package: an instrumented van's
accelerometers, GNSS fixes and state, and road axle detectors, column for column equal to
the independent reader (tools/read_run.py), and the contact points consistent."""

from __future__ import annotations

import numpy as np

import bridgetwin
from conftest import run_cli
from test_read import compare_run, reference

DRIVE_BY = """
seed = 7
[bridge]
span_m = 30.0
flexural_rigidity_n_m2 = 5.629e10
mass_per_length_kg_m = 12000.0
damping_ratio = 0.02
model = { kind = "finite_element", elements = 30 }
[road]
profile = { kind = "iso8608", class = "A" }
approach_m = 30.0
[output]
layout = "sample"
[[vehicles]]
model = { kind = "half_car", preset = "drive_by_van" }
speed_m_s = 8.0
[[vehicles]]
model = { kind = "half_car", preset = "two_axle_truck" }
speed_m_s = 15.0
entry_time_s = 1.0
[[sensors]]
id = "A_mid"
kind = "accelerometer"
position_m = 15.0
rate_hz = 200.0
[[sensors]]
id = "V_front"
kind = "accelerometer"
vehicle = { id = 1, axle = 1 }
rate_hz = 200.0
preset = "mems_lownoise"
[[gnss]]
id = "G"
vehicle = 1
rate_hz = 10.0
[[axle_detectors]]
id = "T1"
position_m = -5.0
jitter_s = 0.001
miss_probability = 0.2
"""


def test_vehicle_instruments_read_as_the_independent_reader_and_add_up(scratch):
    (scratch / "drive.toml").write_text(DRIVE_BY)
    path = scratch / "drive.mcap"
    run_cli("simulate", scratch / "drive.toml", "--out", path, "--quiet")
    run = bridgetwin.read(path)
    for topic in ("/vehicles/1/accel/V_front", "/vehicles/1/gnss/G", "/sensors/axle/T1",
                  "/truth/axle_detections", "/truth/vehicle_state/1"):
        assert topic in run, f"{topic} missing: {sorted(run)}"
    assert compare_run(run, reference(path)) > 10_000

    state = run["/truth/vehicle_state/1"]

    def per_axle(name: str) -> np.ndarray:
        # Lists of one length on every row come as one column per element: name.0, name.1.
        return np.column_stack([state[f"{name}.{j}"].to_numpy() for j in range(2)])

    assert "contacts.road_elevation_m.2" not in state  # the van's two axles
    road = per_axle("contacts.road_elevation_m")
    deck = per_axle("contacts.bridge_deflection_m")
    contact = per_axle("contacts.contact_elevation_m")
    np.testing.assert_allclose(contact, road - deck, rtol=0, atol=1e-15)
    assert np.abs(deck).max() > 1e-5  # the van and the truck bend the deck under it

    # Four axles cross the tape; it reports the detected ones at their own times.
    truth = run["/truth/axle_detections"]
    assert len(truth) == 4
    detected = truth[truth["detected"]]
    measured = run["/sensors/axle/T1"]
    assert len(measured) == len(detected)
    jitter_s = (detected["detected_time_ns"].to_numpy() - detected["crossing_time_ns"].to_numpy()) * 1e-9
    assert np.all(np.abs(jitter_s) < 5e-3)
