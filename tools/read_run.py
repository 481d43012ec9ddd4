#!/usr/bin/env python3
"""Read a bridgetwin run (an MCAP file) into numpy arrays.

    from read_run import load_topic, load_run
    accel = load_topic("run.mcap", "/sensors/accel/A3")
    plt.plot(accel["time_s"], accel["acceleration_m_s2"])

    sensors = load_run("run.mcap")          # every /sensors/... topic, one pass
    python3 tools/read_run.py run.mcap      # summary of a run
    python3 tools/read_run.py run.mcap /truth/axle_loads   # arrays of one topic

The command exits 0 for a whole file; 3 for a damaged one (a killed run's `.partial`, a
truncated copy: the intact part is read and printed, the damage said on stderr); 1 when
the topic is not in the file or has no message, or (summary) the file has no `/sensors/`
topic; 2, with one line on stderr naming the file, when there is nothing to read: no such
file, empty, not an MCAP file, or damaged or truncated before its first intact message
(`tools/bad_input.py`); 4 when the tool itself failed.

Messages are decoded with the schema stored in the file itself (the official `mcap` and
`mcap-protobuf-support` packages), so no generated code is needed and new fields simply
appear as new arrays. What a topic gives, as a dict of numpy arrays:

- ``log_time_ns``: Unix-epoch ns (int64), the true time; ``time_s``: seconds since the
  first message of the file; ``timestamp_ns``: the message's own stamp, equal to the log
  time except on the measured topics of sensors on a DAQ node with a clock model, where it
  is the node's clock (offset, drift, resync). Use it as a real installation's user would.
- every singular field by its name (units are part of the names); a Timestamp field
  such as ``entry_time`` becomes ``entry_time_ns``; a map field becomes ``name.key``.
- repeated numbers: a 2-D array (message x index) when all messages have the same length
  (``/truth/bridge`` ``deflection_m``), else a 1-D object array of arrays.
- repeated messages (the ``axles`` of ``/truth/axle_loads``): one row per element under
  ``axles.<field>``, with its own ``axles.time_s`` and ``axles.log_time_ns``.
- block messages (a ``sample_period_ns`` field, e.g. SampleBlock) are expanded to one row
  per sample, named like the per-sample messages (``acceleration_m_s2`` ...): the block
  and the per-sample layout of a sensor load to the same arrays.
"""

from __future__ import annotations

import sys
from collections import defaultdict
from pathlib import Path
from typing import Any, Iterable

import numpy as np
from google.protobuf.descriptor import FieldDescriptor
from mcap.reader import make_reader
from mcap.records import Channel, Footer, Message, Schema
from mcap.stream_reader import StreamReader
from mcap_protobuf.decoder import DecoderFactory

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bad_input import BadInput, check_mcap, fail, guard, is_cut  # noqa: E402

# SampleBlock.quantity -> name of the same column in the per-sample messages.
BLOCK_VALUE_NAMES = {
    "acceleration": "acceleration_m_s2",
    "strain": "strain_microstrain",
    "displacement": "displacement_m",
    "rotation": "rotation_rad",
    "reaction": "reaction_n",
    "temperature": "temperature_c",
}
SENSOR_PREFIXES = ("/sensors/",)


def load_topic(path: str, topic: str, damage: Damage | None = None) -> dict[str, np.ndarray]:
    """All messages of one topic as a dict of numpy arrays (see the module doc)."""
    return load_topics(path, [topic], damage)[topic]


def load_run(
    path: str, prefixes: Iterable[str] = SENSOR_PREFIXES, damage: Damage | None = None
) -> dict[str, dict[str, np.ndarray]]:
    """Every topic starting with one of ``prefixes`` (default: DAQ sensors), in one pass."""
    prefixes = tuple(prefixes)
    topics = [t for t in list_topics(path, damage) if t.startswith(prefixes)]
    return load_topics(path, topics, damage)


def _summary_or_none(path: str):
    """The summary section, or None when the file has none (a run killed mid-write)."""
    with open(path, "rb") as f:
        try:
            return make_reader(f).get_summary()
        except Exception:  # noqa: BLE001 - any damage in the footer means "no summary"
            return None


class Damage:
    """What a reader found wrong with a file: empty while the file is whole.

    Pass one to the readers below to learn where the intact part of a damaged file ends
    (a `.partial` file of a killed run, a truncated copy, flipped bytes)."""

    def __init__(self) -> None:
        self.problems: list[str] = []

    def add(self, text: str) -> None:
        # A file without summary is scanned twice (topics, then data): one note.
        if text not in self.problems:
            self.problems.append(text)

    def __bool__(self) -> bool:
        return bool(self.problems)


def iter_intact_messages(path: str, topics: Iterable[str] | None = None, damage: Damage | None = None):
    """(channel, message, decoded) of every message before the first damaged record.

    For a `.partial` file of a killed run: its data up to the last periodic flush. Where
    the intact part ends is added to `damage` (printed on stderr without one): a record that
    does not parse or fails its CRC, or a file that ends without its footer."""
    wanted = None if topics is None else set(topics)
    schemas: dict[int, Schema] = {}
    channels: dict[int, Channel] = {}
    decoders: dict[int, Any] = {}
    factory = DecoderFactory()
    count = 0
    finished = False
    problem = None
    with open(path, "rb") as f:
        try:
            for record in StreamReader(f, validate_crcs=True).records:
                if isinstance(record, Footer):
                    finished = True
                elif isinstance(record, Schema):
                    schemas[record.id] = record
                elif isinstance(record, Channel):
                    channels[record.id] = record
                elif isinstance(record, Message):
                    # Counted on every topic: the note on the damage is the same whichever
                    # topics a pass reads.
                    count += 1
                    channel = channels[record.channel_id]
                    if wanted is not None and channel.topic not in wanted:
                        continue
                    if record.channel_id not in decoders:
                        schema = schemas.get(channel.schema_id)
                        decoders[record.channel_id] = factory.decoder_for(channel.message_encoding, schema)
                    yield channel, record, decoders[record.channel_id](record.data)
        except Exception as e:  # noqa: BLE001 - the damaged tail of an interrupted file
            detail = str(e) or "the data ends in the middle of a record"  # mcap's EndOfFile says nothing
            problem = f"intact up to message {count}; then {type(e).__name__}: {detail}"
    if problem is None and not finished:
        problem = f"intact up to message {count}; then the file ends without its footer"
    if problem is not None:
        if damage is None:
            print(f"{path}: {problem}", file=sys.stderr)
        else:
            damage.add(problem)


def list_topics(path: str, damage: Damage | None = None) -> list[str]:
    """Topic names of the file, sorted (a file without summary is scanned; what is
    damaged goes to `damage`)."""
    summary = _summary_or_none(path)
    if summary is None:
        return sorted({c.topic for c, _, _ in iter_intact_messages(path, damage=damage)})
    return sorted({c.topic for c in summary.channels.values()})


def load_topics(path: str, topics: list[str], damage: Damage | None = None) -> dict[str, dict[str, np.ndarray]]:
    """Several topics in one pass over the file: {topic: arrays}. A file without summary
    section is read up to its first damaged record, which is added to `damage`; a
    damaged record in an indexed file raises."""
    rows: dict[str, list[dict]] = {t: [] for t in topics}
    # Rows of repeated message fields: {topic: {field name: rows}}.
    nested: dict[str, dict[str, list[dict]]] = {t: defaultdict(list) for t in topics}
    summary = _summary_or_none(path)
    start_ns = summary.statistics.message_start_time if summary and summary.statistics else None
    if summary is None:
        messages = iter_intact_messages(path, topics, damage)
    else:
        known = {c.topic for c in summary.channels.values()}
        missing = sorted(set(topics) - known)
        if missing:
            raise ValueError(f"{path}: no topic {missing}; topics: {sorted(known)}")
        messages = _iter_indexed(path, topics)
    for channel, message, decoded in messages:
        _add_message(rows[channel.topic], nested[channel.topic], decoded, message.log_time)
    first = [r[0]["log_time_ns"] for r in rows.values() if r]
    if start_ns is None:
        start_ns = min(first, default=0)
    return {t: _to_arrays(rows[t], nested[t], start_ns) for t in topics}


def _iter_indexed(path: str, topics: list[str]):
    with open(path, "rb") as f:
        reader = make_reader(f, validate_crcs=True, decoder_factories=[DecoderFactory()])
        for _, channel, message, decoded in reader.iter_decoded_messages(topics=topics):
            yield channel, message, decoded


def _add_message(rows: list[dict], nested: dict[str, list[dict]], msg: Any, log_time_ns: int) -> None:
    fields = msg.DESCRIPTOR.fields_by_name
    if "sample_period_ns" in fields:
        _add_block(rows, msg, log_time_ns)
        return
    row: dict[str, Any] = {"log_time_ns": log_time_ns}
    for field in msg.DESCRIPTOR.fields:
        if _is_unset_timestamp(msg, field):
            continue  # an unset time (a missed detection's) reads as NaN, not as 1970
        value = getattr(msg, field.name)
        if _is_map(field):
            row.update({f"{field.name}.{k}": v for k, v in value.items()})
        elif field.is_repeated and field.cpp_type == FieldDescriptor.CPPTYPE_MESSAGE:
            for element in value:
                element_row = {"log_time_ns": log_time_ns}
                _add_singular_fields(element_row, element, prefix="")
                nested[field.name].append(element_row)
        elif field.is_repeated:
            row[field.name] = np.asarray(list(value))
        else:
            _add_singular(row, field, value, prefix="")
    rows.append(row)


def _add_singular_fields(row: dict, msg: Any, prefix: str) -> None:
    for field in msg.DESCRIPTOR.fields:
        if _is_unset_timestamp(msg, field):
            continue  # an unset time (a missed detection's) reads as NaN, not as 1970
        value = getattr(msg, field.name)
        if field.is_repeated:
            row[prefix + field.name] = np.asarray(list(value)) if not _is_map(field) else dict(value)
        else:
            _add_singular(row, field, value, prefix)


def _add_singular(row: dict, field: FieldDescriptor, value: Any, prefix: str) -> None:
    if field.cpp_type != FieldDescriptor.CPPTYPE_MESSAGE:
        row[prefix + field.name] = value
    elif field.message_type.full_name == "google.protobuf.Timestamp":
        row[f"{prefix}{field.name}_ns"] = value.seconds * 1_000_000_000 + value.nanos
    else:
        _add_singular_fields(row, value, prefix=f"{prefix}{field.name}.")


def _add_block(rows: list[dict], msg: Any, log_time_ns: int) -> None:
    """One row per sample; sample i is at log_time + i * sample_period_ns."""
    period_ns = msg.sample_period_ns
    stamp_ns = msg.timestamp.seconds * 1_000_000_000 + msg.timestamp.nanos
    columns: dict[str, list] = {}
    for field in msg.DESCRIPTOR.fields:
        if field.is_repeated and field.cpp_type != FieldDescriptor.CPPTYPE_MESSAGE:
            name = field.name
            if name == "values":
                name = BLOCK_VALUE_NAMES.get(msg.quantity, msg.quantity or "values")
            columns[name] = list(getattr(msg, field.name))
    count = max((len(v) for v in columns.values()), default=0)
    for i in range(count):
        row = {"log_time_ns": log_time_ns + i * period_ns, "timestamp_ns": stamp_ns + i * period_ns}
        row.update({k: v[i] for k, v in columns.items() if i < len(v)})
        rows.append(row)


def _is_unset_timestamp(msg: Any, field: FieldDescriptor) -> bool:
    return (
        not field.is_repeated
        and field.cpp_type == FieldDescriptor.CPPTYPE_MESSAGE
        and field.message_type.full_name == "google.protobuf.Timestamp"
        and not msg.HasField(field.name)
    )


def _is_map(field: FieldDescriptor) -> bool:
    return (
        field.cpp_type == FieldDescriptor.CPPTYPE_MESSAGE
        and field.message_type.GetOptions().map_entry
    )


def _to_arrays(rows: list[dict], nested: dict[str, list[dict]], start_ns: int) -> dict[str, np.ndarray]:
    if not rows:
        return {"log_time_ns": np.zeros(0, dtype=np.int64), "time_s": np.zeros(0)}
    out = _columns(rows)
    for field_name, element_rows in nested.items():
        out.update(_columns(element_rows, prefix=field_name))
    for key in [k for k in out if k.endswith("log_time_ns")]:
        out[key[: -len("log_time_ns")] + "time_s"] = (out[key] - start_ns) * 1e-9
    return out


def _columns(rows: list[dict], prefix: str = "") -> dict[str, np.ndarray]:
    """Rows (dicts) -> columns; a key missing from some rows is filled with NaN."""
    keys: dict[str, None] = {}
    for row in rows:
        keys.update(dict.fromkeys(row))
    out = {}
    for key in keys:
        values = [row.get(key, np.nan) for row in rows]
        name = f"{prefix}.{key}" if prefix else key
        if values and isinstance(values[0], np.ndarray):
            lengths = {v.shape for v in values}
            out[name] = np.vstack(values) if len(lengths) == 1 else _object_array(values)
        elif values and isinstance(values[0], dict):
            out[name] = _object_array(values)
        else:
            out[name] = np.asarray(values)
    time_key = f"{prefix}.log_time_ns" if prefix else "log_time_ns"
    if time_key in out:
        out[time_key] = out[time_key].astype(np.int64)
    return out


def _object_array(values: list) -> np.ndarray:
    array = np.empty(len(values), dtype=object)
    array[:] = values
    return array


def _describe(name: str, array: np.ndarray) -> str:
    if array.dtype.kind in "fiub" and array.size:
        return f"  {name:32s} {str(array.shape):14s} min {array.min():.6g}  max {array.max():.6g}"
    return f"  {name:32s} {str(array.shape):14s} {array.dtype}"


def print_summary(path: str, damage: Damage | None = None) -> int:
    """Prints the header, metadata, attachments and per-topic counts of a run; returns
    the number of messages it found."""
    summary = _summary_or_none(path)
    if summary is None:
        counts: dict[str, int] = defaultdict(int)
        for channel, _, _ in iter_intact_messages(path, damage=damage):
            counts[channel.topic] += 1
        print(f"{path}: no summary section (interrupted run); intact messages per topic:")
        for topic, count in sorted(counts.items()):
            print(f"  {topic:36s} {count:8d}")
        return sum(counts.values())
    # The summary repeats what the writer counted: a linear pass with CRCs (nothing
    # decoded) finds flipped bytes or a cut in the data before it.
    for _ in iter_intact_messages(path, topics=[], damage=damage):
        pass
    with open(path, "rb") as f:
        reader = make_reader(f)
        print(f"{path}: written by {reader.get_header().library}")
        for record in reader.iter_metadata():
            print(f"metadata {record.name}: {', '.join(sorted(record.metadata))}")
        for attachment in reader.iter_attachments():
            print(f"attachment {attachment.name} ({attachment.media_type}, {len(attachment.data)} B)")
    if summary.statistics is None:
        print("no statistics record")
        if damage is not None:
            damage.add("the summary has no statistics record")
        return 0
    stats = summary.statistics
    duration_s = (stats.message_end_time - stats.message_start_time) * 1e-9
    print(f"{stats.message_count} messages, {duration_s:.3f} s")
    for channel_id, channel in sorted(summary.channels.items(), key=lambda c: c[1].topic):
        count = stats.channel_message_counts.get(channel_id, 0)
        schema = summary.schemas[channel.schema_id].name
        print(f"  {channel.topic:36s} {schema:32s} {count:8d}")
    return stats.message_count


# Exit status of the command line: 1 when the file has nothing asked for (the topic has no
# message or is not in the file, no sensor topic), 3 when the file is damaged and its
# intact part was read and printed; 2 (bad_input.EXIT_BAD_INPUT) when there is nothing to
# read.
EXIT_UNREADABLE = 1
EXIT_DAMAGED = 3


def main(argv: list[str]) -> int:
    if len(argv) not in (2, 3):
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    path = argv[1]
    try:
        # A cut file is what this command reads the intact part of: only a file that is
        # no MCAP file at all stops it here.
        check_mcap(path, cut_ok=True)
    except BadInput as e:
        return fail("read_run", e)
    damage = Damage()
    try:
        if len(argv) == 2:
            count = print_summary(path, damage)
            if count and not any(t.startswith(SENSOR_PREFIXES) for t in list_topics(path, damage)):
                print(f"{path}: no topic under {', '.join(SENSOR_PREFIXES)}: nothing was measured", file=sys.stderr)
                return EXIT_UNREADABLE
        else:
            arrays = load_topic(path, argv[2], damage)
            count = len(arrays.get("time_s", []))
            print(f"{argv[2]}: {count} rows")
            for name, array in arrays.items():
                print(_describe(name, array))
    except ValueError as e:  # load_topics: a topic the file does not have
        print(f"{path}: {e}" if not str(e).startswith(path) else str(e), file=sys.stderr)
        return EXIT_UNREADABLE
    except BrokenPipeError:
        raise
    except Exception as e:  # noqa: BLE001 - any reader or decoder error ends the command
        return fail("read_run", f"{path}: damaged: {type(e).__name__}: {e}")
    if count == 0 and damage:
        if is_cut(path):
            return fail("read_run", f"{path}: truncated before its first intact message ({damage.problems[0]})")
        return fail("read_run", f"{path}: damaged before its first intact message ({damage.problems[0]})")
    if count == 0:
        print(f"{path}: no message could be read", file=sys.stderr)
        return EXIT_UNREADABLE
    if damage:
        print(f"{path}: damaged, read what is intact: {'; '.join(damage.problems)}", file=sys.stderr)
        return EXIT_DAMAGED
    return 0


if __name__ == "__main__":
    sys.exit(guard("read_run", main, sys.argv))
