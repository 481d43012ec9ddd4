#!/usr/bin/env python3
"""Recompute every figure that docs/physics.md marks *derived*, independently of the crate.

    python3 tools/physics_figures.py                          # table against docs/physics.md
    python3 tools/physics_figures.py --check docs/physics.md  # exit 1 if a figure differs
    python3 tools/physics_figures.py --check docs/physics.md --only lumped

Each figure is one small function, named after what it computes, coded from the formulas
and inputs that docs/physics.md states (the section is in its docstring): the closed forms
in ``physics_figures_formulas.py``, the sprung-mass simulations of section 5.3 (VBI-2D's
scheme re-run, and the continuous equations) in ``physics_figures_vbi2d.py``. numpy and
scipy only, nothing of the crate (no import, no source read). This file holds the list of
figures with their anchors in the document, and the check.

The document's value of each figure is read from its text by an anchor, a regular
expression around the number that matches the document exactly once, so an edit of the
number in the document is what gets checked. A figure agrees when the recomputed value
rounds to the printed one: within half a unit of the last printed digit ("rounded"), or,
for a figure the text states as an upper bound ("within 4e-6", "at most 4e-6"), when the
printed value is the recomputed one rounded up at its last digit ("bound"). Magnitudes
the text prints without their sign are compared as magnitudes.

Exit status with ``--check``: 0 when every figure agrees, 1 naming each figure that does
not (or whose anchor is missing or not unique), 2 when the document cannot be read.
Without ``--check`` the table is printed against the repository's docs/physics.md and
the exit status is 0. Run time about 25 s (the sprung-mass simulations).
"""

from __future__ import annotations

import argparse
import os
import re
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

# Small matrices: BLAS threads only contend for the cores (25 s instead of 1 s for the
# 100-mode re-runs on a loaded 2-core machine).
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

sys.path.insert(0, str(Path(__file__).resolve().parent))

import physics_figures_formulas as F  # noqa: E402
import physics_figures_vbi2d as V  # noqa: E402

DEFAULT_DOC = Path(__file__).resolve().parent.parent / "docs" / "physics.md"

NUM = r"([-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?)"  # the captured figure
N_ = r"[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?"  # a number that is not captured

# ---------------------------------------------------------------- the figures


@dataclass(frozen=True)
class Figure:
    name: str
    section: str
    anchor: str  # regular expression, exactly one match in the document, group 1 the figure
    compute: Callable[[], float]
    kind: str = "rounded"  # or "bound": the printed value is an upper bound, rounded up
    magnitude: bool = False  # the document prints |value|


def table_cell(row_label: str, column: int) -> str:
    """Anchor of the figure in column `column` (0 = first after the label) of a row."""
    cells = [r"[^|\n]+?"] * column + [NUM]
    return r"^\| " + re.escape(row_label) + r" \| " + r" \| ".join(cells) + r"(?: %)? \|"


def _figures() -> list[Figure]:
    f: list[Figure] = [
        Figure(
            "EI/m of the paper's bridge",
            "1",
            r"\(2 L\^2 f1 / pi\)\^2 = " + NUM,
            F.ei_over_m_from_f1,
        ),
    ]
    for i, mode in enumerate((1, 2, 3)):
        nums = [N_, N_, N_]
        nums[i] = NUM
        f.append(
            Figure(
                f"f{mode} of the crate's beam, 7 digits",
                "1",
                r"recomputed: " + ", ".join(nums) + " Hz",
                lambda mode=mode: F.simple_beam_frequency_hz(mode),
            )
        )
        f.append(
            Figure(
                f"f{mode} of the crate's beam",
                "1",
                table_cell(str(mode), 0) + "$",
                lambda mode=mode: F.simple_beam_frequency_hz(mode),
            )
        )
    for n_masses in (7, 20, 31):
        for mode in (1, 2, 3):
            f.append(
                Figure(
                    f"lumped f{mode} error, N = {n_masses}",
                    "2",
                    table_cell(str(n_masses), mode - 1),
                    lambda n=n_masses, mode=mode: F.lumped_frequency_error(n, mode),
                )
            )
    for n_el in (4, 10, 40):
        f.append(
            Figure(
                f"Hermite worst f1..f3 error, {n_el} elements",
                "3",
                table_cell(str(n_el), 0) + "$",
                lambda n=n_el: F.hermite_worst_error_f1_to_f3(n),
            )
        )
    f += [
        Figure(
            "Rayleigh a0", "4.1", r"`a0 = " + NUM + " 1/s`", lambda: F.rayleigh_coefficients()[0]
        ),
        Figure("Rayleigh a1", "4.1", r"`a1 = " + NUM + " s`", lambda: F.rayleigh_coefficients()[1]),
        Figure(
            "Rayleigh ratio at mode 3 (%)",
            "4.1",
            NUM + r" % at mode 3",
            F.rayleigh_ratio_mode3_percent,
        ),
        Figure(
            "Newmark elongation, dt/T = 0.02 (%)",
            "4.2",
            table_cell("0.02", 0),
            lambda: F.newmark_period_elongation_percent(0.02),
        ),
        Figure(
            "Newmark series, dt/T = 0.02 (%)",
            "4.2",
            table_cell("0.02", 1),
            lambda: F.newmark_period_series_percent(0.02),
        ),
        Figure(
            "Newmark elongation, dt/T = 0.1 (%)",
            "4.2",
            table_cell("0.1", 0),
            lambda: F.newmark_period_elongation_percent(0.1),
        ),
        Figure(
            "Newmark series, dt/T = 0.1 (%)",
            "4.2",
            table_cell("0.1", 1),
            lambda: F.newmark_period_series_percent(0.1),
        ),
        Figure(
            "step for axle hop at 15 Hz (ms)",
            "4.2",
            r"`dt <= " + NUM + " ms`",
            F.step_for_axle_hop_ms,
        ),
        Figure(
            "tyre excitation at 20 m/s (Hz)",
            "4.2",
            r"\(" + NUM + r" Hz at\s+20 m/s",
            F.tyre_excitation_top_hz,
        ),
        Figure(
            "dt / T at 1 ms and 80 Hz",
            "4.2",
            r"1 ms is `dt / T = " + NUM + "`",
            F.step_ratio_at_1ms_80hz,
        ),
        Figure(
            "Newmark elongation at 80 Hz, 1 ms (%)",
            "4.2",
            r"`dt / T = " + N_ + "`, about " + NUM + " %",
            lambda: F.newmark_period_elongation_percent(0.08),
        ),
    ]
    for i, alpha in enumerate((0.05, 0.10, 0.20, 0.30, 0.50)):
        f.append(
            Figure(
                f"undamped DAF, alpha = {alpha}",
                "5.1",
                table_cell("DAF", i),
                lambda a=alpha: F.moving_force_daf(a),
            )
        )
    f += [
        Figure(
            "largest undamped DAF (3 digits)",
            "5.1",
            r"The maximum is " + NUM + " near",
            lambda: F.moving_force_daf_maximum()[0],
        ),
        Figure(
            "alpha of the largest DAF (2 digits)",
            "5.1",
            r"near `alpha = " + NUM + "`",
            lambda: F.moving_force_daf_maximum()[1],
        ),
        Figure(
            "largest undamped DAF",
            "5.1",
            r"\(recomputed: " + NUM + " at " + N_ + r"\)",
            lambda: F.moving_force_daf_maximum()[0],
        ),
        Figure(
            "alpha of the largest DAF",
            "5.1",
            r"\(recomputed: " + N_ + " at " + NUM + r"\)",
            lambda: F.moving_force_daf_maximum()[1],
        ),
        Figure(
            "2 f1 L of the paper's bridge (m/s)",
            "5.1",
            r"`2 f1 L = " + NUM + " m/s`",
            F.critical_speed_paper_m_s,
        ),
    ]
    for i, speed in enumerate((10.0, 20.0, 30.0)):
        f.append(
            Figure(
                f"DAF undamped, {speed:g} m/s",
                "5.1",
                table_cell("undamped", i),
                lambda s=speed: F.paper_beam_daf(s, 0.0),
            )
        )
        f.append(
            Figure(
                f"DAF 2 % damped, {speed:g} m/s",
                "5.1",
                table_cell("damped", i),
                lambda s=speed: F.paper_beam_daf(s, 0.02),
            )
        )
    f += [
        Figure(
            "f1 of the VBI-2D beam (Hz)",
            "5.3",
            r"\(f1 =\s+" + NUM + r" Hz, \*derived\*\)",
            V.vbi2d_beam_f1_hz,
        ),
        Figure(
            "sprung mass alone (Hz)", "5.3", r"\(" + NUM + r" Hz alone", V.vbi2d_vehicle_alone_hz
        ),
    ]
    for case in V.VBI2D_CASES:
        row = "`" + case.name + "`"
        f.append(
            Figure(
                f"{case.name} 1 ms re-run, 100 modes: peak (m)",
                "5.3",
                table_cell(row, 2),
                lambda c=case.name: V.vbi2d_published_sample(c, "peak"),
            )
        )
        f.append(
            Figure(
                f"{case.name} 1 ms re-run, 100 modes: peak time (s)",
                "5.3",
                table_cell(row, 3),
                lambda c=case.name: V.vbi2d_published_sample(c, "peak_t"),
            )
        )
        for j, t_s in enumerate(("0.2", "0.4", "0.6", "0.8")):
            nums = [N_] * 4
            nums[j] = NUM
            f.append(
                Figure(
                    f"{case.name} 1 ms re-run, 100 modes: w at {t_s} s (m)",
                    "5.3",
                    r"^\| " + re.escape(row) + r" \|(?:[^|\n]+\|){4} " + ", ".join(nums) + r" \|",
                    lambda c=case.name, t_s=t_s: V.vbi2d_published_sample(c, t_s),
                )
            )
    f.append(
        Figure(
            "VBI-2D re-run, 25 against 100 modes, peaks",
            "5.3",
            r"with 25 modes the peaks move by at most " + NUM,
            V.vbi2d_mode_truncation_peak_rel,
            kind="bound",
        )
    )
    names = [c.name for c in V.VBI2D_CASES]
    for i, name in enumerate(names):
        nums = [N_] * 3
        nums[i] = NUM
        f.append(
            Figure(
                f"{name} step error estimate, peak",
                "5.3",
                r"on the peak\s+" + r",?\s+(?:and\s+)?".join(nums),
                lambda c=name: V.vbi2d_step_error_peak_rel(c),
                magnitude=True,
            )
        )
        f.append(
            Figure(
                f"{name} step error estimate, history",
                "5.3",
                r"and at most\s+"
                + r",?\s+(?:and\s+)?".join(nums)
                + r"\s+of the peak over the histories",
                lambda c=name: V.vbi2d_step_error_history_rel(c),
            )
        )
    f += [
        Figure(
            "DampOn, the equations' dashpot term: history",
            "5.3",
            r"the `DampOn` history moves by up to\s+" + NUM,
            V.vbi2d_assembly_history_rel,
        ),
        Figure(
            "DampOn, the equations' dashpot term: peak",
            "5.3",
            r"and its peak\s+rises by\s+" + NUM,
            V.vbi2d_assembly_peak_rel,
        ),
        Figure(
            "VBI-2D scheme at 0.125 ms against the continuous peaks",
            "5.3",
            r"At 0\.125 ms the scheme's peaks are within\s+" + NUM,
            V.vbi2d_fine_step_vs_reference_rel,
            kind="bound",
        ),
        Figure(
            "DampOn, equations' term at 0.125 ms against the continuous peak",
            "5.3",
            r"the step error left at 0\.125 ms,\s+" + NUM,
            V.vbi2d_fine_step_equations_term_rel,
        ),
    ]
    for preset, col in (("two_axle_truck", 0), ("vbi2d_e01", 1)):
        for mode in range(4):
            nums = [N_] * 4
            nums[mode] = NUM
            cells = [r"[^|\n]+?"] * col + [", ".join(nums)]
            f.append(
                Figure(
                    f"{preset} rigid-road mode {mode + 1} (Hz)",
                    "6.2",
                    r"^\| rigid-road modes \(Hz, \*derived\*\) \| " + r" \| ".join(cells) + r" \|",
                    lambda p=preset, m=mode: float(F.half_car_rigid_road_modes_hz(p)[m]),
                )
            )
        for axle in range(2):
            nums = [N_, N_]
            nums[axle] = NUM
            cells = [r"[^|\n]+?"] * col + [" / ".join(nums)]
            f.append(
                Figure(
                    f"{preset} static axle load {axle + 1} (kN)",
                    "6.2",
                    r"^\| static axle loads \(kN, g = 9\.81, \*derived\*\) \| "
                    + r" \| ".join(cells)
                    + r" \|",
                    lambda p=preset, a=axle: F.half_car_static_axle_load_kn(p, a),
                )
            )
    for road_class in "ABCDEFGH":
        f.append(
            Figure(
                f"ISO 8608 class {road_class} band RMS (mm)",
                "7",
                table_cell(road_class, 2),
                lambda c=road_class: F.iso8608_band_rms_mm(c),
            )
        )
    f += [
        Figure(
            "ISO 8608 class A band RMS, unrounded (mm)",
            "7",
            r"class A\s+\(" + NUM + " mm\)",
            lambda: F.iso8608_band_rms_mm("A"),
        ),
        Figure(
            "JTG D60 mu at 3.78 Hz",
            "8",
            r"`mu = " + NUM + r"` \(\*derived\*\)",
            lambda: F.jtg_d60_mu(3.78),
        ),
        Figure(
            "JTG D60 log law at 1.5 Hz",
            "8",
            r"\(" + NUM + r" against 0\.05 at\s+1\.5 Hz",
            lambda: F.jtg_d60_mu(1.5),
        ),
        Figure(
            "JTG D60 log law at 14 Hz",
            "8",
            NUM + r" against 0\.45 at 14 Hz",
            lambda: F.jtg_d60_mu(14.0),
        ),
    ]
    for mode in (1, 2, 3):
        nums = [N_] * 3
        nums[mode - 1] = NUM
        f.append(
            Figure(
                f"three spans, f{mode} (Hz)",
                "10",
                r"gives\s+" + r",?\s+(?:and\s+)?".join(nums) + r" Hz \(\*derived\*\)",
                lambda m=mode: F.three_span_frequency_hz(m),
            )
        )
    f += [
        Figure(
            "E / E_ref at -10 degC",
            "12",
            r"`E / E_ref = " + NUM + "`",
            lambda: F.stiffness_ratio_default_law(-10.0),
        ),
        Figure(
            "f1 at -10 degC (Hz)",
            "12",
            r"from 3\.7801\s+to " + NUM + " Hz",
            lambda: F.f1_at_temperature_hz(-10.0, False),
        ),
        Figure(
            "damped f1 at -10 degC (Hz)",
            "12",
            r"\(" + NUM + " Hz damped\)",
            lambda: F.f1_at_temperature_hz(-10.0, True),
        ),
    ]
    return f


FIGURES = _figures()


# ---------------------------------------------------------------- reading and comparing


def last_digit_unit(text: str) -> float:
    """One unit in the last printed digit of a number as written ("1.8e-3" -> 1e-4)."""
    mantissa, _, exponent = text.lower().partition("e")
    decimals = len(mantissa.partition(".")[2])
    return 10.0 ** (int(exponent or 0) - decimals)


@dataclass
class Row:
    figure: Figure
    doc_text: str | None
    value: float
    problem: str | None

    @property
    def doc_value(self) -> float | None:
        return float(self.doc_text) if self.doc_text is not None else None


def compare(fig: Figure, doc_text: str, value: float) -> str | None:
    """None when the printed figure agrees with the recomputed value, else why not."""
    printed = float(doc_text)
    unit = last_digit_unit(doc_text)
    x = abs(value) if fig.magnitude else value
    slack = 1e-9 * max(abs(x), unit)  # a tie printed either way is not a disagreement
    if fig.kind == "bound":
        if not (x <= printed + slack and printed - unit < x + slack):
            return f"the bound {doc_text} is not {x:.6g} rounded up at its last digit"
        return None
    if abs(printed - x) > 0.5 * unit + slack:
        return f"{doc_text} is not {x:.6g} rounded to its last digit"
    return None


def evaluate(doc: str, figures: list[Figure]) -> list[Row]:
    rows = []
    for fig in figures:
        # A space of the anchor matches any run of white space: reflowing a paragraph
        # moves line breaks, not figures.
        pattern = fig.anchor.replace(" ", r"\s+")
        matches = list(re.finditer(pattern, doc, flags=re.MULTILINE))
        value = fig.compute()
        if len(matches) != 1:
            rows.append(
                Row(
                    fig,
                    None,
                    value,
                    f"anchor found {len(matches)} times, expected once: {fig.anchor}",
                )
            )
            continue
        text = matches[0].group(1)
        rows.append(Row(fig, text, value, compare(fig, text, value)))
    return rows


def print_table(rows: list[Row]) -> None:
    print(
        f"{'figure':<58} {'sec':>4} {'docs':>13} {'recomputed':>14} {'rel diff':>9} {'tol':>9}  ok"
    )
    for r in rows:
        x = abs(r.value) if r.figure.magnitude else r.value
        if r.doc_text is None:
            print(
                f"{r.figure.name:<58} {r.figure.section:>4} {'-':>13} {x:>14.7g} {'-':>9} {'-':>9}  NO"
            )
            continue
        rel = (x - r.doc_value) / abs(r.doc_value) if r.doc_value else float("nan")
        unit = last_digit_unit(r.doc_text)
        tol = f"<{unit:.0e}" if r.figure.kind == "bound" else f"{0.5 * unit:.1e}"
        ok = "ok" if r.problem is None else "NO"
        print(
            f"{r.figure.name:<58} {r.figure.section:>4} {r.doc_text:>13} {x:>14.7g} {rel:>9.1e} {tol:>9}  {ok}"
        )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--check", metavar="DOC", help="compare with DOC; exit 1 on any disagreement"
    )
    parser.add_argument("--only", metavar="REGEX", help="only the figures whose name matches REGEX")
    args = parser.parse_args(argv)
    path = Path(args.check) if args.check else DEFAULT_DOC
    try:
        doc = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as err:
        print(f"physics_figures: cannot read the document {path}: {err}", file=sys.stderr)
        return 2
    figures = [f for f in FIGURES if args.only is None or re.search(args.only, f.name)]
    if not figures:
        print(f"physics_figures: --only {args.only!r} matches no figure", file=sys.stderr)
        return 2
    rows = evaluate(doc, figures)
    print_table(rows)
    bad = [r for r in rows if r.problem is not None]
    print(f"\n{len(rows) - len(bad)} of {len(rows)} figures agree with {path}")
    for r in bad:
        print(f"DIFFERS: {r.figure.name} (section {r.figure.section}): {r.problem}")
    return 1 if (args.check and bad) else 0


if __name__ == "__main__":
    sys.exit(main())
