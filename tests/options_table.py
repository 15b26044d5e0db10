#!/usr/bin/env python3
"""The CLI reference and the options' declarations: for every command-line
option, the one place it is declared; for every command, its --help.

Declarations are found in the sources (OptionGroup::Option/List/Flag and
CLI11's add_option/add_flag/set_config with a "--name"), the commands' options
in their --help. Fails when
  * an option is declared in more places than it has meanings (HOMONYMS below
    lists the names that mean different things to different commands),
  * a command shows an option no declaration names (declared some other way),
  * with --check FILE: FILE (docs/reference/CLI.md, made from every command's
    --help) is not current.
With --write FILE, FILE is written instead.

Usage: options_table.py SOURCE_DIR BUILD_DIR [--check FILE | --write FILE]
"""
import os
import re
import subprocess
import sys

# Names that are different options for different commands, each declared
# once per meaning: (number of meanings, why).
HOMONYMS = {
    "--out": (5, "run's result directory; experiment's study directory; render's picture directory; "
                 "compare's CSV file; train-model's model file"),
    "--seed": (2, "the maze's seed (maze, run, experiment, the processes); train-model's training seed"),
    "--threads": (2, "worker threads of a run, a study or a process; train-model's threads sharing "
                     "out a round's mazes"),
    "--approach": (2, "run's list of approaches to run; the one approach render and view show"),
    "--run-id": (2, "the run a process belongs to; the run render and view show"),
    "--agents": (3, "how many agent processes to run (run, experiment); how many the coordinator waits for; "
                    "train-model's agent processes hosting the learners of a federated training"),
    "--embedded": (2, "a run's processes or a service's agents as threads over memq:// (run, experiment, "
                      "serve); train-model's agents hosting the learners of a federated training as threads"),
    "--learners": (2, "FedAsynQ's learners per training job (run, experiment, the processes); "
                      "train-model's learners of a federated training of convQ's model"),
    "--config": (2, "a CLI11 config file (run, the processes); experiment's TOML study file, read by toml++"),
    "--delay": (2, "render's GIF frame delay; dynapath-lan-delay's packet hold time"),
    "--rate": (2, "query's requests per second; feed's time steps per second"),
    "--timeout": (2, "view's wait for a run; query and feed's wait for the service"),
    "--resolution": (2, "the frame of a map without one (serve, query, feed, robots; default 1 m); "
                        "web's frame to draw obstacle points with before the service's goal replies give it"),
    "--origin": (2, "the origin of a map without a frame (serve, query, feed, robots; default 0,0); "
                    "web's, with its --resolution"),
    "--force": (3, "experiment's: delete the study in DIR and start over; run's: start a new run "
                   "in a --checkpoint DIR holding an unfinished run's checkpoint; dynapath-recorder's: "
                   "overwrite its --file"),
}

# The commands: how to run each one's --help, relative to the build directory.
COMMANDS = [
    ("dynapath maze", ["tools/dynapath", "maze"]),
    ("dynapath run", ["tools/dynapath", "run"]),
    ("dynapath experiment", ["tools/dynapath", "experiment"]),
    ("dynapath secret", ["tools/dynapath", "secret"]),
    ("dynapath params", ["tools/dynapath", "params"]),
    ("dynapath compare", ["tools/dynapath", "compare"]),
    ("dynapath train-model", ["tools/dynapath", "train-model"]),
    ("dynapath netns", ["tools/dynapath", "netns"]),
    ("dynapath serve", ["tools/dynapath", "serve"]),
    ("dynapath query", ["tools/dynapath", "query"]),
    ("dynapath feed", ["tools/dynapath", "feed"]),
    ("dynapath robots", ["tools/dynapath", "robots"]),
    ("dynapath render", ["tools/dynapath-render"]),
    ("dynapath view", ["tools/dynapath-view"]),
    ("dynapath web", ["tools/dynapath-web"]),
    ("dynapath log-to-mcap", ["tools/dynapath-log-to-mcap"]),
    ("dynapath-envsim", ["envsim/dynapath-envsim"]),
    ("dynapath-coordinator", ["coordinator/dynapath-coordinator"]),
    ("dynapath-agent", ["agent/dynapath-agent"]),
    ("dynapath-recorder", ["recorder/dynapath-recorder"]),
    # Built only with libnetfilter-queue (tools/CMakeLists.txt).
    ("dynapath-lan-delay", ["tools/dynapath-lan-delay"]),
]

# Commands in the reference whose options are not C++ declarations (a Python
# and a shell program): their --help is shown, not checked against sources.
REFERENCE_ONLY = [
    ("dynapath plot", ["tools/dynapath-plot"]),
    ("dynapath-spy", ["tools/dynapath-spy"]),
]

DECLARATION = re.compile(
    r'(?:\b(?:Option|List|Flag)|\badd_option|\badd_flag|\bset_config)\(\s*"(--[a-z0-9-]+)"')
FUNCTION = re.compile(r"^[A-Za-z][\w:<>,&* ]*?\b([A-Za-z_]\w*)\(")
HELP_OPTION = re.compile(r"^\s+(?:-\w,)?(--[a-z][a-z0-9-]*)")
HEADER = """# Command-line reference

<!-- generated by tests/options_table.py from the commands' --help; do not edit.
     ctest options_table fails when it is not current; regenerate with
     tests/options_table.py . build --write docs/reference/CLI.md -->

Every command's `--help`, as built. `dynapath <command>` runs the programs
next to it (`dynapath render` is `dynapath-render`, and so on). Options are
parsed by CLI11: `-h` works everywhere; integers are decimal (`--size 020` is
20, `0x10` is refused); `run` and the three processes also read
`--config FILE` (CLI11 TOML, `key = value` under the options' names; the
command line overrides it). A study file for `dynapath experiment --config`
is TOML with the same keys (docs/howto/STUDIES.md).
"""


def declarations(source):
    """{"--name": ["path: Function", ...]}, from the tracked C++ sources."""
    files = subprocess.run(["git", "-C", source, "ls-files", "--deduplicate", "*.cc", "*.h"], check=True,
                           capture_output=True, text=True).stdout.split()
    found = {}
    for path in files:
        if path.startswith(("tests/", "fuzz/", "bench/")):
            continue
        with open(os.path.join(source, path), encoding="utf-8") as f:
            text = f.read()
        lines = text.split("\n")
        for match in DECLARATION.finditer(text):
            line = text.count("\n", 0, match.start())
            function = "?"
            for previous in range(line, -1, -1):
                m = FUNCTION.match(lines[previous])
                if m:
                    function = m.group(1)
                    break
            found.setdefault(match.group(1), []).append(f"`{path}`: {function}")
    return found


# The parameters' options are declared by their lines in these lists
# (runtime/parameter_options.cc declares one option per line): "--" and the
# member with '_' as '-'.
PARAMETER_LISTS = ["core/include/dynapath/learner_options.h"]
PARAMETER_LINE = re.compile(r"^\s*X\((\w+),")


def parameter_declarations(source, found):
    for path in PARAMETER_LISTS:
        macro = "?"
        with open(os.path.join(source, path), encoding="utf-8") as f:
            for line in f:
                if line.startswith("#define "):
                    macro = line.split()[1].split("(")[0]
                m = PARAMETER_LINE.match(line)
                if m:
                    name = "--" + m.group(1).replace("_", "-")
                    found.setdefault(name, []).append(f"`{path}`: {macro}")


def help_text(build, name, argv):
    """The --help of a command, with the build directory's path spelled
    `build` (so the text is the same on every machine); None if not built."""
    binary = os.path.join(build, argv[0])
    if not os.access(binary, os.X_OK):
        return None
    env = dict(os.environ, COLUMNS="80")
    out = subprocess.run([binary] + argv[1:] + ["--help"], capture_output=True, text=True,
                         timeout=30, env=env)
    if out.returncode != 0:
        sys.exit(f"FAIL: {name} --help exited {out.returncode}: {out.stderr.strip()}")
    text = out.stdout.replace(os.path.realpath(build), "build").rstrip()
    return "\n".join(line.rstrip() for line in text.split("\n"))


def command_options(build):
    """{"command": set of option names}, {"command": --help text}; commands
    not built are left out of both and listed in missing."""
    options, helps, missing = {}, {}, []
    for name, argv in COMMANDS + REFERENCE_ONLY:
        text = help_text(build, name, argv)
        if text is None:
            missing.append(name)
            continue
        helps[name] = text
        if (name, argv) in REFERENCE_ONLY:
            continue
        names = {m.group(1) for m in map(HELP_OPTION.match, text.split("\n")) if m}
        names.discard("--help")
        options[name] = names
    return options, helps, missing


def reference(helps):
    """docs/reference/CLI.md: the header, the homonyms, each command's --help."""
    parts = [HEADER, "Commands: " + ", ".join(
        f"[`{name}`](#{name.replace(' ', '-')})" for name, _ in COMMANDS + REFERENCE_ONLY) + ".\n",
        "Names that mean different things to different commands:\n"]
    parts.append("\n".join(f"* `{name}`: {why}" for name, (_, why) in sorted(HOMONYMS.items())) + "\n")
    for name, _ in COMMANDS + REFERENCE_ONLY:
        parts.append(f"## {name}\n\n```text\n{helps[name]}\n```\n")
    return "\n".join(parts)


def main():
    args = sys.argv[1:]
    if len(args) not in (2, 4) or (len(args) == 4 and args[2] not in ("--check", "--write")):
        sys.exit(__doc__)
    source, build = args[0], args[1]
    found = declarations(source)
    parameter_declarations(source, found)
    options, helps, missing = command_options(build)
    failures = []
    for name, sites in sorted(found.items()):
        allowed = HOMONYMS.get(name, (1, ""))[0]
        if len(sites) > allowed:
            failures.append(f"{name} is declared {len(sites)} times: {'; '.join(sites)}")
    for command, names in options.items():
        for name in sorted(names - set(found)):
            failures.append(f"{command} takes {name}, but no declaration names it")
    if len(args) == 4:
        path = args[3]
        if args[2] == "--write":
            if missing:
                sys.exit(f"FAIL: not built here: {', '.join(missing)}; {path} not written")
            with open(path, "w", encoding="utf-8") as f:
                f.write(reference(helps))
        elif missing:
            print(f"not built here: {', '.join(missing)}; {path} is not compared")
        else:
            with open(path, encoding="utf-8") as f:
                current = f.read()
            if current != reference(helps):
                failures.append(f"{path} is not current (a command's --help changed): run "
                                f"tests/options_table.py {source} {build} --write {path}")
    for failure in failures:
        print("FAIL: " + failure)
    if failures:
        sys.exit(1)
    print(f"options: {len(found)}, each declared once per meaning")


if __name__ == "__main__":
    main()
