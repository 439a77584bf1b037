"""Parse .gest text into a syntax tree (stage 1 of the compiler).

The Lark LALR parser is built once per process; syntax errors become
GestError diagnostics with the position, the line and a caret.
"""

from __future__ import annotations

import functools
import threading

from lark import Lark, Token, Transformer, UnexpectedCharacters, UnexpectedInput, v_args
from lark.exceptions import UnexpectedEOF, UnexpectedToken
from lark.indenter import Indenter

from . import syntax as ast
from .errors import Diagnostic, GestError, Pos
from .resources import grammar_path

MAX_REPEAT = 1000
MAX_DURATION = 600.0  #: s, the longest single move or wait
UNITS = {"s": 1.0, "ms": 0.001}

_WORDS = {
    "NAME": "a name",
    "NUMBER": "a number",
    "UNIT": "a unit (s or ms)",
    "STRING": 'a file name in quotes ("other.gest")',
    "_NL": "the end of the line",
    "_INDENT": "an indented line",
    "_DEDENT": "the end of the indented block",
    "COMMA": "','",
    "COLON": "':'",
    "$END": "the end of the file",
}


class _Indenter(Indenter):
    NL_type = "_NL"
    OPEN_PAREN_types: list[str] = []
    CLOSE_PAREN_types: list[str] = []
    INDENT_type = "_INDENT"
    DEDENT_type = "_DEDENT"
    tab_len = 8

    def handle_NL(self, token: Token):
        indent_str = token.rsplit("\n", 1)[1]
        indent = indent_str.count(" ") + indent_str.count("\t") * self.tab_len
        if indent < self.indent_level[-1] and indent not in self.indent_level:
            raise _SyntaxProblem(
                "this line's indentation matches no enclosing block",
                _next_line_pos(token, indent_str),
                "indent each step of a block by the same amount",
            )
        yield from super().handle_NL(token)


class _SyntaxProblem(Exception):
    def __init__(self, message: str, pos: tuple[int, int, int], hint: str | None = None):
        super().__init__(message)
        self.message, self.pos, self.hint = message, pos, hint


def _next_line_pos(token: Token, indent_str: str) -> tuple[int, int, int]:
    return (token.end_line or token.line, len(indent_str.expandtabs(1)) + 1, 1)


@functools.cache
def parser() -> Lark:
    """The .gest parser, built once. It builds the syntax tree's dataclasses while it
    parses (Lark's tree-less LALR mode); positions come from the tokens."""
    return Lark(
        grammar_path().read_text(encoding="utf-8"),
        parser="lalr",
        lexer="contextual",
        postlex=_Indenter(),
        maybe_placeholders=False,
        transformer=_TO_AST,
        cache=True,  # Lark keeps the analysed grammar in the temp dir between runs
    )


def _tok_pos(file: str, tok: Token) -> Pos:
    return Pos(file, tok.line, tok.column, max(1, len(str(tok))))


@v_args(inline=True)
class _ToAst(Transformer):
    """Parse-tree rules -> syntax dataclasses. ``file`` is set for each parse."""

    file = "<string>"

    def pos(self, tok: Token) -> Pos:
        return _tok_pos(self.file, tok)

    def start(self, *items):
        return ast.Module(self.file, tuple(items))

    def use_stmt(self, path: Token):
        return ast.Use(path[1:-1], self.pos(path))

    def group_def(self, name: Token, *members: Token):
        return ast.GroupDef(ast.Name(str(name), self.pos(name)),
                            tuple(ast.Name(str(m), self.pos(m)) for m in members))

    def pose_def(self, name: Token, *targets: ast.Target):
        return ast.PoseDef(ast.Name(str(name), self.pos(name)), targets)

    def gesture_line(self, name: Token, step):
        return ast.GestureDef(ast.Name(str(name), self.pos(name)), (step,))

    def gesture_block(self, name: Token, *steps):
        return ast.GestureDef(ast.Name(str(name), self.pos(name)), steps)

    def repeat_block(self, count: Token, *steps):
        return ast.Repeat(self._count(count), steps, self.pos(count))

    def repeat_line(self, count: Token, step):
        return ast.Repeat(self._count(count), (step,), self.pos(count))

    def _count(self, tok: Token) -> int:
        text = str(tok)
        if not text.lstrip("+-").isdigit() or not 1 <= int(text) <= MAX_REPEAT:
            raise _SyntaxProblem(f"repeat count must be a whole number from 1 to "
                                 f"{MAX_REPEAT}, got {text}", _tok_tuple(tok))
        return int(text)

    def wait(self, duration: ast.Duration):
        return ast.Wait(duration, duration.pos, "wait")

    def hold(self, duration: ast.Duration):
        return ast.Wait(duration, duration.pos, "hold")

    def move(self, *parts):
        targets = tuple(p for p in parts if isinstance(p, ast.Target))
        over = stagger = None
        for kind, duration in (p for p in parts if isinstance(p, tuple)):
            if kind == "over":
                if over is not None:
                    raise _SyntaxProblem("'over' is given twice in this step",
                                         _pos_tuple(duration.pos))
                over = duration
            else:
                if stagger is not None:
                    raise _SyntaxProblem("'stagger' is given twice in this step",
                                         _pos_tuple(duration.pos))
                stagger = duration
        return ast.Move(targets, over, stagger, targets[0].name.pos)

    def over(self, duration: ast.Duration):
        return ("over", duration)

    def stagger(self, duration: ast.Duration):
        return ("stagger", duration)

    def target(self, name: Token, value: Token | None = None):
        if value is None:
            return ast.Target(ast.Name(str(name), self.pos(name)), None, None)
        text = str(value)
        number = float(text)
        if number != int(number) or "." in text:
            lo, hi = int(number // 1), int(number // 1) + 1
            raise _SyntaxProblem(f"values are whole degrees, got {text}", _tok_tuple(value),
                                 f"use {lo} or {hi}")
        if not 0 <= number <= 180:
            raise _SyntaxProblem(f"value {text} is outside 0..180", _tok_tuple(value),
                                 "0 is straight, 180 is curled")
        return ast.Target(ast.Name(str(name), self.pos(name)), int(number), self.pos(value))

    def duration(self, number: Token, unit: Token | None = None):
        text = str(number)
        pos = self.pos(number)
        if unit is None:
            raise _SyntaxProblem(f"the duration {text} needs a unit", _tok_tuple(number),
                                 f"write {text}s or {text}ms")
        if str(unit) not in UNITS:
            raise _SyntaxProblem(f"unknown unit '{unit}'", _tok_tuple(unit),
                                 f"use s or ms, as in {text}s or {text}ms")
        seconds = float(text) * UNITS[str(unit)]
        span = (number.line, number.column, len(text) + len(str(unit)))
        if not seconds > 0:
            raise _SyntaxProblem(f"a duration must be greater than 0, got {text}{unit}", span)
        if seconds > MAX_DURATION:
            raise _SyntaxProblem(f"duration {text}{unit} is too long (at most "
                                 f"{MAX_DURATION:g} s per step)", span,
                                 "split a long hold into several waits")
        return ast.Duration(seconds, Pos(pos.file, pos.line, pos.column, span[2]), text,
                            str(unit))


_TO_AST = _ToAst()
_LOCK = threading.Lock()  # the parser and its transformer are shared


def _tok_tuple(tok: Token) -> tuple[int, int, int]:
    return (tok.line, tok.column, max(1, len(str(tok))))


def _pos_tuple(pos: Pos) -> tuple[int, int, int]:
    return (pos.line, pos.column, pos.width)


def parse(text: str, file: str = "<string>") -> ast.Module:
    """Parse one .gest source text; raise GestError on any syntax problem."""
    if not text.endswith("\n"):
        text += "\n"
    lines = text.splitlines()

    def fail(message: str, line: int, column: int, width: int = 1, hint: str | None = None):
        source = lines[line - 1] if 1 <= line <= len(lines) else None
        return GestError(Diagnostic("error", message, Pos(file, line, column, width), hint,
                                    source))

    try:
        with _LOCK:
            _TO_AST.file = file
            return parser().parse(text)
    except _SyntaxProblem as problem:  # tree-less mode: callbacks' exceptions come as they are
        raise fail(problem.message, *problem.pos, hint=problem.hint) from None
    except UnexpectedInput as exc:
        message, hint, width = _explain(exc, text)
        line, column = max(1, exc.line), max(1, exc.column)
        token = getattr(exc, "token", None)
        if token is not None and token.type in ("_INDENT", "_DEDENT"):
            # the indenter's tokens borrow the newline's position: point at the next line
            line = token.end_line or token.line + 1
            column = len(str(token).expandtabs(1)) + 1
        elif isinstance(exc, UnexpectedEOF) or exc.line < 0:
            line, column = len(lines), len(lines[-1]) + 1 if lines else 1
        raise fail(message, line, column, width, hint) from None


def _explain(exc: UnexpectedInput, text: str) -> tuple[str, str | None, int]:
    """A sentence for a syntax error: what was found, what was expected, a hint."""
    if isinstance(exc, UnexpectedCharacters):
        return f"unexpected character '{text[exc.pos_in_stream]}'", None, 1
    if isinstance(exc, UnexpectedToken):
        tok = exc.token
        expected = sorted(exc.accepts or exc.expected)
        found = _describe(tok)
        layout = tok.type in ("_NL", "_INDENT", "_DEDENT", "$END")
        width = 1 if layout else max(1, len(str(tok)))
        hint = _hint(tok, set(expected))
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
        return f"number {tok}"
    if tok.type in ("NAME", "UNIT"):
        return f"name '{tok}'"
    return f"'{tok}'"


def _hint(tok: Token, expected: set[str]) -> str | None:
    if "COMMA" in expected and tok.type == "NAME":
        return "separate the servos of a step with ',': index 90, middle 90"
    if "COLON" in expected and tok.type in ("NAME", "NUMBER"):
        return "a gesture starts with its name and ':', as in  peace: index 180"
    if expected == {"NUMBER"}:
        return "durations are written 0.4s or 400ms"
    if expected == {"_INDENT"}:
        return "indent the steps under the gesture's name, or write them after ':'"
    if tok.type == "_INDENT":
        return "only the steps under 'name:' or 'repeat N:' are indented"
    return None


def _or(words: list[str]) -> str:
    words = list(dict.fromkeys(words))
    if len(words) <= 1:
        return words[0] if words else "something else"
    return ", ".join(words[:-1]) + " or " + words[-1]
