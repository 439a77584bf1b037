"""gestc check: report the errors and warnings of .gest files, compiling every gesture."""

from __future__ import annotations

import argparse

from ...compiler import load
from ...errors import GestError
from ...library import library_dirs
from ..common import EXIT_ERROR, EXIT_OK, report
from .target import PROG, add_arguments, compile_one


def run(args: argparse.Namespace) -> int:
    """Each file: 'ok' and its gesture count, or its diagnostics (exit 1)."""
    status = EXIT_OK
    dirs = library_dirs(args.lib)
    for file in args.files:
        try:
            program = load(file, search=dirs)
            for name in program.own:
                compile_one(program, name, args.profile, None, args.strict)
            count = len(program.own)
            print(f"{file}: ok ({count} gesture{'' if count == 1 else 's'})")
        except GestError as exc:
            report(exc.diagnostics, PROG)
            status = EXIT_ERROR
    return status


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestc check FILE...``."""
    p = sub.add_parser("check", help="report errors and warnings only")
    p.add_argument("files", nargs="+", metavar="FILE")
    add_arguments(p, target=False)
    p.set_defaults(func=run)
