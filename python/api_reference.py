#!/usr/bin/env python3
"""Writes docs/reference/PYTHON_API.md from the dynapath package's docstrings.

Every name of ``dynapath.__all__`` in order: its signature (inspect) and
docstring; for a class, its public methods and properties too. Only the
standard library (inspect) and the package itself; run with the module
built:

    PYTHONPATH=build/python python3 python/api_reference.py --write docs/reference/PYTHON_API.md
    PYTHONPATH=build/python python3 python/api_reference.py --check docs/reference/PYTHON_API.md

--check exits 1 (with a diff) when the file differs from what the
docstrings give, 0 when it is current; bad usage exits 2.
"""

import argparse
import difflib
import inspect
import os
import sys

HEADER = """# Python API reference

Made from the docstrings of the package `dynapath` by
`python/api_reference.py` (the test `python_module` fails when this file is
not current); regenerate it with
`PYTHONPATH=build/python python3 python/api_reference.py --write docs/reference/PYTHON_API.md`.
How to use it: [docs/howto/PYTHON.md](../howto/PYTHON.md).
"""


def signature(obj, name):
    try:
        return f"{name}{inspect.signature(obj)}"
    except (TypeError, ValueError):
        return name


def docstring(obj):
    return inspect.cleandoc(getattr(obj, "__doc__", None) or "(no docstring)")


def fenced(text):
    return "```text\n" + text + "\n```\n"


def members(cls):
    """Public methods and properties, the class's own first, then its bases'
    (the C++ extension's base classes included), each name once."""
    found, seen = [], set()
    for owner in cls.__mro__:
        if owner is object or owner.__name__ == "pybind11_object":
            continue
        for name, member in owner.__dict__.items():
            if name in seen or (name.startswith("_") and name != "__init__"):
                continue
            seen.add(name)
            if name == "__init__" and not (inspect.isfunction(member) and member.__doc__):
                continue
            if isinstance(member, (staticmethod, classmethod)):
                found.append((name, getattr(cls, name), "method"))
            elif isinstance(member, property):
                found.append((name, member, "property"))
            elif inspect.isroutine(member):
                found.append((name, member, "method"))
            elif type(member).__name__ == "pybind11_static_property" or hasattr(member, "fget"):
                found.append((name, member, "property"))
    return found


def reference(package):
    parts = [HEADER, "\n## Module `" + package.__name__ + "`\n\n", fenced(docstring(package))]
    constants = []
    for name in package.__all__:
        obj = getattr(package, name)
        if inspect.isclass(obj):
            parts.append(f"\n## class `dynapath.{name}`\n\n")
            parts.append(f"`{signature(obj, name)}`\n\n" if "__init__" in obj.__dict__ else "")
            parts.append(fenced(docstring(obj)))
            for member_name, member, kind in members(obj):
                title = (f"{name}.{member_name}" if kind == "property"
                         else signature(member, f"{name}.{member_name}"))
                parts.append(f"\n### `{title}`{' (property)' if kind == 'property' else ''}\n\n")
                parts.append(fenced(docstring(member)))
        elif callable(obj):
            parts.append(f"\n## `dynapath.{signature(obj, name)}`\n\n")
            parts.append(fenced(docstring(obj)))
        else:
            constants.append(f"| `{name}` | `{obj!r}` |\n")
    if constants:
        parts.append("\n## Constants\n\n| name | value |\n| --- | --- |\n")
        parts.extend(constants)
    return "".join(parts)


def main(argv):
    parser = argparse.ArgumentParser(description="Write or check the Python API reference.")
    mode = parser.add_mutually_exclusive_group(required=True)
    mode.add_argument("--write", metavar="FILE", help="write the reference to FILE")
    mode.add_argument("--check", metavar="FILE", help="exit 1 when FILE is not current")
    args = parser.parse_args(argv)
    # The built package (PYTHONPATH), not the sources beside this script.
    here = os.path.dirname(os.path.abspath(__file__))
    sys.path[:] = [p for p in sys.path if os.path.abspath(p or ".") != here]
    import dynapath

    text = reference(dynapath)
    if args.write:
        with open(args.write, "w", encoding="utf-8") as file:
            file.write(text)
        return 0
    try:
        with open(args.check, encoding="utf-8") as file:
            current = file.read()
    except OSError as error:
        print(f"api_reference.py: {args.check}: {error.strerror}", file=sys.stderr)
        return 2
    if current == text:
        return 0
    sys.stdout.writelines(difflib.unified_diff(current.splitlines(True), text.splitlines(True),
                                               args.check, "from the docstrings"))
    print(f"{args.check} is not current: run python/api_reference.py --write {args.check}",
          file=sys.stderr)
    return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
