"""gestc check: report the errors and warnings of .gest files, compiling every gesture."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from ...compiling.checking import Told, check_program
from ...compiling.compiler import plan_checks
from ...errors import GestError, decode_utf8
from ...language.incremental import BlockParser
from ...language.library import library_dirs
from ...language.load import load
from ...model import collisions
from ..common import EXIT_ERROR, EXIT_OK, report, stdin_bytes
from .target import PROG, add_arguments, link_keeps_up

STDIN = "<stdin>"  #: the name of the text read from standard input (``-``)


def run(args: argparse.Namespace) -> int:
    """Each file: its diagnostics, then 'ok' with its gesture and warning counts, or
    (exit 1) the count of its errors and warnings: every error it has, each gesture's (an
    error in one does not hide another's), each told once. A warning is told once per
    place and message for the whole check, however many gestures (or files) play that
    place. With --strict a link that cannot keep up is an error too."""
    status = EXIT_OK
    dirs = library_dirs(args.lib)
    told: Told = set()
    for file in args.files:
        name = STDIN if file == "-" else file
        try:
            text = decode_utf8(stdin_bytes(), STDIN) if file == "-" else None
            program = load(name, text, search=dirs, partly=BlockParser().parse_partly)
        except GestError as exc:
            report(exc.diagnostics, PROG)
            summary(name, exc.diagnostics, ())
            status = EXIT_ERROR
            continue
        with plan_checks(collisions):  # the robot's parts against each other
            errors, warnings = check_program(program, args.profile, args.strict, told,
                                             link_keeps_up if args.strict else None)
        report(warnings, PROG)
        if errors:
            report(errors, PROG)
            status = EXIT_ERROR
        summary(name, errors, warnings, len(program.own))
    return status


def summary(name: str, errors: Sequence[object], warnings: Sequence[object],
            gestures: int = 0) -> None:
    """The line that ends a file's report, after its diagnostics: ``FILE: ok (N
    gestures, M warnings)`` on standard output, or ``FILE: N errors, M warnings`` on
    standard error."""
    said = [counted(len(warnings), "warning")] if warnings else []
    sys.stderr.flush()  # the diagnostics above it, wherever the two streams go
    if errors:
        print(f"{name}: {', '.join([counted(len(errors), 'error'), *said])}",
              file=sys.stderr, flush=True)
    else:
        print(f"{name}: ok ({', '.join([counted(gestures, 'gesture'), *said])})", flush=True)


def counted(count: int, what: str) -> str:
    """``1 error``, ``2 errors``."""
    return f"{count} {what}{'' if count == 1 else 's'}"


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestc check FILE...``."""
    p = sub.add_parser("check", help="report errors and warnings only",
                       description="Check .gest files as gestc compile would, writing "
                       "nothing: every error and warning of each file, at its place "
                       "(FILE:LINE:COLUMN), in one pass, then a line for the file: 'FILE: ok "
                       "(N gestures, M warnings)' on standard output, or 'FILE: N errors, "
                       "M warnings' on standard error. Exit status 1 if any file has an "
                       "error.")
    p.add_argument("files", nargs="+", metavar="FILE", help="a .gest file, or - for stdin")
    add_arguments(p, target=False)
    p.set_defaults(func=run)
