"""The type stub says what the extension has: the same functions with the same parameters
(names, order, defaults), the same exception classes; and every public name of the
package is documented."""

from __future__ import annotations

import ast
import inspect
from pathlib import Path

import bridgetwin
from bridgetwin import _native

STUB = Path(bridgetwin.__file__).with_name("_native.pyi")


def stub_functions() -> dict[str, list[tuple[str, str | None]]]:
    tree = ast.parse(STUB.read_text())
    out = {}
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            args = node.args.args
            defaults = [None] * (len(args) - len(node.args.defaults)) + [
                ast.unparse(d) for d in node.args.defaults
            ]
            out[node.name] = [(a.arg, d) for a, d in zip(args, defaults)]
    return out


def stub_classes() -> set[str]:
    return {n.name for n in ast.parse(STUB.read_text()).body if isinstance(n, ast.ClassDef)}


def runtime_functions() -> dict[str, list[tuple[str, str | None]]]:
    out = {}
    for name, obj in vars(_native).items():
        if callable(obj) and not isinstance(obj, type) and not name.startswith("__"):
            params = inspect.signature(obj).parameters.values()
            out[name] = [
                (p.name, None if p.default is inspect.Parameter.empty else repr(p.default)) for p in params
                if p.name != "py"
            ]
    return out


def test_stub_functions_match_the_extension():
    stub, runtime = stub_functions(), runtime_functions()
    assert set(stub) == set(runtime), set(stub) ^ set(runtime)
    for name in stub:
        assert stub[name] == runtime[name], (name, stub[name], runtime[name])


def test_stub_classes_match_the_extension():
    runtime = {n for n, o in vars(_native).items() if isinstance(o, type)}
    assert stub_classes() == runtime


def test_every_public_name_is_documented():
    for name in bridgetwin.__all__:
        obj = getattr(bridgetwin, name)
        if name == "__version__":
            continue
        assert inspect.getdoc(obj), name
    for name in ("overview", "representative_sensors", "envelope", "welch_psd"):
        assert inspect.getdoc(getattr(bridgetwin.plot, name)), name
