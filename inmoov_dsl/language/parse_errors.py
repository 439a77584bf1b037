"""What the parser says about a syntax error: Lark's errors and our own, in words.

A ``SyntaxProblem`` is raised while parsing (by the indenter, the AST builder, or
from a Lark ``UnexpectedInput`` through ``lark_problem``); ``parse`` turns it into a
GestError with the line and a caret.
"""

from __future__ import annotations

import re

from lark import Token, UnexpectedCharacters, UnexpectedInput
from lark.exceptions import UnexpectedEOF, UnexpectedToken

from ..errors import Diagnostic, GestError, Pos, did_you_mean
from .syntax import KEYWORDS

Span = tuple[int, int, int]  #: line, column (from 1) and width of what is wrong

_WORDS = {
    "NAME": "a name",
    "ROBOT_NAME": "a robot's profile (rhand, inmoov)",
    "NUMBER": "a number",
    "UNIT": "a unit (s or ms)",
    "STRING": 'a file name in quotes ("other.gest")',
    "_NL": "the end of the line",
    "_INDENT": "an indented line",
    "_DEDENT": "the end of the indented block",
    "AMPERSAND": "'&'",
    "COMMA": "','",
    "COLON": "':'",
    "SIDE": "'left', 'right'",
    "$END": "the end of the file",
}
_KEYWORD_LIST = ", ".join(sorted(KEYWORDS))
_KEYWORD_HINTS = {
    "over": "a step's timing follows its targets, without a comma: index 90 over 0.5s",
    "stagger": "a step's timing follows its targets, without a comma: "
               "index 90, middle 90 stagger 50ms",
    "wait": "a wait is a step on a line of its own: wait 0.5s",
    "hold": "a hold is a step on a line of its own: hold 0.5s",
    "repeat": "a repeat is a step on a line of its own: repeat 2: index 90",
}


class SyntaxProblem(Exception):
    """A syntax error at ``pos`` (line, column, width) of the text being parsed."""

    def __init__(self, message: str, pos: Span, hint: str | None = None):
        super().__init__(message)
        self.message, self.pos, self.hint = message, pos, hint

    def error(self, file: str, lines: list[str]) -> GestError:
        """The GestError for ``file``, whose lines are ``lines``."""
        line, column, width = self.pos
        source = lines[line - 1] if 1 <= line <= len(lines) else None
        return GestError(Diagnostic("error", self.message, Pos(file, line, column, width),
                                    self.hint, source))


def shown(text: str, most: int = 24) -> str:
    """``text`` as a message quotes it: a long number or name is cut short."""
    return text if len(text) <= most else f"{text[:most - 12]}...{text[-6:]}"


def tok_span(tok: Token) -> Span:
    """Where ``tok`` is."""
    return (tok.line, tok.column, max(1, len(str(tok))))


def pos_span(pos: Pos) -> Span:
    """Where ``pos`` is."""
    return (pos.line, pos.column, pos.width)


def keyword_problem(tok: Token, before: Token | None, top: bool) -> SyntaxProblem:
    """A keyword where a name is: a definition's (what starts a line at the top level,
    or follows 'pose' or 'group'), or a reference."""
    if top and (before is None or before.type in ("_NL", "_DEDENT", "POSE", "GROUP")):
        what = {"POSE": "pose", "GROUP": "group"}.get(before.type if before else "",
                                                      "gesture")
        return SyntaxProblem(f"'{tok}' is a keyword and cannot name a {what}", tok_span(tok),
                             f"choose another name (the keywords: {_KEYWORD_LIST})")
    return SyntaxProblem(f"'{tok}' is a keyword, not a servo, group, pose or gesture",
                         tok_span(tok), _KEYWORD_HINTS.get(str(tok)))


def lark_problem(exc: UnexpectedInput, text: str, lines: list[str]) -> SyntaxProblem:
    """Lark's ``exc`` about ``text`` (whose lines are ``lines``) in words, at its place:
    a layout token at the line it starts, the end of the file after its last line."""
    message, hint, width = _explain(exc, text)
    line, column = max(1, exc.line), max(1, exc.column)
    token = getattr(exc, "token", None)
    if token is not None and token.type in ("_INDENT", "_DEDENT"):
        # the indenter's tokens borrow the newline's position: point at the next line
        line = token.end_line or token.line + 1
        column = len(str(token).expandtabs(1)) + 1
    elif isinstance(exc, UnexpectedEOF) or exc.line < 0:
        line, column = len(lines), len(lines[-1]) + 1 if lines else 1
    return SyntaxProblem(message, (line, column, width), hint)


def _explain(exc: UnexpectedInput, text: str) -> tuple[str, str | None, int]:
    """A sentence for a syntax error: what was found, what was expected, a hint."""
    if isinstance(exc, UnexpectedCharacters):
        char = text[exc.pos_in_stream]
        quoted = f"'{char}'" if char.isprintable() else f"U+{ord(char):04X}"
        hint = _file_name(text, exc.pos_in_stream) or _CHAR_HINTS.get(char)
        return f"unexpected character {quoted}", hint, 1
    if isinstance(exc, UnexpectedToken):
        tok = exc.token
        expected = sorted(exc.accepts or exc.expected)
        found = _describe(tok)
        layout = tok.type in ("_NL", "_INDENT", "_DEDENT", "$END")
        width = 1 if layout else max(1, len(str(tok)))
        hint = _misspelt(tok, set(expected)) or _step_keyword(text, exc.line) or \
            _hint(tok, set(expected), _word_before(text, tok)) or \
            _colon(tok, set(expected), text, exc.line)
        wanted = _or([_WORDS.get(e, f"'{e.lower()}'") for e in expected if e in _WORDS or
                      e.isupper()])
        return f"unexpected {found}; expected {wanted}", hint, width
    return "syntax error", None, 1


def _describe(tok: Token) -> str:
    if tok.type == "_NL":
        return "end of line"
    if tok.type == "$END":
        return "end of the file"
    if tok.type in ("_INDENT",):
        return "indentation"
    if tok.type == "_DEDENT":
        return "end of block"
    if tok.type == "NUMBER":
        return f"number {shown(str(tok))}"
    if tok.type in ("NAME", "UNIT"):
        return f"name '{shown(str(tok))}'"
    return f"'{shown(str(tok))}'"


def _misspelt(tok: Token, expected: set[str]) -> str | None:
    """'did you mean' for a name close to a keyword the grammar expects here."""
    keywords = {e.lower() for e in expected} & KEYWORDS
    return did_you_mean(str(tok), keywords) if tok.type == "NAME" else None


def _word_before(text: str, tok: Token) -> str:
    """The word right before ``tok`` on its line ('' at the line's start)."""
    start = tok.start_pos if tok.start_pos is not None else 0
    words = text[:start].rsplit("\n", 1)[-1].split()
    return words[-1] if words else ""


def _hint(tok: Token, expected: set[str], before: str = "") -> str | None:
    if "COMMA" in expected and tok.type == "NAME":
        return "separate the servos of a step with ',': index 90, middle 90"
    if "COLON" in expected and tok.type in ("NAME", "NUMBER"):
        return "a gesture starts with its name and ':', as in  peace: index 180"

    if expected == {"NUMBER"} and before == "repeat":
        return "repeat takes how many times: repeat 3:"
    if expected == {"NUMBER"}:
        return "durations are written 0.4s or 400ms"
    if expected == {"_INDENT"}:
        return "indent the steps under the gesture's name, or write them after ':'"
    if tok.type == "_INDENT":
        return "only the steps under 'name:' or 'repeat N:' are indented"
    return None


def _colon(tok: Token, expected: set[str], text: str, line: int) -> str | None:
    """A hint when a line ends where its name wants a ':' (``peace`` with its steps
    below, ``group pair``)."""
    if expected != {"COLON"} or tok.type != "_NL":
        return None
    lines = text.split("\n")
    first = lines[line - 1].split()[0] if 1 <= line <= len(lines) and lines[line - 1].split() \
        else ""
    return {"group": "end the group's name with ':', then its servos: group pair: index, "
                     "middle",
            "pose": "end the pose's name with ':', then its targets: pose open: fingers 0",
            "repeat": "end 'repeat N' with ':', then the steps it repeats"}.get(
        first, "end the gesture's name with ':', then its steps after it or on the lines "
               "below, indented")


_CHAR_HINTS = {
    "=": "a servo and its value are separated by a space: index 90",
}
_FILE_NAME = r"([A-Za-z_][\w-]*)\.gest\b"  # patterns compiled when a mistake needs them


def _file_name(text: str, at: int) -> str | None:
    """A hint when the '.' at ``at`` is in a file name (``peace.gest``) where a step
    names a gesture."""
    start, end = text.rfind("\n", 0, at) + 1, text.find("\n", at)
    for found in re.finditer(_FILE_NAME, text[start:len(text) if end < 0 else end]):
        found_at = start + found.start(), start + found.end()
        if found_at[0] < at < found_at[1]:
            return f"a step names a gesture, not its file: {found[1]}"
    return None


_STEP_START = r"\s*(?:[A-Za-z_]\w*\s*:\s*)?([A-Za-z_]\w*)\s+\d"
_STEP_KEYWORDS = ("wait", "hold", "repeat")  #: the keywords a step starts with, then a number


def _step_keyword(text: str, line: int) -> str | None:
    """A hint when the step on ``line`` starts with a misspelt keyword (``wiat 1s``,
    read as a servo and its value until the unit)."""
    lines = text.split("\n")
    found = re.match(_STEP_START, lines[line - 1]) if 1 <= line <= len(lines) else None
    if found is None or found[1] in KEYWORDS:
        return None
    return did_you_mean(found[1], _STEP_KEYWORDS)


def _or(words: list[str]) -> str:
    words = list(dict.fromkeys(words))
    if len(words) <= 1:
        return words[0] if words else "something else"
    return ", ".join(words[:-1]) + " or " + words[-1]
