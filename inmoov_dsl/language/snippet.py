"""One line typed outside a file (``--from``, a line at the repl), parsed as a file.

The line is wrapped in a prefix that makes it a definition (``pose start__: ...``,
``_: ...``); what is said about the wrapped text is moved back onto the typed line, so
a caret points at what the user typed.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import replace

from ..errors import Diagnostic, GestError, Pos
from .parse import parse
from .syntax import Module


@contextmanager
def parsed(text: str, file: str, prefix: str, line: int = 1) -> Iterator[Module]:
    """Parse ``prefix + text`` under the name ``file`` and give its module; a GestError
    raised while parsing it or in the ``with`` block (resolving it) comes out pointing
    into ``text``, which is line ``line`` of ``file``."""
    try:
        yield parse(f"{prefix}{text}\n", file)
    except GestError as exc:
        raise GestError([unwrap(d, text, file, prefix, line)
                         for d in exc.diagnostics]) from None


def unwrap(d: Diagnostic, text: str, file: str, prefix: str, line: int = 1) -> Diagnostic:
    """``d`` moved from the wrapped text back onto ``text``, line ``line`` of ``file`` (a
    diagnostic about another file stays as it is)."""
    if d.pos is None or d.pos.file != file:
        return d
    return replace(d, pos=shift(d.pos, text, file, prefix, line), source_line=text)


def shift(pos: Pos | None, text: str, file: str, prefix: str, line: int = 1) -> Pos | None:
    """A position in the wrapped text moved back onto ``text``, line ``line`` of ``file``
    (one in another file, or None, as it is)."""
    if pos is None or pos.file != file:
        return pos
    column = max(1, min(pos.column - len(prefix), len(text) + 1))
    return Pos(file, line, column, pos.width)
