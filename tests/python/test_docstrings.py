"""The module's docstrings, from which docs/reference/python.md is generated: every public name is in __all__ and
has one, in Google's style with the sections its kind needs (arguments named as the signature names them, Returns,
Raises where it raises, an example), and every Example runs as written: doctest, from the source tree, in a child
process of its own (with gymnasium's stand-in on the path where gymnasium is not installed)."""

import importlib.util
import inspect
import os
import pathlib
import re
import subprocess
import sys
import types

import pytest

import poet

SOURCE_DIR = pathlib.Path(__file__).resolve().parents[2]
STAND_IN = pathlib.Path(__file__).resolve().parent / "gymnasium_stand_in"
sys.path.insert(0, str(SOURCE_DIR / "tools" / "reference"))
import python_reference as reference  # noqa: E402  (tools/reference/python_reference.py)

# A Python function raises when it raises itself or passes its arguments to a checker or to the C++ core.
RAISING = re.compile(r"\braise\b|\b_whole\(|\b_number\(|\b_course\(|\b_path\(|\b_existing_file\(|\b_seconds\(|"
                     r"\b_command\(|_poet\.|self\._env\.|\b_until_running\(")


def public_callables():
    """(qualified name, object, kind): every callable of __all__ and each class's public methods and properties."""
    found = []
    for name in poet.__all__:
        obj = getattr(poet, name)
        if not callable(obj):
            continue
        found.append((name, obj, "class" if inspect.isclass(obj) else "function"))
        if inspect.isclass(obj):
            found += [(f"{name}.{member}", value, kind) for member, kind, value in reference.members(obj)]
    return found


def parameters(name, obj, kind):
    """The names of the parameters a docstring's Args must list (a class's: its constructor's)."""
    signature, _ = reference.signature_of(obj, method=kind == "method")
    if signature is None:
        return []
    inner = signature.strip()[1:].rsplit(")", 1)[0]
    return [p.split("=")[0].strip() for p in inner.split(",") if p.strip() and p.strip() not in ("*", "/")]


def source_raises(obj):
    if inspect.isclass(obj):
        obj = obj.__init__
    if not inspect.isfunction(obj):
        return True  # the bindings' arguments are checked: every one with arguments raises
    return bool(RAISING.search(inspect.getsource(obj)))


def test_every_public_name_is_in_all_and_every_constant_is_described():
    public = {n for n, v in vars(poet).items() if not n.startswith("_") and not isinstance(v, types.ModuleType)}
    assert public == set(poet.__all__), "a public name outside __all__, or a name of __all__ missing"
    described = {reference.item_name(n) for n, _ in reference.parse_docstring(poet.__doc__)["Attributes"]}
    constants = {n for n in poet.__all__ if not callable(getattr(poet, n))} | {"__version__"}
    assert described == constants, "the module docstring's Attributes: must describe every constant, and only them"
    assert reference.parse_docstring(poet.__doc__)["Example"]


@pytest.mark.parametrize("name, obj, kind", public_callables(), ids=lambda v: v if isinstance(v, str) else "")
def test_docstring_has_the_sections_its_kind_needs(name, obj, kind):
    doc = obj.__doc__ if kind == "property" else reference.signature_of(obj, method=kind == "method")[1]
    parsed = reference.parse_docstring(doc)
    assert parsed["summary"], f"{name}: no docstring"
    unknown = re.findall(r"^(\w+):\s*$", inspect.cleandoc(doc), re.MULTILINE)
    assert set(unknown) <= set(reference.SECTIONS), f"{name}: sections {unknown}, not Google's"
    if kind == "property":
        assert re.match(r"^[\w.]+( or [\w.]+)?: ", parsed["summary"]), f"{name}: a property's doc starts 'type: '"
        return
    wanted = parameters(name, obj, kind)
    given = [reference.item_name(n) for n, _ in parsed.get("Args", [])]
    assert given == wanted, f"{name}: Args: {given}, the signature's: {wanted}"
    assert all("(" in n for n, _ in parsed.get("Args", [])), f"{name}: every argument has its type"
    if kind in ("function", "method"):
        assert parsed.get("Returns"), f"{name}: no Returns:"
    if wanted and source_raises(obj):
        assert parsed.get("Raises"), f"{name}: raises, but has no Raises:"
    if kind in ("class", "function"):
        assert parsed.get("Example"), f"{name}: no Example:"


def examples():
    """(name, example lines) of every docstring with an Example, the module's included."""
    found = [("poet", reference.parse_docstring(poet.__doc__)["Example"])]
    for name, obj, kind in public_callables():
        doc = obj.__doc__ if kind == "property" else reference.signature_of(obj, method=kind == "method")[1]
        example = reference.parse_docstring(doc).get("Example")
        if example:
            found.append((name, example))
    return found


CHILD = r"""
import doctest, sys
import numpy as np, poet
test = doctest.DocTestParser().get_doctest(sys.stdin.read(), {"np": np, "poet": poet}, sys.argv[1], None, 0)
runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
runner.run(test)
sys.exit(1 if runner.failures else 0)
"""


@pytest.mark.parametrize("name, example", examples(), ids=lambda v: v if isinstance(v, str) else "")
def test_example_runs_as_written(name, example):
    env = dict(os.environ)
    if "gymnasium" in "\n".join(example) or "as_gymnasium" in name:
        if importlib.util.find_spec("gymnasium") is None:
            env["PYTHONPATH"] = os.pathsep.join([str(STAND_IN), env.get("PYTHONPATH", "")])
    done = subprocess.run([sys.executable, "-c", CHILD, name], input="\n".join(example) + "\n", text=True,
                          capture_output=True, cwd=SOURCE_DIR, env=env, timeout=240)
    assert done.returncode == 0, f"{name}'s example:\n{done.stdout}{done.stderr}"
