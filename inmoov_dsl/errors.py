"""Diagnostics for people: ``file:line:col: error: message``, the line, a caret, a hint."""

from __future__ import annotations

import difflib
from collections.abc import Iterable
from dataclasses import dataclass


@dataclass(frozen=True)
class Pos:
    """A place in a source file; line and column count from 1."""

    file: str
    line: int
    column: int
    width: int = 1  #: characters the caret underlines


@dataclass(frozen=True)
class Diagnostic:
    """One error or warning, with where it is and what might fix it."""

    severity: str  #: "error" or "warning"
    message: str
    pos: Pos | None = None
    hint: str | None = None
    source_line: str | None = None

    def format(self) -> str:
        """Render like a compiler: location, message, the source line, a caret, a hint."""
        head = f"{self.severity}: {self.message}"
        if self.pos is not None:
            head = f"{self.pos.file}:{self.pos.line}:{self.pos.column}: {head}"
        lines = [head]
        if self.pos is not None and self.source_line is not None:
            text = self.source_line.rstrip("\r\n").expandtabs(1)
            lines.append(f"    {text}")
            width = max(1, min(self.pos.width, len(text) - self.pos.column + 1))
            lines.append("    " + " " * (self.pos.column - 1) + "^" + "~" * (width - 1))
        if self.hint:
            lines.append(f"  hint: {self.hint}")
        return "\n".join(lines)


class GestError(Exception):
    """Everything that stops a compile: one or more error diagnostics."""

    def __init__(self, diagnostics: Diagnostic | Iterable[Diagnostic]):
        if isinstance(diagnostics, Diagnostic):
            diagnostics = [diagnostics]
        self.diagnostics: tuple[Diagnostic, ...] = tuple(diagnostics)
        super().__init__(self.format())

    def format(self) -> str:
        return "\n".join(d.format() for d in self.diagnostics)

    @property
    def first(self) -> Diagnostic:
        return self.diagnostics[0]


class SourceMap:
    """The text of every file read in one compile, so a diagnostic can show its line."""

    def __init__(self) -> None:
        self._texts: dict[str, list[str]] = {}

    def add(self, file: str, text: str) -> None:
        self._texts[file] = text.splitlines()

    def line(self, pos: Pos | None) -> str | None:
        if pos is None:
            return None
        lines = self._texts.get(pos.file)
        if lines is None or not 1 <= pos.line <= len(lines):
            return None
        return lines[pos.line - 1]

    def error(self, message: str, pos: Pos | None, hint: str | None = None) -> Diagnostic:
        return Diagnostic("error", message, pos, hint, self.line(pos))

    def warning(self, message: str, pos: Pos | None, hint: str | None = None) -> Diagnostic:
        return Diagnostic("warning", message, pos, hint, self.line(pos))


def did_you_mean(name: str, known: Iterable[str]) -> str | None:
    """A 'did you mean' hint for a misspelt name, or None when nothing is close."""
    close = difflib.get_close_matches(name, sorted(set(known)), n=1, cutoff=0.6)
    return f"did you mean '{close[0]}'?" if close else None
