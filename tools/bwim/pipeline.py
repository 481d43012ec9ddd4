"""The whole B-WIM run, from the file to the exit status (tools/bwim_check.py docstring):
read, find the axles (FAD gauges or road axle detectors), calibrate on the truck's runs (or
load a calibration), weigh, and only then read the truth and score.

An input it cannot use (no such file, empty, not an MCAP file, truncated, a run without
the example's gauges, an unusable calibration file) raises ``BadInput`` (tools/bad_input.py):
tools/bwim_check.py prints its line and exits 2."""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

from bad_input import BadInput, check_exists, check_run, reader_error, require_topics

from .axles import detect_vehicles, fad_channels
from .calibration import Calibration, calibrate, calibration_runs, leave_one_out
from .cost323 import class_rank
from .io import AXLE_PREFIX, STRAIN_PREFIX, TRUTH_VEHICLES, read_axle_truth, read_strains, read_truth, weighing_sections
from .report import axle_truth_lines, plot, print_report, write_json
from .scoring import score_run, vehicle_errors
from .tapes import detect_vehicles_tapes
from .weighing import moses, weigh


def detect(rec, geo, args):
    """(vehicles, detection info, geometry) by the axle detection of --axles."""
    if args.axles == "detectors":
        return detect_vehicles_tapes(rec, args)
    return detect_vehicles(rec, geo, args)


EXAMPLE = "bwim_calibration"  # examples/bwim_calibration.toml: the installation this is made for


def load_calibration(path: str) -> Calibration:
    """The calibration written by --save-calibration, or BadInput naming the file."""
    check_exists(path, "calibration file")
    try:
        return Calibration.from_json(json.loads(Path(path).read_text()))
    except (ValueError, KeyError, TypeError, AttributeError) as e:  # JSONDecodeError is a ValueError
        raise BadInput(
            f"{path}: not a calibration file written by --save-calibration ({type(e).__name__}: {e})"
        ) from None


def read_record(args):
    """The strain record of the run, after the checks that say plainly what is wrong with
    a file that is not a B-WIM installation's run."""
    files = check_run(args.run)
    topics = require_topics(files[0], (STRAIN_PREFIX,), "strain gauge", EXAMPLE)
    if args.axles == "detectors":
        require_topics(files[0], (AXLE_PREFIX,), "road axle detector", EXAMPLE)
    try:
        rec = read_strains(args.run)
    except ValueError as e:  # what read_strains finds wrong: its message names the file
        raise BadInput(str(e)) from None
    except Exception as e:  # noqa: BLE001 - a file the readers cannot read is bad input
        raise reader_error(args.run, e) from None
    if args.axles == "fad":
        try:
            fad_channels(rec, args.fad_max_m)
        except ValueError as e:
            raise BadInput(f"{args.run}: {e} among its {len(topics)} strain gauges: is it the {EXAMPLE} example?") from None
    return rec


def run(args) -> int:
    t_start = time.perf_counter()
    rec = read_record(args)
    t_read = time.perf_counter() - t_start
    fad = args.axles == "fad"
    try:
        cal = None
        geo = None
        if args.calibration_from:
            cal = load_calibration(args.calibration_from)
            if cal.axles != args.axles:
                raise ValueError(
                    f"{args.calibration_from} was calibrated with --axles {cal.axles}: "
                    "weigh with the same axle detection"
                )
            geo = cal.geometry
        vehicles, det, geo = detect(rec, geo, args)
        if not vehicles:
            raise ValueError(f"no vehicle detected by the {'FAD gauges' if fad else 'road axle detectors'}")
        truth = None
        loo = []
        if cal is None:
            # The calibration truck's weighbridge ticket: its static loads and spacings.
            truth = read_truth(args.run)
            ids = args.calibration_ids if args.calibration_ids is not None else rec.listed_vehicle_ids
            cal_truth = [tr for tr in truth if tr["id"] in set(ids)]
            if not cal_truth:
                raise ValueError(f"no calibration vehicle (ids {ids}) in {TRUTH_VEHICLES}")
            if fad:  # the FAD distance calibrated on the truck's known spacings
                _, geo = calibration_runs(rec, vehicles, cal_truth, geo, args, others=[])
                vehicles, det, geo = detect_vehicles(rec, geo, args)  # with the calibrated distance
            # The runs alone on the bridge: a first calibration on every run weighs the
            # detections, so that rebounds taken for vehicles (lighter than --min-gross-kn)
            # do not disqualify a run.
            f1 = det["f1_hz"] if args.vibration_terms else None
            every, geo = calibration_runs(rec, vehicles, cal_truth, geo, args, others=[], calibrate_distance=fad)
            _, dropped = weigh(rec, vehicles, calibrate(rec, every, geo, args)[0], args, f1)
            real = [v for v in vehicles if all(v is not d for d in dropped)]
            for v in vehicles:
                v.loads_n = None
            clean, geo = calibration_runs(rec, vehicles, cal_truth, geo, args, others=real, calibrate_distance=fad)
            cal, parts = calibrate(rec, clean, geo, args)
            if not fad:  # the installation: which detectors, where
                keys = ("lane", "direction", "up", "down", "up_position_m", "down_position_m", "distance_m")
                cal.detectors = [{k: p[k] for k in keys} for p in det["pairs"]]
            # Leave-one-out: each calibration run weighed with the others' influence lines.
            sections = weighing_sections(rec, args.fad_max_m)
            for tr, v in clean:
                try:
                    cal_k = leave_one_out(cal, parts, tr["id"], args.il_smoothing)
                except ValueError:
                    continue
                moses(
                    rec,
                    sections,
                    cal_k,
                    [v],
                    args.pad_s,
                    args.group_penalty,
                    det["f1_hz"] if args.vibration_terms else None,
                )
                v.truth = tr
                loo.append(vehicle_errors(v))
                v.truth, v.loads_n = None, None
        groups, dropped = weigh(rec, vehicles, cal, args, det["f1_hz"] if args.vibration_terms else None)
        vehicles = [v for v in vehicles if all(v is not d for d in dropped)]
        for k, v in enumerate(vehicles):
            v.index = k
    except ValueError as e:  # what the steps find wrong with the run: no vehicle, no calibration run ...
        print(f"bwim_check: {args.run}: {e}", file=sys.stderr)
        return 2
    t_process = time.perf_counter() - t_start
    if args.save_calibration:
        Path(args.save_calibration).write_text(json.dumps(cal.to_json(), indent=1))
    # ---- only now the truth of the traffic
    if truth is None:
        try:
            truth = read_truth(args.run)
        except (KeyError, ValueError) as e:
            raise BadInput(f"{args.run}: no truth to score against ({TRUTH_VEHICLES}): {e}") from None
    s = score_run(rec, vehicles, groups, truth, loo, geo, args)
    if not s.weighed:
        print(
            f"bwim_check: {args.run}: no traffic vehicle over 3.5 t was detected and weighed ({len(s.heavy_truth)} in the truth)",
            file=sys.stderr,
        )
        return 2
    axle_lines, axle_truth = ([], None) if fad else axle_truth_lines(det, read_axle_truth(args.run))
    gross = s.table["gross"]
    ok = gross.get("class_reached") is not None and class_rank(gross["class_reached"]) <= class_rank(args.expect_class)
    # ---- report
    common = (args, rec, cal, det, len(vehicles), len(dropped), loo, s, (t_read, t_process), ok)
    print_report(*common, axle_lines)
    if args.json:
        write_json(args.json, *common, axle_truth)
    if args.plot:
        plot(
            args.plot,
            cal,
            s.weighed,
            s.table,
            f"B-WIM of {Path(args.run).name}: {len(s.weighed)} vehicles > 3.5 t weighed, conditions {args.conditions}",
        )
    return 0 if ok else 1
