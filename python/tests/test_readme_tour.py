"""The README's tour in Python, run as written: the shell commands of its tour regions
(between a ``<!-- tour`` mark and the next ``<!-- /tour -->``) make the files, with
``cargo run --release --`` taken as the command-line binary, then every ``python`` block of
the regions runs in the same folder, in a fresh interpreter. tests/suite/readme_tour.rs runs
the shell commands for the cargo suite; this runs them again to give the Python lines the
files the README says they read."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import REPO, _cli

CARGO_RUN = "cargo run --release --"


def tour_blocks(text: str) -> list[tuple[str, int, list[str]]]:
    """(info string, line of the opening fence, lines) of every fenced block in a tour region."""
    blocks, inside, open_block = [], False, None
    for number, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if open_block is not None:
            if stripped.startswith("```"):
                blocks.append(open_block)
                open_block = None
            else:
                open_block[2].append(line)
        elif stripped.startswith("<!-- tour"):
            inside = True
        elif stripped == "<!-- /tour -->":
            inside = False
        elif inside and stripped.startswith("```"):
            open_block = (stripped[3:].strip(), number, [])
    return blocks


def shell_commands(blocks) -> list[tuple[int, str]]:
    """(README line, command) of the sh blocks: continuation lines joined, comments left out."""
    commands, pending = [], None
    for info, fence, lines in blocks:
        if info != "sh":
            continue
        for offset, line in enumerate(lines, start=1):
            piece = line.strip()
            continues = piece.endswith("\\")
            piece = piece.rstrip("\\").rstrip()
            if pending is not None:
                pending = (pending[0], f"{pending[1]} {piece}")
            elif piece and not piece.startswith("#"):
                pending = (fence + offset, piece)
            if pending is not None and not continues:
                commands.append(pending)
                pending = None
    return commands


def test_the_python_lines_of_the_readme_tour_run(tmp_path: Path) -> None:
    """Every python block of the README's tour runs (exit 0) on the files its shell lines
    wrote; a failure names the block's README line and shows its stderr."""
    blocks = tour_blocks((REPO / "README.md").read_text())
    python = [(fence, lines) for info, fence, lines in blocks if info == "python"]
    commands = shell_commands(blocks)
    assert python, "the README's tour has no python block between its <!-- tour --> marks"
    assert commands, "the README's tour has no shell commands between its <!-- tour --> marks"
    (tmp_path / "examples").symlink_to(REPO / "examples")
    cli = str(_cli())
    for line, command in commands:
        if "verify" in command or "bench" in command:
            continue  # the headline's checks: the cargo suite runs them; no file comes of them
        done = subprocess.run(command.replace(CARGO_RUN, f"'{cli}'"), shell=True, cwd=tmp_path,
                              capture_output=True, text=True, stdin=subprocess.DEVNULL)
        assert done.returncode == 0, f"README line {line}: `{command}` failed:\n{done.stderr}"
    env = dict(os.environ, MPLBACKEND="Agg")
    for fence, lines in python:
        done = subprocess.run([sys.executable, "-c", "\n".join(lines)], cwd=tmp_path, env=env,
                              capture_output=True, text=True, stdin=subprocess.DEVNULL)
        assert done.returncode == 0, f"README python block at line {fence} failed:\n{done.stderr}"
    assert (tmp_path / "overview.png").stat().st_size > 0, "the tour's overview.png is empty"


def test_the_tour_blocks_are_found_with_their_lines() -> None:
    """The extraction on a made-up README: only blocks inside the marks, with their lines."""
    text = "```python\nnot_in_the_tour()\n```\n<!-- tour -->\n```sh\ncargo run --release -- a \\\n  b\n```\n" \
           "```python\nimport bridgetwin\n```\n<!-- /tour -->\n"
    blocks = tour_blocks(text)
    assert [(info, fence) for info, fence, _ in blocks] == [("sh", 5), ("python", 9)]
    assert shell_commands(blocks) == [(6, "cargo run --release -- a b")]


if __name__ == "__main__":
    sys.exit(pytest.main([__file__, "-q"]))
