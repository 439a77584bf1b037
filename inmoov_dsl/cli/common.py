"""What both command-line tools share: error printing and exit codes."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Iterable

from ..errors import Diagnostic, GestError

EXIT_OK, EXIT_ERROR, EXIT_USAGE, EXIT_INTERRUPTED = 0, 1, 2, 130


def report(diagnostics: Iterable[Diagnostic], prog: str) -> None:
    for d in diagnostics:
        text = d.format()
        if d.pos is None:
            text = f"{prog}: {text}"
        print(text, file=sys.stderr)


def run(prog: str, body: Callable[[], int]) -> int:
    """Run a command: people get messages and exit codes, never a traceback."""
    try:
        return body()
    except GestError as exc:
        report(exc.diagnostics, prog)
        return EXIT_ERROR
    except KeyboardInterrupt:
        print(f"{prog}: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except BrokenPipeError:
        sys.stderr.close()  # the reader went away (| head): nothing more to say
        return EXIT_OK
    except OSError as exc:
        where = f" '{exc.filename}'" if exc.filename else ""
        print(f"{prog}: error: cannot use{where}: {exc.strerror or exc}", file=sys.stderr)
        return EXIT_ERROR


def add_lib(p: argparse.ArgumentParser) -> None:
    p.add_argument("--lib", action="append", default=[], metavar="DIR",
                   help="also look for gestures in DIR (before GEST_PATH, ./gestures and "
                   "the built-in library); may be repeated")
