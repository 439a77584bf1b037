"""Diagnostics for people: ``file:line:col: error: message``, the line, a caret, a hint."""

from __future__ import annotations

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
        head = f"{self.severity}: {_escaped(self.message)}"
        if self.pos is not None:
            head = f"{_escaped(self.pos.file)}:{self.pos.line}:{self.pos.column}: {head}"
        lines = [head]
        if self.pos is not None and self.source_line is not None:
            text, column = _window(self.source_line.rstrip("\r\n").expandtabs(1),
                                   self.pos.column)
            # one character each, so the caret stays under its place
            text = "".join(c if c.isprintable() else "?" for c in text)
            lines.append(f"    {text}")
            width = max(1, min(self.pos.width, len(text) - column + 1, SHOWN))
            lines.append("    " + " " * (column - 1) + "^" + "~" * (width - 1))
        if self.hint:
            lines.append(f"  hint: {_escaped(self.hint)}")
        return "\n".join(lines)


def _escaped(text: str) -> str:
    """``text`` with what a terminal would not print as a character (NUL, escape
    sequences, a lone surrogate; a newline stays) written as a Python escape."""
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() or c == "\n" else
                   c.encode("unicode_escape").decode("ascii") for c in text)


SHOWN = 120  #: characters of a long source line shown around the caret


def _window(text: str, column: int) -> tuple[str, int]:
    """At most SHOWN characters of ``text`` around ``column`` (from 1), marked with
    '...' where cut, and the column in what is shown."""
    if len(text) <= SHOWN:
        return text, column
    start = max(0, min(column - 1 - SHOWN // 2, len(text) - SHOWN))
    shown = text[start:start + SHOWN]
    if start > 0:
        shown, column = "..." + shown, column - start + 3
    if start + SHOWN < len(text):
        shown += "..."
    return shown, column


class GestError(Exception):
    """Everything that stops a compile: one or more error diagnostics."""

    def __init__(self, diagnostics: Diagnostic | Iterable[Diagnostic]):
        if isinstance(diagnostics, Diagnostic):
            diagnostics = [diagnostics]
        self.diagnostics: tuple[Diagnostic, ...] = tuple(diagnostics)
        super().__init__(self.format())

    def format(self) -> str:
        """Every diagnostic, rendered, one after the other."""
        return "\n".join(d.format() for d in self.diagnostics)

    @property
    def first(self) -> Diagnostic:
        """The first diagnostic (most errors carry one)."""
        return self.diagnostics[0]


class Errors:
    """Errors gathered so that one does not hide the next: ``with errors:`` around each
    part keeps the part's GestError and goes on; ``raise_any`` raises them all, in the
    order met, each told once."""

    def __init__(self) -> None:
        self.found: list[Diagnostic] = []
        self._told: set[Diagnostic] = set()  # found's, looked up at once

    def __enter__(self) -> Errors:
        return self

    def __exit__(self, kind, exc, tb) -> bool:
        if isinstance(exc, GestError):
            for d in exc.diagnostics:
                if d not in self._told:
                    self._told.add(d)
                    self.found.append(d)
            return True
        return False

    def raise_any(self) -> None:
        """Raise every error gathered as one GestError, if there is any."""
        if self.found:
            raise GestError(self.found)


class SourceMap:
    """The text of every file read in one compile, so a diagnostic can show its line."""

    def __init__(self) -> None:
        self._texts: dict[str, list[str]] = {}

    def add(self, file: str, text: str) -> None:
        """Keep the text of ``file``."""
        self._texts[file] = text.split("\n")  # lines as the parser counts them

    def line(self, pos: Pos | None) -> str | None:
        """The source line at ``pos``, or None when the file or line is unknown."""
        if pos is None:
            return None
        lines = self._texts.get(pos.file)
        if lines is None or not 1 <= pos.line <= len(lines):
            return None
        return lines[pos.line - 1]

    def error(self, message: str, pos: Pos | None, hint: str | None = None) -> Diagnostic:
        """An error at ``pos``, with its source line."""
        return Diagnostic("error", message, pos, hint, self.line(pos))

    def warning(self, message: str, pos: Pos | None, hint: str | None = None) -> Diagnostic:
        """A warning at ``pos``, with its source line."""
        return Diagnostic("warning", message, pos, hint, self.line(pos))


MAX_SUGGESTED = 64  #: characters; longer names get no 'did you mean'


def counted(n: int, noun: str) -> str:
    """``n`` and its noun, as a message says it: ``1 byte``, ``1,029 bytes``."""
    return f"{n:,} {noun}{'' if n == 1 else 's'}"


def did_you_mean(name: str, known: Iterable[str]) -> str | None:
    """A 'did you mean' hint for a misspelt name, or None when nothing is close."""
    meant = closest(name, known)
    return f"did you mean '{meant}'?" if meant is not None else None


def closest(name: str, known: Iterable[str]) -> str | None:
    """The known name closest to a misspelt ``name``, or None when nothing is close.
    Names longer than MAX_SUGGESTED are not compared (difflib is quadratic in length)."""
    if len(name) > MAX_SUGGESTED:
        return None
    candidates = sorted({k for k in known if len(k) <= MAX_SUGGESTED})
    import difflib  # here: only a mistake needs it (start-up time)

    close = difflib.get_close_matches(name, candidates, n=1, cutoff=0.6)
    return close[0] if close else None


def decode_utf8(data: bytes, file: str) -> str:
    """``data`` as UTF-8 text, with newlines as Python reads a text file (``\r\n`` and
    ``\r`` become ``\n``) and without the byte-order mark some editors (Notepad) write
    at the start; bytes that are not UTF-8 are a GestError at their place. A BOM
    elsewhere is text (U+FEFF), left for the parser to refuse."""
    bom = 3 if data.startswith(b"\xef\xbb\xbf") else 0
    try:
        text = data[bom:].decode("utf-8")
    except UnicodeDecodeError as exc:
        start = exc.start + bom  # in data
        line_start = max(data.rfind(b"\n", 0, start) + 1, bom)
        line = data.count(b"\n", 0, start) + 1
        column = len(data[line_start:start].decode("utf-8", "replace")) + 1
        line_end = data.find(b"\n", start)
        shown = data[line_start:line_end if line_end >= 0 else len(data)]
        raise GestError(Diagnostic(
            "error", f"this file is not UTF-8 text: {exc.reason} (byte "
            f"0x{data[start]:02x})", Pos(file, line, column),
            "save it as UTF-8", shown.decode("utf-8", "replace"))) from None
    return text.replace("\r\n", "\n").replace("\r", "\n")
