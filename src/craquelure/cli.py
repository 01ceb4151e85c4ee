"""Command line: ``craquelure <command> ...``.

Commands live in :mod:`craquelure.commands`, one module each with ``NAME``, ``HELP``,
``add_arguments(parser)`` and ``main(args) -> int``; this module discovers them.
"""

import argparse
import importlib
import pkgutil
import sys

from craquelure import __version__
from craquelure.errors import INTERRUPTED_EXIT, CraquelureError, RunInterrupted


def build_parser() -> argparse.ArgumentParser:
    import craquelure.commands as commands

    parser = argparse.ArgumentParser(prog="craquelure", description=__doc__.splitlines()[0])
    parser.add_argument("--version", action="version", version=f"craquelure {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    for info in sorted(pkgutil.iter_modules(commands.__path__), key=lambda i: i.name):
        module = importlib.import_module(f"craquelure.commands.{info.name}")
        if not hasattr(module, "NAME"):
            continue
        p = sub.add_parser(module.NAME, help=module.HELP, description=module.HELP)
        module.add_arguments(p)
        p.set_defaults(_main=module.main)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        if getattr(args, "threads", None):  # the commands that take --threads
            import numba

            numba.set_num_threads(args.threads)
        return int(args._main(args) or 0)
    except RunInterrupted as exc:  # checkpoint written: resume with --resume
        _fail(args.command, str(exc), "interrupted")
        return INTERRUPTED_EXIT
    except CraquelureError as exc:  # scene, dataset, guard (SimulationDiverged)
        return _fail(args.command, str(exc))
    except MemoryError:
        return _fail(args.command, "out of memory: the run does not fit in this machine's "
                     "memory; make the scene smaller")
    except ArithmeticError as exc:  # overflow / division by zero of a scene's numbers
        return _fail(args.command, f"the scene's numbers cannot be computed with "
                     f"({type(exc).__name__}: {exc}); check the magnitudes of its values")
    except OSError as exc:  # a file that cannot be read or written: name it
        where = exc.filename or ""
        return _fail(args.command, f"{where}: {exc.strerror or exc}" if where else str(exc))
    except (ValueError, KeyError) as exc:
        return _fail(args.command, str(exc))


def _fail(command: str, message: str, what: str = "error") -> int:
    """One line on stderr (a multi-line message's items joined by "; "); exit 2."""
    head, *items = [line.strip() for line in message.splitlines() if line.strip()] or [""]
    if items:
        head = f"{head} {'; '.join(items)}" if head.endswith(":") else "; ".join([head, *items])
    print(f"craquelure {command}: {what}: {head}", file=sys.stderr)
    return 2
