"""What the tools in tools/ do with an input they cannot use: one line on stderr that names
the file and says what is wrong with it, and exit status 2 (``EXIT_BAD_INPUT``), never a
traceback. An exception nothing expected (a defect of the tool) is one line too, with exit
status 4 (``EXIT_TOOL_FAILED``): never 1, the status of a check that failed on valid data,
so that a crash cannot pass a check that is meant to fail.

    from bad_input import BadInput, check_mcap, guard, require_topics

    def main(argv):
        check_mcap(path)                          # no such file, empty, not MCAP, truncated
        require_topics(path, ("/sensors/strain/",), "strain", "bwim_calibration")
        ...

    if __name__ == "__main__":
        sys.exit(guard("bwim_check", main, sys.argv[1:]))

``check_mcap`` looks only at the file's size and its two MCAP magic strings (8 bytes at
the start, 8 at the end, `docs/output.md`): a file that starts with the magic but does not
end with it was cut short (a killed run's ``.partial``, a copy that stopped), and the
``mcap`` reader would only say ``EndOfFile:`` or ``RecordLengthLimitExceeded`` about it.
"""

from __future__ import annotations

import glob
import os
import subprocess
import sys
import traceback
from pathlib import Path
from typing import Callable, Iterable

EXIT_BAD_INPUT = 2
# The tool itself failed (an exception nothing expected): see guard().
EXIT_TOOL_FAILED = 4
MAGIC = b"\x89MCAP0\r\n"
# The smallest whole file: magic, a header record (opcode, length, two empty strings),
# the footer record (opcode, length, two offsets, a CRC) and the magic again.
MIN_WHOLE_BYTES = len(MAGIC) + (1 + 8 + 4 + 4) + (1 + 8 + 8 + 8 + 4) + len(MAGIC)


class BadInput(Exception):
    """An input the tool cannot use. ``str()`` is the line to print: it names the file."""


def check_exists(path: str | os.PathLike, what: str = "file") -> Path:
    """The path, if it names a file that exists and is not empty."""
    p = Path(path)
    if not p.exists():
        raise BadInput(f"{path}: no such {what}")
    if p.is_dir():
        raise BadInput(f"{path}: is a folder, not a {what}")
    if p.stat().st_size == 0:
        raise BadInput(f"{path}: empty (0 bytes)")
    return p


def check_mcap(path: str | os.PathLike, cut_ok: bool = False) -> None:
    """Raises BadInput unless `path` is a whole MCAP file by its size and magic strings.

    ``cut_ok``: a file that starts as MCAP but was cut short passes (a reader of the intact
    part of a killed run's ``.partial``); one too short to hold any record does not."""
    p = check_exists(path)
    size = p.stat().st_size
    with open(p, "rb") as f:
        head = f.read(len(MAGIC))
    if not head.startswith(MAGIC[: len(head)]):
        raise BadInput(f"{path}: not an MCAP file (it starts with {head!r}, not the MCAP magic)")
    if len(head) < len(MAGIC) or (size < MIN_WHOLE_BYTES and not cut_ok):
        raise BadInput(f"{path}: truncated: {size} bytes, too short for an MCAP file")
    if not cut_ok and is_cut(p):
        raise BadInput(
            f"{path}: truncated: {size} bytes and no MCAP footer at the end "
            "(a killed run's .partial or a copy cut short: tools/read_run.py reads its intact part)"
        )


def check_run(path: str | os.PathLike) -> list[str]:
    """The files of a run named as the bridgetwin package names them (a file, a glob of
    hourly parts, a split run's name ``day.mcap`` for ``day-0000.mcap`` ...), each passed
    through ``check_mcap``; BadInput when none is found."""
    text = os.fspath(path)
    if any(c in text for c in "*?["):
        files = sorted(glob.glob(text))
        if not files:
            raise BadInput(f"{text}: no file matches")
    elif Path(text).exists():
        files = [text]
    else:
        stem = text[: -len(".mcap")] if text.endswith(".mcap") else text
        files = sorted(glob.glob(glob.escape(stem) + "-[0-9][0-9][0-9][0-9].mcap"))
        if not files:
            raise BadInput(f"{text}: no such file")
    for f in files:
        check_mcap(f)
    return files


def check_binary(path: str | os.PathLike) -> str:
    """The path of a runnable bridgetwin binary (what the studies run), or BadInput: no
    such file, empty, not executable, cut short or not a program (the system cannot run
    it), or a program that is not bridgetwin (``--version`` does not name it)."""
    p = check_exists(path, "bridgetwin binary")
    if not os.access(p, os.X_OK):
        raise BadInput(f"{path}: not executable: not the bridgetwin binary")
    try:
        # An absolute path: a bare name would be looked for on PATH, not here.
        done = subprocess.run([str(p.absolute()), "--version"], capture_output=True, text=True, timeout=60)
    except OSError as e:  # ENOEXEC: a data file marked executable
        raise BadInput(f"{path}: cannot be run ({e.strerror}): not a program") from None
    except subprocess.TimeoutExpired:
        raise BadInput(f"{path}: `--version` did not answer in 60 s: not the bridgetwin binary") from None
    if done.returncode < 0:  # a cut copy of a program starts and dies (SIGSEGV, SIGBUS)
        raise BadInput(
            f"{path}: died of signal {-done.returncode} on `--version`: a truncated copy of the binary?"
        )
    if done.returncode != 0 or not done.stdout.startswith("bridgetwin"):
        said = (done.stdout or done.stderr).strip().splitlines()
        raise BadInput(
            f"{path}: not the bridgetwin binary (`--version` exited {done.returncode}"
            + (f" and printed {said[0][:80]!r})" if said else ")")
        )
    return str(p.absolute())


def run_binary(command: list[str]) -> None:
    """Runs a bridgetwin command (its output discarded); BadInput with its last line of
    stderr when it fails."""
    done = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        said = done.stderr.strip().splitlines()
        raise BadInput(
            f"{command[0]}: `{' '.join(command[1:3])} ...` exited {done.returncode}" + (f": {said[-1]}" if said else "")
        )


def is_cut(path: str | os.PathLike) -> bool:
    """Whether the file ends without the MCAP magic (it was cut short)."""
    with open(path, "rb") as f:
        f.seek(0, os.SEEK_END)
        size = f.tell()
        f.seek(max(size - len(MAGIC), 0))
        return f.read(len(MAGIC)) != MAGIC


def summary_of(path: str | os.PathLike):
    """The summary section of a whole MCAP file (``check_mcap`` first), or BadInput."""
    check_mcap(path)
    from mcap.reader import make_reader

    try:
        with open(path, "rb") as f:
            summary = make_reader(f).get_summary()
    except Exception as e:  # noqa: BLE001 - any reader error here is damage in the file
        raise reader_error(path, e) from None
    if summary is None:
        raise BadInput(f"{path}: damaged: no summary section")
    return summary


def require_topics(
    path: str | os.PathLike,
    prefixes: Iterable[str],
    what: str,
    example: str | None,
    topics: Iterable[str] | None = None,
    keep: Callable[[str], object] | None = None,
    shown: str | None = None,
) -> list[str]:
    """The file's topics under `prefixes` (and, with `keep`, those it keeps); BadInput when
    there is none, asking whether the file is the run of `example` (the
    examples/<example>.toml a tool is made for). `topics`: the file's topics when the
    caller has them, else read from the summary; `shown`: the topics named in the message
    (default: the prefixes)."""
    prefixes = tuple(prefixes)
    if topics is None:
        topics = [c.topic for c in summary_of(path).channels.values()]
    found = sorted(t for t in topics if t.startswith(prefixes) and (keep is None or keep(t)))
    if not found:
        names = shown or ", ".join(p + "*" for p in prefixes)
        hint = f": is it the {example} example?" if example else ""
        raise BadInput(f"{path}: this file has no {what} topics ({names}){hint}")
    return found


def reader_error(path: str | os.PathLike, error: BaseException) -> BadInput:
    """One line for an exception a reader raised on `path` (the mcap package's EndOfFile
    has no message of its own)."""
    if isinstance(error, BadInput):
        return error
    if isinstance(error, FileNotFoundError):
        return BadInput(f"{path}: no such file")
    name = type(error).__name__
    detail = str(error).strip().splitlines()[0] if str(error).strip() else ""
    if name == "EndOfFile" or not detail:
        detail = "the data ends in the middle of a record (truncated?)"
    return BadInput(f"{path}: damaged: {name}: {detail}")


def fail(tool: str, error: BadInput | str) -> int:
    """Prints the one line and returns EXIT_BAD_INPUT."""
    print(f"{tool}: {error}", file=sys.stderr)
    return EXIT_BAD_INPUT


def guard(tool: str, main: Callable[..., int], *args, path: str | None = None) -> int:
    """Runs ``main(*args)`` and returns its status, with two exceptions turned into one line:

    - BadInput, and with `path` (the tool's input file) any error the readers raise on
      it (the mcap and protobuf packages', the bridgetwin package's ReadError, an OSError):
      EXIT_BAD_INPUT;
    - anything else, a defect of the tool: EXIT_TOOL_FAILED, the exception and where it
      was raised on the line (``BRIDGETWIN_TOOLS_TRACEBACK=1`` prints the traceback
      instead). Never 1, which means a check failed: a crash cannot pass for one."""
    try:
        return main(*args)
    except BadInput as e:
        return fail(tool, e)
    except BrokenPipeError:  # the reader of stdout left (| head): as the shell's commands do
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 141
    except KeyboardInterrupt:
        print(f"{tool}: interrupted", file=sys.stderr)
        return 130
    except Exception as e:  # noqa: BLE001 - the last resort: one line, a status of its own
        if path is not None and _is_reader_error(e):
            return fail(tool, reader_error(path, e))
        if os.environ.get("BRIDGETWIN_TOOLS_TRACEBACK"):
            raise
        where = traceback.extract_tb(e.__traceback__)[-1]
        print(
            f"{tool}: internal error (a defect of the tool, not of the input): {type(e).__name__}: "
            f"{str(e).strip().splitlines()[0] if str(e).strip() else ''} "
            f"(at {Path(where.filename).name}:{where.lineno})",
            file=sys.stderr,
        )
        return EXIT_TOOL_FAILED


def _is_reader_error(error: BaseException) -> bool:
    module = type(error).__module__ or ""
    return (
        module.startswith(("mcap", "google.protobuf", "bridgetwin"))
        or isinstance(error, (EOFError, OSError))
        or type(error).__name__ in ("ReadError", "DecodeError", "ZstdError")
    )
