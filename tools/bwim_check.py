#!/usr/bin/env python3
"""Bridge weigh-in-motion (B-WIM) of a bridgetwin run, scored against the run's own truth.

    python3 tools/bwim_check.py run.mcap                        # calibrate, weigh, score
    python3 tools/bwim_check.py run.mcap --expect-class "B+(7)" --json bwim.json --plot bwim.svg
    python3 tools/bwim_check.py run.mcap --save-calibration cal.json
    python3 tools/bwim_check.py other.mcap --calibration-from cal.json   # another run's calibration
    python3 tools/bwim_check.py run.mcap --axles detectors      # road axle detectors, not FAD

What it does, as a B-WIM operator would with a real installation's files. It reads only the
measured strain streams (``/sensors/strain/*``: the DAQ's stamps and values, the gauges'
positions from the channel metadata, the span from the run's metadata) and, for the
calibration, the calibration truck's static axle loads and axle spacings: the weighbridge
ticket and tape measure of a real calibration. Those come from ``/truth/vehicles`` for the
vehicles given by ``--calibration-ids`` (default: the vehicles the scenario lists one by one,
``[[vehicles]]``; the generated traffic is never used), together with their direction and
roughly when they crossed (the crew's log), only to say which detected vehicle is the truck.

1. **Axle detection and speed (FAD).** Gauges within ``--fad-max-m`` of a support are
   free-of-axle-detector gauges; those at one support are averaged. Near a support the
   strain influence line of a simply supported span rises steeply over the gauge's distance
   ``a`` from the support and falls slowly beyond, so each axle entering at that end is a
   step of about ``a (1 - a / L) P y / EI`` in the record (about 1 microstrain for a 6 t
   axle here), each axle leaving there a step down. The bridge's second mode, which would
   pass for a train of axles, is first subtracted from the FAD records with a reference:
   the difference of two weighing sections placed symmetrically (x and L - x), band-passed
   around ``4 f1`` (``f1`` picked blind from the spectrum), scaled by least squares. A step
   filter (mean of the next ``w`` samples minus mean of the previous ``w``, less its running
   median) turns the steps into peaks (``scipy.signal.find_peaks``) above
   ``--fad-threshold`` times its robust noise level (1.4826 MAD); a peak next to a deeper
   one of the other sign (``--lobe-s``) is that step's rebound, not a step. Clear entry
   steps grouped by time gaps (``--max-axle-gap-s``) make a candidate vehicle; the delay to
   the far support is the lag that best correlates the entry steps with the exit steps
   (``--min-correlation``), so speed ``v = D / delay``; the axles are the peaks of the sum
   of the entry steps and the exit steps one delay later (both ends' evidence,
   ``--axle-threshold``, each end at least ``--end-threshold``), at least ``--min-spacing-m``
   apart and split where two are farther apart than ``--max-spacing-m``. Spacings are ``v``
   times the differences of the axle times. ``D``, the effective distance between the two
   supports' steps (nominally ``L - a``), is calibrated on the truck: its known spacings
   give its speed.

   **Or road axle detectors** (``--axles detectors``; tape switches, the SiWIM practice):
   ``/sensors/axle/<id>``, each hit the detector's time of an axle crossing it, and per lane
   a pair of detectors a known distance apart (their positions and lanes from the channel
   metadata, as the installer measured them). Hits are grouped into vehicles by time gaps
   (``--max-axle-gap-s``); the two detectors' groups are paired under the delay that makes
   most axles reappear (``--tape-tolerance-s``), speed = distance / mean delay; an axle one
   detector missed takes its time from the other (counted and reported), one both missed
   is lost, and a vehicle one detector missed whole keeps the other's hits at the lane's
   median speed. The axle times are carried at that speed to the entry support, the reference
   point ``s = 0`` of the influence lines; nothing needs calibrating (``bwim/tapes.py``).
2. **Influence lines by the matrix method** (E. J. OBrien, M. J. Quilligan & R. Karoumi,
   "Calculating an influence line from direct measurements", Proc. ICE Bridge Eng. 159
   (BE1), 2006, 31-34; as cited, *not checked here*): with known axle loads ``A_i`` and axle
   positions ``s_i(t)`` the measured strain is ``e(t) = sum_i A_i I(s_i(t))``, linear in the
   ordinates of ``I``; least squares over every calibration run. The paper's ordinates sit
   at the sample spacing of one run; here they are the nodal values of a piecewise-linear
   ``I(s)`` (``--il-step-m``) so that runs at different speeds stack in one system, with a
   small second-difference (Tikhonov) penalty (``--il-smoothing``). Each run has its own
   nuisance columns, eliminated exactly: a baseline and the first mode's vibration (cos
   and sin at ``f1`` with linearly varying amplitudes; ``--no-vibration-terms``). One
   influence line per weighing section (gauges at one position, averaged) and travel
   direction (lane), in the travel coordinate ``s`` from the entry support. The calibrated
   line keeps what the truck's own dynamics add on average over the runs (the method's
   known limit): the study compares it with the twin's static influence line.
3. **Axle loads by Moses' least squares** (F. Moses, "Weigh-in-motion system using
   instrumented bridges", Transportation Engineering Journal, Proc. ASCE 105 (TE3), 1979,
   233-249, as docs/sensors.md section 3 cites it): ``min ||e - sum_i A_i I(s_i(t))||^2``
   over the vehicle's time on the bridge, every weighing section stacked (each weighted by
   the inverse of its noise), each section with the nuisance columns above. Vehicles whose
   times on the bridge overlap (multiple presence: two lanes, a close follower) are solved
   jointly, the unknowns being the axles of all of them (``--multiple-presence skip``
   leaves them unweighed instead). A detection lighter than ``--min-gross-kn`` is no vehicle:
   dropped, and its cluster solved again. A cluster whose fit leaves a relative residual
   (rms residual over rms of the modelled vehicle strain) above ``--max-residual`` is flagged
   and not weighed: a vehicle the FAD gauges missed or a wrong axle count shows there.
   ``--group-penalty`` adds a Tikhonov penalty on the load differences of neighbouring axles
   in a group (default 0: plain Moses). Gross weight = sum of the axle loads. Vehicles the FAD gauges do not see (cars, below about 3 t per
   axle) are not weighed; their strain, when they share the bridge with a truck, goes into
   the truck's estimate. Road axle detectors see them: they are weighed with the trucks
   they share the bridge with.
4. **Only then the truth.** ``/truth/vehicles`` (static axle loads, spacings, speed, entry
   time at the entry support) is matched to the detections by direction and entry time;
   relative errors of the gross weight, of each group of axles (spacing < 2.1 m, as
   ``src/measurement/wim/groups.rs``), of single axles and of the axles of a group, for the
   traffic vehicles of the COST 323 domain (gross weight > 3.5 t). The calibration runs are
   scored apart, leave-one-out (each run weighed with the influence lines of the others;
   conditions r2-I: one vehicle, several speeds).

**COST 323 classes.** Tolerances ``delta`` per class and criterion as the crate's table
(``src/measurement/wim/cost323.rs``, docs/sensors.md section 3; B. Jacob, E. J. OBrien &
S. Jehaes (eds.), Weigh-in-Motion of Road Vehicles: Final Report of the COST 323 Action,
LCPC, 2002). Acceptance: from the ``n`` relative errors of a criterion, mean ``m`` and
standard deviation ``s``, the level of confidence of the centred interval ``[-delta, delta]``
under a normal law is ``pi = Phi((delta - m) / s) - Phi((-delta - m) / s)``; a criterion is in
a class when ``pi >= pi0``. The minimum ``pi0`` depends on the test conditions (repeatability
r1, r2, R1, R2 x environment I, II, III; ``--conditions``, default ``R2-I``: a sample of the
traffic within one day) and on ``n``:
``pi0(n) = 2 Phi(u_inf sqrt((n - 1) / chi2_{n-1, 1-alpha})) - 1``, ``u_inf = Phi^-1((1 + pi_inf)/2)``:
the level that a system whose errors are unbiased and normal with exactly the coverage
``pi_inf`` of the conditions still reaches with probability ``1 - alpha`` (``alpha`` = 5 %) in a
sample of ``n`` (the sample standard deviation at its upper ``1 - alpha`` quantile), so that small
samples are judged with the margin their scatter needs and ``pi0 -> pi_inf`` as ``n`` grows. This
is this tool's reading of the specification's acceptance rule, and the ``pi_inf`` values in
``PI_INF`` are as recalled from the specification's table: *not checked here* against its
text (docs/sensors.md section 3 says the same of the tolerance table). ``delta_min``, the
narrowest interval that passes, is reported with ``pi`` and ``pi0`` so that the margin is
visible. The class reached is the best class whose ``delta`` is at least ``delta_min``.

Exit status 0 when the gross-weight class reached is ``--expect-class`` or better (default
D+(20)), 1 otherwise, 2 on bad input, one line on stderr naming the file (no such file,
empty, not an MCAP file, truncated; no strain topics or no FAD gauges, or with ``--axles
detectors`` no axle detectors: not the bwim_calibration example; no pair of axle
detectors, no usable calibration run, a missing or unreadable calibration file or one made
with the other axle detection, nothing to score: ``tools/bad_input.py``), 4 when the tool
itself failed.

The pipeline is the package ``tools/bwim/`` (one job per module: reading, FAD axles, road
axle detectors, calibration, weighing, COST 323, scoring, report); this file is its command
line.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

# The package tools/bwim/ next to this file, from any working directory.
sys.path.insert(0, str(Path(__file__).resolve().parent))

from bad_input import guard  # noqa: E402
from bwim.cost323 import CLASSES, PI_INF, assess, class_rank, pi0, pi_level  # noqa: E402, F401
from bwim.io import _reader, read_strains, read_truth  # noqa: E402, F401
from bwim.pipeline import run  # noqa: E402


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("run", help="bridgetwin MCAP file (or, with the bridgetwin package, a glob of hourly parts)")
    p.add_argument(
        "--expect-class",
        default="D+(20)",
        choices=CLASSES,
        help="exit 1 unless the gross weight reaches this class (D+(20))",
    )
    p.add_argument(
        "--conditions",
        default="R2-I",
        choices=[f"{r}-{e}" for r, e in PI_INF],
        help="COST 323 test conditions of the traffic sample (R2-I)",
    )
    p.add_argument(
        "--calibration-ids",
        type=lambda s: [int(x) for x in s.split(",") if x],
        help="vehicle ids of the calibration runs (default: the scenario's [[vehicles]])",
    )
    p.add_argument(
        "--calibration-from", help="use this calibration file (from --save-calibration) instead of calibrating"
    )
    p.add_argument("--save-calibration", help="write the calibration (influence lines, FAD distance) here")
    p.add_argument(
        "--multiple-presence",
        choices=["joint", "skip"],
        default="joint",
        help="vehicles on the bridge together: solved jointly (default) or not weighed",
    )
    p.add_argument(
        "--axles",
        choices=["fad", "detectors"],
        default="fad",
        help="axles and speed from the FAD gauges (default) or from road axle detectors, a pair per lane",
    )
    p.add_argument(
        "--tape-tolerance-s",
        type=float,
        default=0.005,
        help="with --axles detectors: an axle's two hits agree with the vehicle's delay to (0.005 s)",
    )
    p.add_argument("--fad-max-m", type=float, default=1.0, help="gauges this close to a support are FAD gauges (1.0 m)")
    p.add_argument("--fad-window-s", type=float, default=0.02, help="half length of the step filter (0.02 s)")
    p.add_argument("--fad-threshold", type=float, default=5.0, help="step detection threshold in noise sd (5)")
    p.add_argument(
        "--no-mode2-cancel",
        dest="cancel_mode2",
        action="store_false",
        help="keep the bridge's second mode in the FAD records",
    )
    p.add_argument(
        "--trend-window-s", type=float, default=0.5, help="running median removed from the step records (0.5 s)"
    )
    p.add_argument(
        "--lobe-s", type=float, default=0.1, help="a step's rebound of the other sign within this is no step (0.1 s)"
    )
    p.add_argument(
        "--axle-threshold",
        type=float,
        default=4.0,
        help="axle threshold on the sum of both ends' steps, in its noise sd (4)",
    )
    p.add_argument("--end-threshold", type=float, default=2.5, help="each end's step at an axle, in its noise sd (2.5)")
    p.add_argument(
        "--min-correlation", type=float, default=0.5, help="entry and exit step records must correlate this well (0.5)"
    )
    p.add_argument("--min-spacing-m", type=float, default=0.9, help="closest two axles of a vehicle (0.9 m)")
    p.add_argument("--max-spacing-m", type=float, default=8.0, help="farthest two consecutive axles of a vehicle (8 m)")
    p.add_argument(
        "--max-residual",
        type=float,
        default=0.3,
        help="a fit leaving more relative residual is flagged and not weighed (0.3)",
    )
    p.add_argument(
        "--min-gross-kn",
        type=float,
        default=10.0,
        help="a detection weighing less is no vehicle: dropped and its cluster weighed again (10 kN)",
    )
    p.add_argument("--min-axle-sep-s", type=float, default=0.025, help="closest two axles' steps (0.025 s)")
    p.add_argument(
        "--max-axle-gap-s", type=float, default=0.6, help="a longer gap between axle steps starts a new vehicle (0.6 s)"
    )
    p.add_argument("--v-min", type=float, default=5.0, help="slowest speed searched (5 m/s)")
    p.add_argument("--v-max", type=float, default=45.0, help="fastest speed searched (45 m/s)")
    p.add_argument("--il-step-m", type=float, default=0.1, help="node spacing of the influence lines (0.1 m)")
    p.add_argument(
        "--il-margin-m", type=float, default=1.0, help="influence lines extend this far beyond the supports (1.0 m)"
    )
    p.add_argument(
        "--il-smoothing", type=float, default=1e-3, help="second-difference penalty, relative to the data (1e-3)"
    )
    p.add_argument(
        "--group-penalty",
        type=float,
        default=0.0,
        help="Tikhonov penalty on load differences inside axle groups, relative (0: plain Moses)",
    )
    p.add_argument(
        "--no-vibration-terms",
        dest="vibration_terms",
        action="store_false",
        help="no first-mode vibration columns in the least squares",
    )
    p.add_argument("--pad-s", type=float, default=0.3, help="record kept before and after a vehicle's crossing (0.3 s)")
    p.add_argument(
        "--cal-match-s",
        type=float,
        default=1.0,
        help="a calibration run is the detection within this of its logged entry (1.0 s)",
    )
    p.add_argument(
        "--match-truth-s", type=float, default=0.25, help="detection and truth entry times agree to (0.25 s)"
    )
    p.add_argument("--json", help="write the results here")
    p.add_argument("--plot", help="write an SVG figure here")
    return p


def main(argv: list[str]) -> int:
    return run(parser().parse_args(argv))


if __name__ == "__main__":
    sys.exit(guard("bwim_check", main, sys.argv[1:]))
