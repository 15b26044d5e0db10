#!/usr/bin/env python3
"""Executable documentation: runs the shell blocks (```sh, ```bash,
```console) of one Markdown page against a build, in order, and fails when
one of their commands fails or a file they name does not exist.

Usage: docs_test.py SOURCE_DIR BUILD_DIR PAGE [--timeout SECONDS] [--python PYTHON]
       docs_test.py --self-test

PAGE is relative to SOURCE_DIR (README.md, docs/howto/MAPS.md, ...). The
page's blocks run one after the other in one bash, in a fresh temporary
folder holding a copy of the source tree (the files git tracks: what a clone
holds) (so a block may write anywhere,
e.g. scripts/make_reproduction_report.py rewriting docs/REPRODUCTION.md,
without touching the repository) and `build`, a symlink to BUILD_DIR: the
docs' `build/tools/dynapath` is the build under test. The page runs inside
`BUILD_DIR/tools/dynapath netns --`, a private network (its LCM traffic
never reaches the host's); exit 77 (skipped) where namespaces are refused.
With --python, the blocks' `python3` is PYTHON (the interpreter CMake found,
the one the Python module is built for), whatever PATH holds.

What fails the page:
  * a command of a runnable block exits non-zero (each command, not only a
    block's last: `a && b` failing counts; pipelines with pipefail);
  * a block names a repository file that git does not track (an argument
    whose first path component is a top-level entry of the source tree, e.g.
    tests/data/..., docs/examples/...; checked in skipped blocks too);
  * the file given to an input option (--maze, --stations-file, --changes,
    --config, --replay, --load-policy, ...) or a build/... program does not
    exist when its command is about to run;
  * a runnable block keeps a placeholder (PID, DIR, `...`, <name>): the
    docs show real commands only;
  * a marker that no longer matches its block (below), or the page takes
    longer than --timeout (default 300 s).

Markers: HTML comments (invisible on a rendered page) on the lines just
before a block's opening fence, one directive each:
  <!-- docs-test: skip REASON -->       not run here, and why (docker, a
                                         display, several hosts); required
  <!-- docs-test: set --opt VALUE ... --> every `--opt X` (or --opt=X) of
                                         the block gets VALUE instead: the
                                         test runs smaller sizes and steps
                                         than the page shows; an option the
                                         block lacks is an error
  <!-- docs-test: replace OLD NEW -->   literal text substitution in the
                                         block (shell quoting for OLD/NEW);
                                         OLD must occur
  <!-- docs-test: env NAME=VALUE ... --> exported while the block runs
  <!-- docs-test: requires PATH ... -->  the block needs what an optional
                                         part of the build makes (e.g.
                                         build/python/dynapath, built when
                                         pybind11 is installed): skipped,
                                         saying so, when PATH is missing
  The page's shell also has __docs_wait_netns PID for markers: it waits
  until PID (a launcher started with &) is in its private network, e.g.
  before `dynapath view --pid $!` joins it.
  <!-- docs-test: background -->        the block's last command is a
                                         service meant to run until stopped:
                                         the test starts it in the
                                         background, the page's later blocks
                                         talk to it, and it is stopped (with
                                         everything else the page started)
                                         when the page ends
"""
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import time

SHELL_LANGUAGES = {"sh", "bash", "console", "shell"}
MARKER = re.compile(r"^\s*<!--\s*docs-test:\s*(.*?)\s*-->\s*$")
FENCE = re.compile(r"^(\s*)(```+|~~~+)\s*([A-Za-z0-9_+-]*)")
# Options whose value is a file or folder the command reads.
INPUT_OPTIONS = {"--maze", "--stations-file", "--changes", "--config", "--maps", "--replay",
                 "--load-policy", "--resume", "--secret-file", "--reference"}
# Options whose value is a file or folder the command writes.
OUTPUT_OPTIONS = {"--out", "--save", "--save-changes", "--save-policy", "--log", "--checkpoint", "--write",
                  "--screenshot", "-o"}
PLACEHOLDER = re.compile(r"^(PID|DIR|FILE|COMMAND|ARGS|URL|PATH|HOST|NAME|N)$|\.\.\.|…|^\[.*\.\.\.\]$")
ANGLE_PLACEHOLDER = re.compile(r"<[A-Za-z][A-Za-z0-9 _-]*>")  # <this repository>
# Top-level entries of a source tree that are outputs, not repository files.
NOT_REPOSITORY = {"build", "out", "results", "study"}


class PageError(Exception):
    pass


class Block:
    def __init__(self, page, line, language, text, markers):
        self.page, self.line, self.language, self.text = page, line, language, text
        self.skip = None
        self.sets = []       # [(option, value)]
        self.replaces = []   # [(old, new)]
        self.env = []        # ["NAME=VALUE"]
        self.background = False
        self.requires = []   # paths (build/... or the tree's) an optional part of the build makes
        for marker_line, directive in markers:
            self._apply_marker(marker_line, directive)

    def where(self, offset=0):
        return f"{self.page}:{self.line + offset}"

    def _apply_marker(self, line, directive):
        where = f"{self.page}:{line}"
        word, _, rest = directive.partition(" ")
        rest = rest.strip()
        try:  # a skip's reason is prose, not shell words
            args = shlex.split(rest) if word != "skip" else rest.split()
        except ValueError as error:
            raise PageError(f"{where}: docs-test marker: {error}")
        if word == "skip":
            if not rest:
                raise PageError(f"{where}: docs-test: skip needs a reason")
            self.skip = rest
        elif word == "set":
            if not args or len(args) % 2 != 0 or not all(a.startswith("--") for a in args[::2]):
                raise PageError(f"{where}: docs-test: set takes pairs: --option VALUE ...")
            self.sets += list(zip(args[::2], args[1::2]))
        elif word == "replace":
            if len(args) != 2:
                raise PageError(f"{where}: docs-test: replace takes OLD NEW, got {len(args)} words")
            self.replaces.append((args[0], args[1]))
        elif word == "env":
            if not args or not all(re.match(r"^[A-Za-z_][A-Za-z0-9_]*=", a) for a in args):
                raise PageError(f"{where}: docs-test: env takes NAME=VALUE ...")
            self.env += args
        elif word == "background" and not args:
            self.background = True
        elif word == "requires" and args:
            self.requires += args
        else:
            raise PageError(f"{where}: unknown docs-test directive '{directive}' "
                            "(skip REASON, set --opt V, replace OLD NEW, env N=V, background, requires PATH)")

    def runnable_text(self):
        """The block as the test runs it: markers' substitutions applied."""
        text = self.text
        for old, new in self.replaces:
            if old not in text:
                raise PageError(f"{self.where()}: docs-test: replace: '{old}' is not in the block")
            text = text.replace(old, new)
        for option, value in self.sets:
            pattern = re.compile(r"(?<![\w-])" + re.escape(option) + r"(=|\s+)(\"[^\"]*\"|'[^']*'|\S+)")
            text, count = pattern.subn(lambda m: option + m.group(1) + shlex.quote(value), text)
            if count == 0:
                raise PageError(f"{self.where()}: docs-test: set: the block has no {option}")
        return text


def parse_page(page, text):
    """The page's shell blocks, each with the markers just before it."""
    blocks, markers, lines = [], [], text.split("\n")
    i = 0
    while i < len(lines):
        marker = MARKER.match(lines[i])
        fence = FENCE.match(lines[i])
        if marker:
            markers.append((i + 1, marker.group(1)))
            i += 1
            continue
        if fence:
            indent, ticks, language = fence.groups()
            end = i + 1
            while end < len(lines) and not lines[end].strip().startswith(ticks):
                end += 1
            body = [l[len(indent):] if l.startswith(indent) else l for l in lines[i + 1:end]]
            if language.lower() in SHELL_LANGUAGES:
                blocks.append(Block(page, i + 2, language, "\n".join(body), markers))
            elif markers:
                raise PageError(f"{page}:{markers[0][0]}: a docs-test marker before a block that is not sh/bash/console")
            markers = []
            i = end + 1
            continue
        if markers and lines[i].strip():
            raise PageError(f"{page}:{markers[0][0]}: a docs-test marker must come just before a block's fence")
        i += 1
    if markers:
        raise PageError(f"{page}:{markers[0][0]}: a docs-test marker after the last block")
    return blocks


HEREDOC = re.compile(r"<<(-?)\s*(['\"]?)([A-Za-z_][A-Za-z0-9_]*)\2")


def logical_lines(text):
    """(offset, command text) per command line: backslash continuations,
    quotes spanning lines and here-documents joined; blank and comment-only
    lines left out."""
    result, pending, start, heredoc = [], [], 0, None
    for offset, line in enumerate(text.split("\n")):
        if heredoc:  # inside a here-document, up to its delimiter line
            pending.append(line)
            if (line.lstrip("\t") if heredoc[0] else line) == heredoc[1]:
                result.append((start, "\n".join(pending)))
                pending, heredoc = [], None
            continue
        if not pending:
            start = offset
        if line.startswith("$ "):  # a console prompt
            line = line[2:]
        pending.append(line)
        joined = "\n".join(pending)
        if joined.endswith("\\"):
            continue
        try:
            shlex.split(joined, comments=True)
        except ValueError:  # an open quote
            continue
        match = HEREDOC.search(joined.split("#")[0] if "'" not in joined else joined)
        if match:
            heredoc = (match.group(1) == "-", match.group(3))
            continue
        if shlex.split(joined, comments=True):
            result.append((start, joined))
        pending = []
    if pending:
        result.append((start, "\n".join(pending)))
    return result


def command_part(command):
    """A logical line without its here-document bodies (the shell's words)."""
    lines = command.split("\n")
    for i, line in enumerate(lines):
        if HEREDOC.search(line):
            return "\n".join(lines[:i + 1])
    return command


def words(command):
    command = command_part(command)
    try:
        lexer = shlex.shlex(command, posix=True, punctuation_chars=";&|()<>")
        lexer.whitespace_split = True
        lexer.commenters = "#"
        return list(lexer)
    except ValueError:
        return []


def check_placeholders(block):
    for offset, command in logical_lines(block.text):
        angle = ANGLE_PLACEHOLDER.search(command_part(command).split(" #")[0])
        if angle:
            raise PageError(f"{block.where(offset)}: a placeholder ('{angle.group(0)}') in a block the test runs: "
                            "show a real command, or mark the block skip with a reason")
        for word in words(command):
            if re.match(r"^[A-Za-z_][A-Za-z0-9_]*=", word):
                word = word.split("=", 1)[1]
            if word and PLACEHOLDER.search(word):
                raise PageError(f"{block.where(offset)}: a placeholder ('{word}') in a block the test runs: "
                                "show a real command, or mark the block skip with a reason")


def repository_paths(command, top_level):
    """The arguments of a command that name files of the source tree (not
    the outputs it makes: output options' values, mkdir's arguments)."""
    previous, program = None, None
    for word in words(command):
        if previous is None or set(previous) <= set(";&|("):
            program = word
        output = previous in OUTPUT_OPTIONS or program == "mkdir"
        previous = word
        if output or word.split("=", 1)[0] in OUTPUT_OPTIONS:
            continue
        for value in ([word] + ([word.split("=", 1)[1]] if "=" in word else [])):
            first = value.split("/", 1)[0]
            if "/" in value and first in top_level and "$" not in value and "*" not in value:
                yield value


def input_files(command):
    """Files the command reads: the values of input options, programs under build/."""
    ws = words(command)
    for i, word in enumerate(ws):
        value = None
        if word in INPUT_OPTIONS and i + 1 < len(ws):
            value = ws[i + 1]
        elif "=" in word and word.split("=", 1)[0] in INPUT_OPTIONS:
            value = word.split("=", 1)[1]
        elif word.startswith("build/") and (i == 0 or ws[i - 1] in ";&|(" or ws[i - 1] in ("exec", "timeout")
                                            or re.match(r"^[A-Za-z_][A-Za-z0-9_]*=", ws[i - 1])):
            value = word
        if value and "$" not in value and not value.startswith("-"):
            # --maps takes a comma-separated list
            yield from (value.split(",") if ws[i] == "--maps" or word.startswith("--maps=") else [value])


SCRIPT_HEAD = r"""set -o pipefail
__docs_at=
__docs_fail() { echo "docs-test: FAILED at $__docs_at: $1" >&2; exit 1; }
__docs_check() { [ "$1" -eq 0 ] || __docs_fail "the command exited $1"; }
__docs_need() { [ -e "$1" ] || __docs_fail "names $1, which does not exist"; }
# For markers: wait (at most 10 s) until process $1 is in a network of its
# own, as a launcher of --agents is once it has set up its private network.
__docs_wait_netns() {
  local i
  for i in $(seq 100); do
    [ "$(readlink /proc/$1/ns/net 2>/dev/null)" != "$(readlink /proc/$$/ns/net)" ] && return 0
    sleep 0.1
  done
  __docs_fail "process $1 made no private network within 10 s"
}
__docs_start=$EPOCHREALTIME
__docs_block() {  # the block's start, with the seconds since the page's
  local t=$(( (${EPOCHREALTIME/./} - ${__docs_start/./}) / 100000 ))
  echo "docs-test: $1: running (at $((t / 10)).$((t % 10)) s)"
}
"""


def page_script(blocks):
    out = [SCRIPT_HEAD]
    for block in blocks:
        if block.skip:
            out.append(f"echo {shlex.quote(f'docs-test: {block.where()}: skipped: {block.skip}')}")
            continue
        out.append(f"__docs_block {shlex.quote(block.where())}")
        for assignment in block.env:
            out.append("export " + assignment.split("=", 1)[0] + "=" + shlex.quote(assignment.split("=", 1)[1]))
        commands = logical_lines(block.runnable_text())
        for index, (offset, command) in enumerate(commands):
            out.append(f"__docs_at={shlex.quote(block.where(offset))}")
            for path in input_files(command):
                out.append(f"__docs_need {shlex.quote(path)}")
            if block.background and index == len(commands) - 1:
                command = command.rstrip()
                if not command.endswith("&"):
                    command = "{ " + command + "\n} &"
            out.append(command)
            out.append("__docs_check $?")
        for assignment in block.env:
            out.append("unset " + assignment.split("=", 1)[0])
    out.append("exit 0")
    return "\n".join(out) + "\n"


def tracked_files(source):
    """The files git tracks in SOURCE (what a clone has: a developer's own
    left-overs, a study in the top folder say, stay out), or None outside git."""
    try:
        listing = subprocess.run(["git", "-C", source, "ls-files", "-z"], capture_output=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return None
    files = [f for f in listing.decode().split("\0") if f and os.path.lexists(os.path.join(source, f))]
    return files or None


def in_repository(source, files, path):
    if files is None:
        return os.path.exists(os.path.join(source, path))
    path = os.path.normpath(path)
    return any(f == path or f.startswith(path.rstrip("/") + "/") for f in files)


def copy_source(source, files, folder):
    if files is not None:
        for f in files:
            os.makedirs(os.path.join(folder, os.path.dirname(f)), exist_ok=True)
            shutil.copy2(os.path.join(source, f), os.path.join(folder, f), follow_symlinks=False)
        return

    def ignore(directory, names):
        if os.path.abspath(directory) != os.path.abspath(source):
            return [n for n in names if n == "__pycache__"]
        return [n for n in names if n.startswith(".git") or n.startswith("build") or n in NOT_REPOSITORY]
    shutil.copytree(source, folder, ignore=ignore, symlinks=True, dirs_exist_ok=True)


def run_page(source, build, page, timeout, python=None):
    with open(os.path.join(source, page), encoding="utf-8") as f:
        blocks = parse_page(page, f.read())
    files = tracked_files(source)
    top_level = {n for n in os.listdir(source) if not n.startswith(".") and n not in NOT_REPOSITORY}
    for block in blocks:
        for offset, command in logical_lines(block.text):
            for path in repository_paths(command, top_level):
                if not in_repository(source, files, path):
                    raise PageError(f"{block.where(offset)}: names {path}, which is not in the repository")
        if not block.skip:
            check_placeholders(block)
            block.runnable_text()  # a stale marker fails before anything runs
    for block in blocks:
        for path in block.requires:
            built = os.path.join(build, path[len("build/"):]) if path.startswith("build/") else \
                os.path.join(source, path)
            if not block.skip and not os.path.exists(built):
                block.skip = f"requires {path}, which this build did not make"
    run = [b for b in blocks if not b.skip]
    print(f"docs-test: {page}: {len(run)} blocks to run, {len(blocks) - len(run)} skipped")
    for b in blocks:
        if b.skip:
            print(f"docs-test: {b.where()}: skip: {b.skip}")
    if not run:
        print(f"docs-test: SKIPPED: {page}: every block is marked skip")
        return 77
    dynapath = os.path.join(build, "tools", "dynapath")
    if subprocess.run([dynapath, "netns", "--", "true"], stdout=subprocess.DEVNULL,
                      stderr=subprocess.DEVNULL).returncode != 0:
        print("docs-test: SKIPPED: no private network namespace here (dynapath netns -- true failed)")
        return 77
    folder = tempfile.mkdtemp(prefix="dynapath-docs-")
    try:
        copy_source(source, files, folder)
        os.symlink(os.path.abspath(build), os.path.join(folder, "build"))
        script = os.path.join(folder, ".docs-test.sh")
        with open(script, "w", encoding="utf-8") as f:
            f.write(page_script(blocks))
        env = {k: v for k, v in os.environ.items() if k != "LCM_DEFAULT_URL"}
        if python:
            tools = os.path.join(folder, ".docs-bin")
            os.mkdir(tools)
            os.symlink(python, os.path.join(tools, "python3"))
            env["PATH"] = tools + os.pathsep + env.get("PATH", "")
        started = time.monotonic()
        process = subprocess.Popen([dynapath, "netns", "--", "bash", "--noprofile", "--norc", script],
                                   cwd=folder, env=env, start_new_session=True, stdin=subprocess.DEVNULL)
        try:
            code = process.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            print(f"docs-test: FAILED: {page} took longer than {timeout} s", flush=True)
            code = 124
        finally:
            try:  # the page's background services, and anything a timeout left
                os.killpg(process.pid, signal.SIGTERM)
                time.sleep(0.5)
                os.killpg(process.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            process.wait()
        print(f"docs-test: {page}: {'passed' if code == 0 else 'FAILED'} in {time.monotonic() - started:.1f} s")
        return 0 if code == 0 else 1
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def self_test():
    """The parser, markers and checks on small pages (no build needed)."""
    page = ("<!-- docs-test: set --size 20 --steps 3 -->\n```sh\n"
            "build/tools/dynapath run --size 50 --steps=100 \\\n  --out out/a\n```\n"
            "text\n<!-- docs-test: skip (docker: no engine) -->\n```bash\ndocker compose up\n```\n"
            "```\nnot shell\n```\n<!-- docs-test: background -->\n```console\nsleep 100\n```\n")
    blocks = parse_page("p.md", page)
    assert [b.line for b in blocks] == [3, 9, 16], [b.line for b in blocks]
    assert blocks[0].runnable_text() == "build/tools/dynapath run --size 20 --steps=3 \\\n  --out out/a"
    assert blocks[1].skip == "(docker: no engine)"
    assert logical_lines(blocks[0].text) == [(0, blocks[0].text)]
    assert "{ sleep 100\n} &" in page_script(blocks)
    assert list(input_files("build/tools/dynapath run --maze m.map --changes=c.ch | build/x")) == \
        ["build/tools/dynapath", "m.map", "c.ch", "build/x"]
    assert list(input_files("x experiment --maps a.map,b")) == ["a.map", "b"]
    assert list(repository_paths("x --maze docs/examples/maps/a.map --out docs/b; mkdir -p docs/c", {"docs"})) == \
        ["docs/examples/maps/a.map"]
    assert logical_lines("bash -c '\n  a & b\n  c'\n# note\nd") == [(0, "bash -c '\n  a & b\n  c'"), (4, "d")]
    heredoc = "PYTHONPATH=x python3 - <<'EOF'\nprint('...', \"it's\")\nEOF\nls\ncat <<-END\n\tPID\n\tEND"
    assert logical_lines(heredoc) == [(0, "PYTHONPATH=x python3 - <<'EOF'\nprint('...', \"it's\")\nEOF"), (3, "ls"),
                                      (4, "cat <<-END\n\tPID\n\tEND")], logical_lines(heredoc)
    check_placeholders(parse_page("p.md", "```sh\n" + heredoc + "\n```\n")[0])
    failures = {
        "```sh\nbuild/tools/dynapath view --pid PID\n```\n": "placeholder",
        "```sh\nbuild/tools/dynapath feed ... --rate 4\n```\n": "placeholder",
        "```sh\ngit clone <this repository> dynapath\n```\n": "placeholder",
        "<!-- docs-test: set --size 2 -->\n```sh\nls\n```\n": "has no --size",
        "<!-- docs-test: replace a b -->\n```sh\nls\n```\n": "is not in the block",
        "<!-- docs-test: skip -->\n```sh\nls\n```\n": "needs a reason",
        "<!-- docs-test: frobnicate -->\n```sh\nls\n```\n": "unknown docs-test directive",
        "<!-- docs-test: skip x -->\n\nprose\n```sh\nls\n```\n": "just before",
    }
    for text, expected in failures.items():
        try:
            for block in parse_page("p.md", text):
                check_placeholders(block)
                block.runnable_text()
        except PageError as error:
            assert expected in str(error), (text, str(error))
        else:
            raise AssertionError(f"no error for {text!r}")
    print("docs_test self-test: passed")
    return 0


def stop_on_sigterm(signum, frame):
    # ctest's TIMEOUT sends SIGTERM: end as on a failure, so that the page's
    # processes are stopped and its folder removed (the finally clauses).
    raise SystemExit(1)


def main(argv):
    signal.signal(signal.SIGTERM, stop_on_sigterm)
    if argv[1:] == ["--self-test"]:
        return self_test()
    args, timeout, python = argv[1:], 300, None
    if "--timeout" in args:
        i = args.index("--timeout")
        timeout = float(args[i + 1])
        del args[i:i + 2]
    if "--python" in args:
        i = args.index("--python")
        python = args[i + 1]
        del args[i:i + 2]
    if len(args) != 3:
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    try:
        return run_page(*args, timeout, python)
    except PageError as error:
        print(f"docs-test: FAILED: {error}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
