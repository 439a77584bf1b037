"""gestc check: report the errors and warnings of .gest files, compiling every gesture."""

from __future__ import annotations

import argparse

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
    """Each file: 'ok' and its gesture count, or its diagnostics (exit 1): every error
    it has, each gesture's (an error in one does not hide another's), each told once. A
    warning is told once per place and message for the whole check, however many
    gestures (or files) play that place. With --strict a link that cannot keep up is an
    error too."""
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
            status = EXIT_ERROR
            continue
        with plan_checks(collisions):  # the robot's parts against each other
            errors, warnings = check_program(program, args.profile, args.strict, told,
                                             link_keeps_up if args.strict else None)
        report(warnings, PROG)
        if errors:
            report(errors, PROG)
            status = EXIT_ERROR
        else:
            count = len(program.own)
            print(f"{name}: ok ({count} gesture{'' if count == 1 else 's'})")
    return status


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestc check FILE...``."""
    p = sub.add_parser("check", help="report errors and warnings only",
                       description="Check .gest files as gestc compile would, writing "
                       "nothing: every error and warning of each file, at its place "
                       "(FILE:LINE:COLUMN), in one pass; 'FILE: ok (N gestures)' on "
                       "standard output for a file without errors. Exit status 1 if any "
                       "file has an error.")
    p.add_argument("files", nargs="+", metavar="FILE", help="a .gest file, or - for stdin")
    add_arguments(p, target=False)
    p.set_defaults(func=run)
