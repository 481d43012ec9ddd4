"""Fixtures of the package's tests: the command-line tool they compare against, the
repository's independent pure-Python reader (tools/read_run.py), and small runs made once
per session by the command line."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "tools"))


def _cli() -> Path:
    """The bridgetwin binary: $BRIDGETWIN_BIN, else the release build of this checkout."""
    found = os.environ.get("BRIDGETWIN_BIN") or REPO / "target" / "release" / "bridgetwin"
    found = Path(found)
    if not found.exists():
        pytest.exit(f"{found}: no bridgetwin binary (cargo build --release, or set BRIDGETWIN_BIN)", 2)
    return found


@pytest.fixture(scope="session")
def cli() -> Path:
    return _cli()


def run_cli(*args: object, check: bool = True) -> subprocess.CompletedProcess:
    return subprocess.run([str(_cli()), *map(str, args)], capture_output=True, text=True, check=check)


@pytest.fixture(scope="session")
def runs(tmp_path_factory) -> Path:
    """A folder of runs made by the command line: the two-truck example in both layouts,
    and a 12 s default run whole and split into 4 s parts."""
    folder = tmp_path_factory.mktemp("runs")
    block = REPO / "examples" / "two_trucks.toml"
    sample = folder / "two_trucks_sample.toml"
    sample.write_text(block.read_text().replace('layout = "block"', 'layout = "sample"'))
    assert sample.read_text() != block.read_text(), "two_trucks.toml no longer sets layout = \"block\""
    run_cli("simulate", block, "--out", folder / "block.mcap", "--quiet")
    run_cli("simulate", sample, "--out", folder / "sample.mcap", "--quiet")
    default = run_cli("scenario", "show").stdout
    (folder / "whole.toml").write_text(default)
    split = default.replace("[output]", "[output]\nsplit_every_s = 4.0", 1)
    assert split != default, "the default scenario has no [output] table"
    (folder / "split.toml").write_text(split)
    run_cli("simulate", folder / "whole.toml", "--duration-s", 12, "--out", folder / "whole.mcap", "--quiet")
    run_cli("simulate", folder / "split.toml", "--duration-s", 12, "--out", folder / "day.mcap", "--quiet")
    return folder


@pytest.fixture()
def scratch(tmp_path) -> Path:
    return tmp_path


def copy(src: Path, dst: Path) -> Path:
    shutil.copyfile(src, dst)
    return dst
