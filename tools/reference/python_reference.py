#!/usr/bin/python3
"""docs/reference/python.md from the module's own docstrings: every public name of poet (its __all__), each
class's public methods and properties, with signature, arguments, returns, raised errors and example.

The docstrings are in Google's style (Args:, Returns:, Raises:, Attributes:, Example:), in Python and in the
bindings (python/module.cpp); parse_docstring is shared with tests/python/test_docstrings.py, which checks that
every name has the sections its kind needs and runs every example. Debian's python3, stdlib and the built module.

Usage (from the source tree): PYTHONPATH=build/python /usr/bin/python3 tools/reference/python_reference.py
                                  [--out docs/reference/python.md]
"""

import argparse
import inspect
import os
import re
import sys
import tempfile

SECTIONS = ("Args", "Attributes", "Returns", "Raises", "Example")
_SECTION = re.compile(r"^(%s):\s*$" % "|".join(SECTIONS))
_ITEM = re.compile(r"^(\S[^:]*?):\s+(.*)$")  # "name (type): text" or "ValueError: text"
REGENERATE = ("PYTHONPATH=build/python /usr/bin/python3 tools/reference/python_reference.py "
              "--out docs/reference/python.md")


def parse_docstring(doc):
    """A docstring as {"summary": str, "description": [paragraphs], section: text or [(name, text)]}.

    Args, Attributes and Raises become lists of (name, text) (a name with its type in parentheses); Returns is
    its text; Example its lines, dedented, as doctest reads them."""
    lines = inspect.cleandoc(doc or "").splitlines()
    parsed = {"summary": "", "description": []}
    section, body = None, []

    def flush():
        if section is not None:
            parsed[section] = _section_value(section, body)

    prose = []
    for line in lines:
        match = _SECTION.match(line)
        if match:
            flush()
            section, body = match.group(1), []
        elif section is None:
            prose.append(line)
        else:
            body.append(line)
    flush()
    paragraphs = [" ".join(p.split()) for p in "\n".join(prose).split("\n\n") if p.strip()]
    if paragraphs:
        parsed["summary"], parsed["description"] = paragraphs[0], paragraphs[1:]
    return parsed


def _section_value(section, body):
    body = inspect.cleandoc("\n".join(body)).splitlines() if any(line.strip() for line in body) else []
    if section == "Example":
        return body
    if section == "Returns":
        return " ".join(" ".join(body).split())
    items = []
    for line in body:
        match = _ITEM.match(line) if not line.startswith(" ") else None
        if match:
            items.append([match.group(1), match.group(2)])
        elif items:
            items[-1][1] += " " + line.strip()
    return [(name, " ".join(text.split())) for name, text in items]


def item_name(name):
    """"seed (int, optional)" -> "seed"."""
    return name.split(" (")[0]


def _pybind_signature(doc):
    """The parameters of a pybind11 function from its docstring's first line, "name(a: T, b: U = d) -> R", without
    self and types, and the docstring without that line."""
    first, _, rest = (doc or "").partition("\n")
    match = re.match(r"^\w+\((.*)\)(?: -> .*)?$", first)
    if not match:
        return None, doc
    params, depth, current = [], 0, ""
    for ch in match.group(1) + ",":
        if ch == "," and depth == 0:
            if current.strip():
                params.append(current.strip())
            current = ""
            continue
        depth += ch in "[(" and 1 or (ch in "])" and -1 or 0)
        current += ch
    shown = []
    for param in params:
        name, _, default = param.partition(" = ")
        name = name.split(":")[0].strip()
        if name != "self":
            shown.append(f"{name}={default.strip()}" if default else name)
    return "(" + ", ".join(shown) + ")", rest


def signature_of(obj, method=False):
    """(signature text or None, docstring) of a Python or pybind11 callable; a method's without self."""
    doc = inspect.getdoc(obj) or ""
    try:
        signature = inspect.signature(obj)
    except (TypeError, ValueError):
        return _pybind_signature(doc) if callable(obj) and not inspect.isclass(obj) else (None, doc)
    params = list(signature.parameters.values())
    if method and params and params[0].name == "self":
        signature = signature.replace(parameters=params[1:])
    return str(signature), doc


def members(cls):
    """A class's public methods and properties, (name, kind, object), its own and its package bases', in order."""
    found, seen = [], set()
    for klass in cls.__mro__:
        if not klass.__module__.startswith("poet"):
            continue
        for name, value in vars(klass).items():
            if name.startswith("_") or name in seen:
                continue
            if isinstance(value, property):
                found.append((name, "property", value))
            elif isinstance(value, staticmethod):
                found.append((name, "method", getattr(cls, name)))
            elif callable(value):
                found.append((name, "method", value))
            else:
                continue
            seen.add(name)
    return [m for m in found if m[1] == "method"] + [m for m in found if m[1] == "property"]


def public_names(module):
    """The names of __all__, in its order."""
    return list(module.__all__)


def _items(title, items):
    out = [f"**{title}**", ""]
    for name, text in items:
        base, _, kind = name.partition(" (")
        shown = f"`{base}` ({kind}" if kind else f"`{base}`"
        out.append(f"- {shown}: {text}")
    return out + [""]


def render_doc(parsed):
    out = [parsed["summary"], ""]
    for paragraph in parsed["description"]:
        out += [paragraph, ""]
    if parsed.get("Args"):
        out += _items("Arguments", parsed["Args"])
    if parsed.get("Returns"):
        out += ["**Returns**", "", _typed(parsed["Returns"]), ""]
    if parsed.get("Raises"):
        out += _items("Raises", parsed["Raises"])
    if parsed.get("Attributes"):
        out += _items("Attributes", parsed["Attributes"])
    if parsed.get("Example"):
        out += ["**Example**", "", "```pycon", *parsed["Example"], "```", ""]
    return out


def _typed(text):
    """"type: text" (a Returns: section, a property's doc) as "*type*: text"."""
    match = re.match(r"^([\w.]+(?: or [\w.]+| of [\w.]+)*): (.*)$", text, re.DOTALL)
    return f"*{match.group(1)}*: {match.group(2)}" if match else text


def render(module):
    """The page's markdown."""
    parsed_module = parse_docstring(module.__doc__)
    out = ["# Python API", "",
           "<!-- Generated by tools/reference/python_reference.py from the module's docstrings; do not edit. -->",
           "", "The module `poet`: every public name, generated from its docstrings "
           f"(`{REGENERATE}`). The examples assume `import numpy as np, poet` and the source tree as the working "
           "directory; the tests run every one of them. How to use the module: [Python](../python.md); the "
           "environment's observations, actions and rewards: [the environment](environment.md).", ""]
    out += ["## Constants", "", "| name | value | meaning |", "|---|---|---|"]
    for name, text in parsed_module.get("Attributes", []):
        base = item_name(name)
        value = getattr(module, base)
        if base == "__version__":  # its one home is CMakeLists.txt: the page would go stale at every release
            shown = "the version"
        elif len(repr(value)) <= 40:
            shown = f"`{value!r}`"
        else:
            shown = f"{len(value)} names, `{value[0]!r}` to `{value[-1]!r}`"
        out.append(f"| `poet.{base}` | {shown} | {text} |")
    out += ["", "```pycon", *parsed_module.get("Example", []), "```", ""]
    for name in public_names(module):
        obj = getattr(module, name)
        if not callable(obj):
            continue
        signature, doc = signature_of(obj)
        kind = "class " if inspect.isclass(obj) else ""
        out += [f"## poet.{name}", "", "```python", f"{kind}poet.{name}{signature or ''}", "```", ""]
        out += render_doc(parse_docstring(doc))
        if not inspect.isclass(obj):
            continue
        for member, member_kind, value in members(obj):
            if member_kind == "property":
                summary = parse_docstring(value.__doc__)["summary"]
                out += [f"### {name}.{member}", "", f"Property. {_typed(summary)}", ""]
                continue
            signature, doc = signature_of(value, method=True)
            prefix = "static " if isinstance(inspect.getattr_static(obj, member), staticmethod) else ""
            out += [f"### {name}.{member}", "", "```python", f"{prefix}{name}.{member}{signature or '()'}", "```", ""]
            out += render_doc(parse_docstring(doc))
    while out and out[-1] == "":
        out.pop()
    return "\n".join(out) + "\n"


def write_page(page, out):
    """Writes the page to `out` atomically (a reader never sees half a page), or to standard output when out is
    None; also environment_card.py's."""
    if out is None:
        sys.stdout.write(page)
        return
    directory = os.path.dirname(os.path.abspath(out))
    with tempfile.NamedTemporaryFile("w", encoding="utf-8", dir=directory, delete=False) as f:
        f.write(page)
    os.chmod(f.name, 0o644)  # a page of the checkout, not a secret (NamedTemporaryFile makes it 0600)
    os.replace(f.name, out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", help="the page to write (default: standard output)")
    args = parser.parse_args()
    import poet

    write_page(render(poet), args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
