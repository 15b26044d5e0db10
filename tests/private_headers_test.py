#!/usr/bin/env python3
"""Core's private headers are refused by the compiler outside core.

Every header beside core's sources (core/<room>/<name>.h) has a probe source
that includes it (tests/CMakeLists.txt, target core_private_header_probe,
compiled with a layer's flags: runtime's). Each probe is compiled with its
command from the build's compile_commands.json and must fail on the
header's guard ("private to dynapath_core"). The smallest header's probe is
compiled once more with -DDYNAPATH_CORE_PRIVATE (what core and the tests of
its insides have) and must pass, so that the refusal is the guard's and not
a missing include path.

Usage: private_headers_test.py SOURCE_DIR BUILD_DIR
"""

import json
import os
import shlex
import subprocess
import sys
import tempfile

GUARD_TEXT = "private to dynapath_core"


def private_headers(source):
    core = os.path.join(source, "core")
    headers = []
    for folder, dirs, files in os.walk(core):
        if os.path.relpath(folder, core).split(os.sep)[0] == "include":
            continue
        headers += [os.path.relpath(os.path.join(folder, name), source)
                    for name in files if name.endswith(".h")]
    return sorted(headers)


def probe_commands(build):
    """The compile command of each probe, by the header it includes."""
    with open(os.path.join(build, "compile_commands.json"), encoding="utf-8") as f:
        entries = json.load(f)
    commands = {}
    for entry in entries:
        path = entry["file"]
        if os.sep + "private_header_probes" + os.sep not in path:
            continue
        with open(path, encoding="utf-8") as f:
            line = f.read().strip()
        header = line.removeprefix('#include "').removesuffix('"')
        args = entry["arguments"] if "arguments" in entry else shlex.split(entry["command"])
        commands[header] = (entry["directory"], args)
    return commands


def compile_probe(directory, args, output, extra):
    """Runs a probe's command, its object going to `output`; (status, text)."""
    args = list(args)
    if "-o" in args:
        args[args.index("-o") + 1] = output
    args += extra
    done = subprocess.run(args, cwd=directory, capture_output=True, text=True, timeout=300)
    return done.returncode, done.stdout + done.stderr


def main():
    if len(sys.argv) != 3:
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    source, build = sys.argv[1], sys.argv[2]
    headers = private_headers(source)
    commands = probe_commands(build)
    failures = []
    if not headers:
        failures.append(f"no private header found under {source}/core")
    with tempfile.TemporaryDirectory() as work:
        output = os.path.join(work, "probe.o")
        for header in headers:
            if header not in commands:
                failures.append(f"{header}: no probe in {build}/compile_commands.json "
                                "(reconfigure the build)")
                continue
            directory, args = commands[header]
            status, text = compile_probe(directory, args, output, ["-Wfatal-errors"])
            if status == 0:
                failures.append(f"{header}: a layer's compile accepted it (its guard, "
                                "#ifndef DYNAPATH_CORE_PRIVATE ... #error, is missing)")
            elif GUARD_TEXT not in text:
                failures.append(f"{header}: refused, but not by its guard:\n{text[-2000:]}")
        # The control: the smallest header with core's definition compiles.
        present = [h for h in headers if h in commands]
        if present:
            header = min(present, key=lambda h: os.path.getsize(os.path.join(source, h)))
            directory, args = commands[header]
            status, text = compile_probe(directory, args, output,
                                         ["-DDYNAPATH_CORE_PRIVATE", "-fsyntax-only"])
            if status != 0:
                failures.append(f"{header} with -DDYNAPATH_CORE_PRIVATE did not compile, so "
                                f"the refusals above prove nothing:\n{text[-2000:]}")
    for failure in failures:
        print("FAIL:", failure)
    if failures:
        return 1
    print(f"core_private_headers: all {len(headers)} private headers refused outside core")
    return 0


if __name__ == "__main__":
    sys.exit(main())
