"""gestc check: report the errors and warnings of .gest files, compiling every gesture."""

from __future__ import annotations

import argparse
from collections.abc import Iterable

from ...compiling.compiler import compile_program
from ...compiling.stretch import without_count
from ...errors import Diagnostic, GestError, Pos, decode_utf8
from ...language.library import library_dirs
from ...language.load import load
from ...language.program import Program
from ..common import EXIT_ERROR, EXIT_OK, report, stdin_bytes
from .target import PROG, add_arguments, link_keeps_up

STDIN = "<stdin>"  #: the name of the text read from standard input (``-``)

Told = set[tuple[str, Pos | None, str]]  #: (severity, place, message) already printed


def run(args: argparse.Namespace) -> int:
    """Each file: 'ok' and its gesture count, or its diagnostics (exit 1): every error
    it has, each gesture's (an error in one does not hide another's), each told once. A
    warning is told once per place and message for the whole check, however many
    gestures (or files) play that place."""
    status = EXIT_OK
    dirs = library_dirs(args.lib)
    told: Told = set()
    for file in args.files:
        name = STDIN if file == "-" else file
        try:
            text = decode_utf8(stdin_bytes(), STDIN) if file == "-" else None
            program = load(name, text, search=dirs)
        except GestError as exc:
            report(exc.diagnostics, PROG)
            status = EXIT_ERROR
            continue
        errors: list[Diagnostic] = []
        for gesture in program.own:
            try:
                _check_gesture(program, gesture, args, told)
            except GestError as exc:
                errors += untold(exc.diagnostics, told)
        if errors:
            report(errors, PROG)
            status = EXIT_ERROR
        else:
            count = len(program.own)
            print(f"{name}: ok ({count} gesture{'' if count == 1 else 's'})")
    return status


def _check_gesture(program: Program, gesture: str, args: argparse.Namespace,
                   told: Told) -> None:
    """Compile one gesture, print the warnings not told yet; with --strict a link that
    cannot keep up is an error too."""
    compiled, plan = compile_program(program, gesture, args.profile, None, args.strict)
    report(untold(compiled.warnings, told), PROG)
    if args.strict:
        link_keeps_up(program, compiled, plan)


def untold(warnings: Iterable[Diagnostic], told: Told) -> list[Diagnostic]:
    """The ``warnings`` whose place and message are not in ``told`` (which gets them):
    a place that two gestures play, or one plays three times, warns once."""
    out = []
    for d in warnings:
        key = (d.severity, d.pos, without_count(d.message))
        if key not in told:
            told.add(key)
            out.append(d)
    return out


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestc check FILE...``."""
    p = sub.add_parser("check", help="report errors and warnings only")
    p.add_argument("files", nargs="+", metavar="FILE", help="a .gest file, or - for stdin")
    add_arguments(p, target=False)
    p.set_defaults(func=run)
