"""gestc lsp: the language server, on standard input and output (an editor starts it,
with ``--stdio`` or without)."""

from __future__ import annotations

import argparse

from ...errors import Diagnostic, GestError
from ..common import EXIT_OK

INSTALL = "pip install 'inmoov-dsl[lsp]' (pygls), then start it again (docs/editors.md)"


def run(args: argparse.Namespace) -> int:
    """Serve until the editor asks the server to exit."""
    try:
        from ...editor.server import main
    except ImportError as exc:
        raise GestError(Diagnostic("error", f"the language server needs pygls: {exc}",
                                   hint=INSTALL)) from None
    main()
    return EXIT_OK


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestc lsp``."""
    p = sub.add_parser("lsp", help="the language server for editors (stdin and stdout)",
                       description="The language server of .gest files, for editors: "
                       "errors as you type, hover, completion, formatting (docs/editors.md). "
                       "An editor starts it and talks to it on standard input and output; "
                       "it needs pygls (pip install 'inmoov-dsl[lsp]').")
    p.add_argument("--stdio", action="store_true",
                   help="talk on standard input and output (what it does anyway: the flag "
                   "most editors' LSP settings pass)")
    p.set_defaults(func=run)
