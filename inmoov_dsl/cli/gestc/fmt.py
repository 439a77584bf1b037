"""gestc fmt: rewrite .gest files in the canonical layout."""

from __future__ import annotations

import argparse
import codecs
import sys
from pathlib import Path

from ...errors import GestError, decode_utf8
from ..common import EXIT_ERROR, EXIT_OK, report, stdin_bytes
from .target import PROG


def run(args: argparse.Namespace) -> int:
    """Rewrite files in the canonical layout (``-``: stdin to stdout). The text is read
    as UTF-8; a byte-order mark at its start is dropped (a file that has one is
    rewritten without it)."""
    from ...language.fmt import format_source
    from ...language.load import folder_given

    status = EXIT_OK
    for file in args.files:
        name = "<stdin>" if file == "-" else file
        try:
            data = stdin_bytes() if file == "-" else Path(file).read_bytes()
            text = decode_utf8(data, name)
            formatted = format_source(text, name)
        except GestError as exc:
            report(exc.diagnostics, PROG)
            status = EXIT_ERROR
            continue
        except IsADirectoryError:
            report([folder_given(file)], PROG)
            status = EXIT_ERROR
            continue
        if file == "-":
            sys.stdout.write(formatted)
        elif formatted != text or data.startswith(codecs.BOM_UTF8):
            if args.check:
                print(f"{file}: would be reformatted")
                status = EXIT_ERROR
            else:
                Path(file).write_text(formatted, encoding="utf-8")
                print(f"{file}: reformatted", file=sys.stderr)
    return status


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestc fmt FILE...``."""
    p = sub.add_parser("fmt", help="rewrite .gest files in the canonical layout")
    p.add_argument("files", nargs="+", metavar="FILE", help="a .gest file, or - for stdin")
    p.add_argument("--check", action="store_true",
                   help="change nothing; list the files fmt would change, exit 1 if any")
    p.set_defaults(func=run)
