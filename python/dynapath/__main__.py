"""python3 -m dynapath run|experiment ARGS: the CLI's runs with Python approaches.

``dynapath run`` and ``dynapath experiment`` hand their command line over
to this when an approach of --approach (--approaches) is ``py:MODULE:CLASS``
(MODULE a module on the Python path, or a .py file): each such entry is
an instance of CLASS (a new one for each run of a study), the others are
built-in approaches, and the whole command line is parsed by the C++
binding with the CLI's own option declarations. The run happens in this
process (--local), evaluated and written by the same C++ code as the
CLI's. Exit status: 0 done, 1 the run failed, 2 bad options, 130
interrupted.
"""

import importlib
import importlib.util
import os
import sys

from . import _dynapath
from .run import _label

USAGE = "usage: python3 -m dynapath run|experiment [the CLI's options]"


def load_approach(spec):
    """The class named by ``py:MODULE:CLASS`` (MODULE dotted, or a path to a .py file)."""
    parts = spec.split(":")
    if len(parts) != 3 or parts[0] != "py" or not parts[1] or not parts[2]:
        raise ValueError(f"a Python approach is py:MODULE:CLASS, got '{spec}'")
    module_name, class_name = parts[1], parts[2]
    if module_name.endswith(".py"):
        if not os.path.isfile(module_name):
            raise ValueError(f"{spec}: no file {module_name}")
        name = os.path.splitext(os.path.basename(module_name))[0]
        loaded = importlib.util.spec_from_file_location(name, module_name)
        module = importlib.util.module_from_spec(loaded)
        loaded.loader.exec_module(module)
    else:
        try:
            module = importlib.import_module(module_name)
        except ImportError as error:
            raise ValueError(f"{spec}: cannot import {module_name}: {error}") from error
    approach = getattr(module, class_name, None)
    if not isinstance(approach, type):
        raise ValueError(f"{spec}: {module_name} has no class {class_name}")
    for method in ("initialize", "adapt"):
        if not callable(getattr(approach, method, None)):
            raise ValueError(f"{spec}: {class_name} has no method {method}(grid, ...)")
    return approach


def split_command_line(args, option):
    """The arguments with --OPTION's py: entries taken out, whether built-in
    names remain, and the Python approaches as the binding takes them."""
    rest, names, external = [], [], []
    i = 0
    while i < len(args):
        arg = args[i]
        value = None
        if arg == option and i + 1 < len(args):
            value, i = args[i + 1], i + 2
        elif arg.startswith(option + "="):
            value, i = arg[len(option) + 1:], i + 1
        else:
            rest.append(arg)
            i += 1
            continue
        for entry in value.split(","):
            if entry.strip().startswith("py:"):
                approach = load_approach(entry.strip())
                external.append((",".join(names), _label(approach), approach))
            else:
                names.append(entry)
    if names:
        rest += [option, ",".join(names)]
    return rest, bool(names), external


def main(argv):
    if len(argv) < 1 or argv[0] not in ("run", "experiment"):
        print(USAGE, file=sys.stderr)
        return 2
    command, args = argv[0], argv[1:]
    program = f"dynapath {command}"
    if "--help" in args or "-h" in args:
        print(f"{program} with a py:MODULE:CLASS approach runs in this process (--local) "
              f"through the Python module; its options are those of `{program} --help` "
              f"(docs/howto/PYTHON.md)")
        return 0
    try:
        args, builtin, external = split_command_line(
            args, "--approach" if command == "run" else "--approaches")
        if command == "run":
            out = _dynapath.cli_run(args, builtin, external)
            import pandas

            table = pandas.read_csv(os.path.join(out, "results.csv"))
            print(table.to_string(index=False))
        else:
            out = _dynapath.experiment(args, builtin, external)
            print(f"{program}: study done; results in {os.path.join(out, 'results.csv')}",
                  file=sys.stderr)
        return 0
    except KeyboardInterrupt:
        print(f"\n{program}: interrupted", file=sys.stderr)
        return 130
    except (ValueError, TypeError, FileNotFoundError) as error:
        text = str(error)
        if text.startswith("unknown option"):  # one of the CLI's that need its own process
            text = text.replace(" (see --help)", "") + ": not available with a py: approach " \
                "(docs/howto/PYTHON.md)"
        print(f"{program}: {text}", file=sys.stderr)
        return 2
    except (OSError, RuntimeError) as error:
        print(f"{program}: {error}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
