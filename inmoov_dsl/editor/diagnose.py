"""A text's errors and warnings as an editor shows them while it is typed (pure): what
``gestc check`` tells of the file, every error, each at its place with its hint."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from ..compiling.checking import check_program
from ..errors import Diagnostic, GestError
from ..language.library import library_dirs
from ..language.load import load


def diagnose(text: str, path: str, lib: Sequence[str] = ()) -> list[Diagnostic]:
    """Every error and warning of ``text``, the file at ``path`` (its ``use`` lines and
    its robot line read beside it; ``lib``: more gesture folders), errors first."""
    try:
        program = load(str(Path(path)), text, search=library_dirs(list(lib)))
    except GestError as exc:
        return list(exc.diagnostics)
    errors, warnings = check_program(program)
    return errors + warnings
