#!/usr/bin/env python3
"""Validate bridgetwin MCAP files with the official Python packages, independently of the
Rust writer.

    python3 tools/check_mcap.py run.mcap [more.mcap ...] [--no-require-metadata]

Checks, per file:
- every record parses, with CRCs (a linear pass with StreamReader, chunks decompressed);
- every message decodes with the schema embedded in the file (make_reader + DecoderFactory);
- the summary statistics (message count per channel, start and end time, schema, channel,
  metadata and attachment counts) equal what was read;
- log_time is never 0, never decreases through the file, equals publish_time and the
  message's ``timestamp`` field (on the measured topics of sensors on a DAQ node clock,
  channel metadata ``daq_node``, the timestamp is the node's: within 1 s of log_time; a
  ``foxglove.SceneUpdate`` has none: each of its entities' and deletions' timestamps);
- sequence counts 1, 2, 3 ... on every channel (in a later part of a split run, metadata
  ``split`` with ``part`` > 0, it goes on from the previous part: consecutive from where
  each channel starts);
- metadata records ``bridgetwin``, ``scenario`` and ``bridge_model`` exist (switchable);
- at least one ``/sensors/`` or ``/vehicles/`` channel (a bridge or a vehicle-mounted
  instrument) has messages (switchable): a run that measured nothing is not a valid
  monitoring record.

Prints one ``OK`` line per valid file; otherwise ``FAIL`` lines on stderr.

Exit status: 0 when every file is valid; 1 when a check failed on a file that could be
read (flipped bytes, a wrong count, no sensor message ...); 2 when a file cannot be
checked at all: no such file, empty, not an MCAP file, or truncated (it ends without the
MCAP footer: a killed run's ``.partial``, a copy cut short), one line on stderr per such
file (``tools/bad_input.py``); 4 when the tool itself failed.
"""

from __future__ import annotations

# A DAQ node's clock error (offset + drift between resyncs) stays far below this.
NODE_CLOCK_MAX_ERROR_NS = 1_000_000_000

import argparse
import sys
from collections import Counter
from datetime import datetime, timezone
from pathlib import Path

from mcap.reader import make_reader
from mcap.records import Attachment, Chunk, DataEnd, Footer, Message, Metadata
from mcap.stream_reader import StreamReader
from mcap_protobuf.decoder import DecoderFactory

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bad_input import EXIT_BAD_INPUT, BadInput, check_mcap, fail, guard  # noqa: E402

REQUIRED_METADATA = ("bridgetwin", "scenario", "bridge_model")
MAX_PROBLEMS = 20  # per file; the first ones say enough
# Topics of what an installation measures: on the bridge and road, or riding on a vehicle.
MEASURED_PREFIXES = ("/sensors/", "/vehicles/")


class Problems:
    """Collects failures. A check that fails on many messages is reported once, with the
    first offending values and the number of occurrences."""

    def __init__(self) -> None:
        self.first: dict[str, str] = {}  # key -> first message
        self.count: Counter = Counter()

    def add(self, text: str, key: str | None = None) -> None:
        key = key or text
        self.count[key] += 1
        if key not in self.first and len(self.first) < MAX_PROBLEMS:
            self.first[key] = text

    def check(self, ok: bool, text: str, key: str | None = None) -> None:
        if not ok:
            self.add(text, key)

    def lines(self) -> list[str]:
        return [
            text if self.count[key] == 1 else f"{text} (and {self.count[key] - 1} more like it)"
            for key, text in self.first.items()
        ]


def scan_records(path: str, problems: Problems) -> tuple[Counter, bool]:
    """Linear pass over every record, CRCs checked. Returns counts by record kind, and
    whether the file is a later part of a split run (its sequences go on from the last)."""
    counts: Counter = Counter()
    metadata_names = []
    continued = False
    with open(path, "rb") as f:
        for record in StreamReader(f, validate_crcs=True).records:
            counts[type(record).__name__] += 1
            if isinstance(record, Metadata):
                metadata_names.append(record.name)
                if record.name == "split":
                    continued = int(record.metadata.get("part", "0")) > 0
    problems.check(counts[DataEnd.__name__] == 1, "no DataEnd record (file not finished?)")
    problems.check(counts[Footer.__name__] == 1, "no Footer record (file not finished?)")
    problems.check(counts[Chunk.__name__] == 0, "chunk left undecoded by the stream reader")
    counts.update(f"metadata:{name}" for name in metadata_names)
    return counts, continued


def check_messages(path: str, problems: Problems, continued: bool) -> tuple[dict, dict]:
    """Indexed pass with decoding, in file order. Returns (summary info, observed).
    `continued`: a later part of a split run, whose channels start anywhere from 1."""
    per_channel: Counter = Counter()
    last_sequence: dict[int, int] = {}
    first_ns = last_ns = None
    previous_ns = 0
    with open(path, "rb") as f:
        reader = make_reader(f, validate_crcs=True, decoder_factories=[DecoderFactory()])
        header = reader.get_header()
        summary = reader.get_summary()
        if summary is None or summary.statistics is None:
            problems.add("no summary section or no statistics record")
            return {}, {}
        # log_time_order=False: read in file order, so that disorder is seen, not sorted away.
        for schema, channel, message, decoded in reader.iter_decoded_messages(log_time_order=False):
            topic, t_ns = channel.topic, message.log_time
            problems.check(schema is not None and schema.encoding == "protobuf", f"{topic}: schema encoding is not protobuf")
            problems.check(channel.message_encoding == "protobuf", f"{topic}: message encoding is not protobuf")
            problems.check(t_ns != 0, f"{topic}: log_time is 0", f"{topic} zero")
            problems.check(
                t_ns >= previous_ns,
                f"{topic}: log_time {t_ns} < previous {previous_ns} (not time-ordered)",
                f"{topic} order",
            )
            problems.check(message.publish_time == t_ns, f"{topic}: publish_time != log_time", f"{topic} publish")
            first = channel.id not in last_sequence
            expected = message.sequence if continued and first else last_sequence.get(channel.id, 0) + 1
            problems.check(
                message.sequence == expected and message.sequence >= 1,
                f"{topic}: sequence {message.sequence}, expected {expected}",
                f"{topic} sequence",
            )
            last_sequence[channel.id] = message.sequence
            if schema.name == "foxglove.SceneUpdate":
                # Foxglove's schema has no timestamp of its own: every entity and deletion
                # carries one, and each must be the log time.
                stamps = [e.timestamp for e in decoded.entities] + [d.timestamp for d in decoded.deletions]
                problems.check(bool(stamps), f"{topic}: a scene update with no entity", f"{topic} empty")
                for stamp in stamps:
                    stamp_ns = stamp.seconds * 1_000_000_000 + stamp.nanos
                    problems.check(
                        stamp_ns == t_ns,
                        f"{topic}: entity timestamp {stamp_ns} != log_time {t_ns}",
                        f"{topic} timestamp",
                    )
            elif "timestamp" not in decoded.DESCRIPTOR.fields_by_name:
                problems.add(f"{topic}: message {schema.name} has no timestamp field")
            else:
                stamp_ns = decoded.timestamp.seconds * 1_000_000_000 + decoded.timestamp.nanos
                if "daq_node" in channel.metadata:
                    problems.check(
                        abs(stamp_ns - t_ns) <= NODE_CLOCK_MAX_ERROR_NS,
                        f"{topic}: node timestamp {stamp_ns} more than 1 s from log_time {t_ns}",
                        f"{topic} node timestamp",
                    )
                else:
                    problems.check(
                        stamp_ns == t_ns,
                        f"{topic}: timestamp field {stamp_ns} != log_time {t_ns}",
                        f"{topic} timestamp",
                    )
            per_channel[channel.id] += 1
            previous_ns = t_ns
            first_ns = t_ns if first_ns is None else min(first_ns, t_ns)
            last_ns = t_ns if last_ns is None else max(last_ns, t_ns)
        attachments = sum(1 for _ in reader.iter_attachments())
        metadata = [m.name for m in reader.iter_metadata()]
    observed = {
        "per_channel": per_channel,
        "first_ns": first_ns,
        "last_ns": last_ns,
        "attachments": attachments,
        "metadata": metadata,
    }
    return {"header": header, "summary": summary}, observed


def check_file(path: str, require_metadata: bool, require_sensors: bool = True) -> tuple[Problems, str]:
    problems = Problems()
    try:
        records, continued = scan_records(path, problems)
        info, seen = check_messages(path, problems, continued)
    except Exception as error:  # any reader or decoder error is a failed check
        detail = str(error) or "unexpected end of data (truncated or unfinished file?)"
        problems.add(f"{type(error).__name__}: {detail}")
        return problems, ""
    if not info:
        return problems, ""
    summary, stats = info["summary"], info["summary"].statistics
    total = sum(seen["per_channel"].values())
    problems.check(stats.message_count == total, f"statistics: {stats.message_count} messages, read {total}")
    problems.check(records[Message.__name__] == total, f"linear pass read {records[Message.__name__]} messages, indexed {total}")
    for channel_id, channel in summary.channels.items():
        listed = stats.channel_message_counts.get(channel_id, 0)
        read = seen["per_channel"].get(channel_id, 0)
        problems.check(listed == read, f"{channel.topic}: statistics say {listed} messages, read {read}")
    problems.check(set(seen["per_channel"]) <= set(summary.channels), "messages on channels missing from the summary")
    if total:
        problems.check(stats.message_start_time == seen["first_ns"], "statistics: message_start_time != first log_time")
        problems.check(stats.message_end_time == seen["last_ns"], "statistics: message_end_time != last log_time")
    problems.check(stats.schema_count == len(summary.schemas), "statistics: schema_count != schemas in summary")
    problems.check(stats.channel_count == len(summary.channels), "statistics: channel_count != channels in summary")
    problems.check(stats.metadata_count == records[Metadata.__name__] == len(seen["metadata"]), "statistics: metadata_count != metadata records")
    problems.check(stats.attachment_count == records[Attachment.__name__] == seen["attachments"], "statistics: attachment_count != attachments")
    for schema in summary.schemas.values():
        problems.check(not schema.name.startswith("."), f"schema name {schema.name!r} has a leading dot")
    if require_metadata:
        for name in REQUIRED_METADATA:
            problems.check(name in seen["metadata"], f"metadata record {name!r} missing")
    if require_sensors:
        measured = [
            c.topic
            for i, c in summary.channels.items()
            if c.topic.startswith(MEASURED_PREFIXES) and seen["per_channel"].get(i, 0) > 0
        ]
        problems.check(bool(measured), "no /sensors/ or /vehicles/ channel has a message: nothing was measured")

    start = datetime.fromtimestamp(stats.message_start_time / 1e9, tz=timezone.utc)
    duration_s = (stats.message_end_time - stats.message_start_time) * 1e-9
    line = (
        f"{total} messages on {len(summary.channels)} channels, {len(summary.schemas)} schemas, "
        f"{stats.metadata_count} metadata, {stats.attachment_count} attachments, "
        f"{duration_s:.3f} s from {start.isoformat()} ({info['header'].library})"
    )
    return problems, line


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("files", nargs="+", metavar="FILE")
    parser.add_argument(
        "--require-metadata",
        action=argparse.BooleanOptionalAction,
        default=True,
        help="require the bridgetwin, scenario and bridge_model metadata records (default: on)",
    )
    parser.add_argument(
        "--require-sensors",
        action=argparse.BooleanOptionalAction,
        default=True,
        help="require messages on at least one /sensors/ or /vehicles/ channel (default: on)",
    )
    args = parser.parse_args()
    failed = unusable = 0
    for path in args.files:
        try:
            check_mcap(path)
        except BadInput as e:
            unusable += 1
            fail("check_mcap", e)
            continue
        problems, line = check_file(path, args.require_metadata, args.require_sensors)
        if problems.first:
            failed += 1
            for item in problems.lines():
                print(f"FAIL {path}: {item}", file=sys.stderr)
        else:
            print(f"OK {path}: {line}")
    return EXIT_BAD_INPUT if unusable else 1 if failed else 0


if __name__ == "__main__":
    sys.exit(guard("check_mcap", main))
