"""Parse .gest text into a syntax tree (stage 1 of the compiler).

The Lark LALR parser is built once per process; syntax errors become
GestError diagnostics with the position, the line and a caret.
"""

from __future__ import annotations

import functools
import hashlib
import math
import sys
import threading

from lark import Lark, Token, Transformer, UnexpectedCharacters, UnexpectedInput, v_args
from lark import __version__ as lark_version
from lark.exceptions import UnexpectedEOF, UnexpectedToken
from lark.indenter import Indenter

from . import syntax as ast
from .errors import Diagnostic, GestError, Pos
from .resources import grammar_path, private_cache_dir, private_file
from .syntax import KEYWORDS

MAX_REPEAT = 1000
MAX_DURATION = 600.0  #: s, the longest single move or wait
MAX_SOURCE = 1_000_000  #: characters in one .gest file, checked before parsing
MAX_LINE = 10_000  #: characters in one line, checked before parsing
MAX_DEPTH = 100  #: repeats within repeats
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

    def process(self, stream):
        self.style: tuple[str, int] | None = None  # the first indentation: its char, line
        return self._no_keyword_names(super().process(stream))

    def _no_keyword_names(self, tokens):
        """Where the grammar takes a name and not a keyword, the lexer makes a keyword a
        NAME (``wait: index 90``): an error here, before it means anything."""
        before = None
        for tok in tokens:
            if tok.type == "NAME" and str(tok) in KEYWORDS:
                raise _keyword_problem(tok, before, self.indent_level[-1] == 0)
            before = tok
            yield tok

    def handle_NL(self, token: Token):
        indent_str = token.rsplit("\n", 1)[1]
        if indent_str:
            self._check_style(token, indent_str)
        indent = indent_str.count(" ") + indent_str.count("\t") * self.tab_len
        if indent < self.indent_level[-1] and indent not in self.indent_level:
            raise _SyntaxProblem(
                "this line's indentation matches no enclosing block",
                _next_line_pos(token, indent_str),
                "indent each step of a block by the same amount",
            )
        yield from super().handle_NL(token)

    def _check_style(self, token: Token, indent_str: str) -> None:
        """One file indents with spaces or with tabs, never both (their widths would
        be a guess)."""
        pos = _next_line_pos(token, indent_str)
        hint = "indent with spaces only (four per level), or with tabs only"
        if " " in indent_str and "\t" in indent_str:
            raise _SyntaxProblem("this line's indentation mixes tabs and spaces",
                                 (pos[0], 1, len(indent_str)), hint)
        char = indent_str[0]
        if self.style is None:
            self.style = (char, pos[0])
        elif self.style[0] != char:
            kinds = {" ": "spaces", "\t": "tabs"}
            raise _SyntaxProblem(f"this line is indented with {kinds[char]}, line "
                                 f"{self.style[1]} with {kinds[self.style[0]]}",
                                 (pos[0], 1, len(indent_str)), hint)


def _keyword_problem(tok: Token, before: Token | None, top: bool) -> _SyntaxProblem:
    """A keyword where a name is: a definition's (what starts a line at the top level,
    or follows 'pose' or 'group'), or a reference."""
    if top and (before is None or before.type in ("_NL", "_DEDENT", "POSE", "GROUP")):
        what = {"POSE": "pose", "GROUP": "group"}.get(before.type if before else "",
                                                      "gesture")
        return _SyntaxProblem(f"'{tok}' is a keyword and cannot name a {what}",
                              _tok_tuple(tok),
                              f"choose another name (the keywords: {_KEYWORD_LIST})")
    return _SyntaxProblem(f"'{tok}' is a keyword, not a servo, group, pose or gesture",
                          _tok_tuple(tok), _KEYWORD_HINTS.get(str(tok)))


class _SyntaxProblem(Exception):
    def __init__(self, message: str, pos: tuple[int, int, int], hint: str | None = None):
        super().__init__(message)
        self.message, self.pos, self.hint = message, pos, hint


def _next_line_pos(token: Token, indent_str: str) -> tuple[int, int, int]:
    return (token.end_line or token.line, len(indent_str.expandtabs(1)) + 1, 1)


@functools.cache
def parser() -> Lark:
    """The .gest parser, built once. It builds the syntax tree's dataclasses while it
    parses (Lark's tree-less LALR mode); positions come from the tokens.

    Lark can keep the analysed grammar between runs, but it reads its cache file with
    pickle, which runs whatever the file says: the cache is kept only in this user's
    private cache directory (resources.private_cache_dir), never in the shared temp
    directory Lark would choose, and not at all when no private place can be trusted."""
    text = grammar_path().read_text(encoding="utf-8")
    return Lark(
        text,
        parser="lalr",
        lexer="contextual",
        postlex=_Indenter(),
        maybe_placeholders=False,
        transformer=_TO_AST,
        cache=_cache_file(text),
    )


def _cache_file(grammar: str) -> str | bool:
    """The private file for Lark's cache of ``grammar``, or False (no cache)."""
    where = private_cache_dir()
    if where is None:
        return False
    digest = hashlib.sha256(f"{grammar}{lark_version}{sys.version_info[:2]}".encode())
    path = where / f"gest-grammar-{digest.hexdigest()[:16]}.lark"
    return str(path) if private_file(path) else False


def _tok_pos(file: str, tok: Token) -> Pos:
    return Pos(file, tok.line, tok.column, max(1, len(str(tok))))


@v_args(inline=True)
class _ToAst(Transformer):
    """Parse-tree rules -> syntax dataclasses. ``file`` is set for each parse."""

    file = "<string>"
    depths: dict[int, int] = {}  #: id of a Repeat -> how many repeats deep it goes

    def _pos(self, tok: Token) -> Pos:
        return _tok_pos(self.file, tok)

    def start(self, *items):
        return ast.Module(self.file, tuple(items))

    def _name(self, tok: Token) -> ast.Name:
        return ast.Name(str(tok), self._pos(tok))

    def use_stmt(self, path: Token):
        return ast.Use(path[1:-1], self._pos(path))

    def group_def(self, name: Token, *members: Token):
        return ast.GroupDef(self._name(name), tuple(self._name(m) for m in members))

    def pose_def(self, name: Token, *targets: ast.Target):
        return ast.PoseDef(self._name(name), targets)

    def gesture_line(self, name: Token, step):
        return ast.GestureDef(self._name(name), (step,))

    def gesture_block(self, name: Token, *steps):
        return ast.GestureDef(self._name(name), steps)

    def repeat_block(self, count: Token, *steps):
        return self._repeat(count, steps)

    def repeat_line(self, count: Token, step):
        return self._repeat(count, (step,))

    def _repeat(self, count: Token, body: tuple) -> ast.Repeat:
        """A repeat; one inside more than MAX_DEPTH others is an error (what walks the
        tree, the formatter say, may recurse)."""
        depth = 1 + max((self.depths.get(id(s), 0) for s in body), default=0)
        if depth > MAX_DEPTH:
            raise _SyntaxProblem(f"repeats are nested more than {MAX_DEPTH} deep",
                                 _tok_tuple(count))
        node = ast.Repeat(self._count(count), body, self._pos(count))
        self.depths[id(node)] = depth
        return node

    def _count(self, tok: Token) -> int:
        text = str(tok)
        digits = text.lstrip("+-")
        # a count with more digits than MAX_REPEAT is too large before int() sees it
        if not digits.isdigit() or len(digits.lstrip("0")) > len(str(MAX_REPEAT)) \
                or not 1 <= int(text) <= MAX_REPEAT:
            raise _SyntaxProblem(f"repeat count must be a whole number from 1 to "
                                 f"{MAX_REPEAT}, got {_shown(text)}", _tok_tuple(tok))
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
            return ast.Target(self._name(name), None, None)
        text = str(value)
        number = float(text)  # inf when it has hundreds of digits
        outside = _SyntaxProblem(f"value {_shown(text)} is outside 0..180", _tok_tuple(value),
                                 "0 is straight, 180 is curled")
        if not math.isfinite(number) or abs(number) > 1e9:
            raise outside
        if number != int(number) or "." in text:
            lo, hi = int(number // 1), int(number // 1) + 1
            raise _SyntaxProblem(f"values are whole degrees, got {_shown(text)}",
                                 _tok_tuple(value), f"use {lo} or {hi}")
        if not 0 <= number <= 180:
            raise outside
        return ast.Target(self._name(name), int(number), self._pos(value))

    def duration(self, number: Token, unit: Token | None = None):
        text = str(number)
        pos = self._pos(number)
        if unit is None:
            raise _SyntaxProblem(f"the duration {_shown(text)} needs a unit",
                                 _tok_tuple(number),
                                 f"write {_shown(text)}s or {_shown(text)}ms")
        if str(unit) not in UNITS:
            raise _SyntaxProblem(f"unknown unit '{_shown(str(unit))}'", _tok_tuple(unit),
                                 f"use s or ms, as in {_shown(text)}s or {_shown(text)}ms")
        seconds = float(text) * UNITS[str(unit)]  # inf when it has hundreds of digits
        span = (number.line, number.column, len(text) + len(str(unit)))
        if not seconds > 0:
            raise _SyntaxProblem(f"a duration must be greater than 0, got {_shown(text)}{unit}",
                                 span)
        if seconds > MAX_DURATION:
            raise _SyntaxProblem(f"duration {_shown(text)}{unit} is too long (at most "
                                 f"{MAX_DURATION:g} s per step)", span,
                                 "split a long hold into several waits")
        return ast.Duration(seconds, Pos(pos.file, pos.line, pos.column, span[2]), text,
                            str(unit))


_TO_AST = _ToAst()
_LOCK = threading.Lock()  # the parser and its transformer are shared
_KEYWORD_LIST = ", ".join(sorted(KEYWORDS))
_KEYWORD_HINTS = {
    "over": "a step's timing follows its targets, without a comma: index 90 over 0.5s",
    "stagger": "a step's timing follows its targets, without a comma: "
               "index 90, middle 90 stagger 50ms",
    "wait": "a wait is a step on a line of its own: wait 0.5s",
    "hold": "a hold is a step on a line of its own: hold 0.5s",
    "repeat": "a repeat is a step on a line of its own: repeat 2: index 90",
}


def _shown(text: str, most: int = 24) -> str:
    """``text`` as a message quotes it: a long number or name is cut short."""
    return text if len(text) <= most else f"{text[:most - 12]}...{text[-6:]}"


def _tok_tuple(tok: Token) -> tuple[int, int, int]:
    return (tok.line, tok.column, max(1, len(str(tok))))


def _pos_tuple(pos: Pos) -> tuple[int, int, int]:
    return (pos.line, pos.column, pos.width)


def parse(text: str, file: str = "<string>") -> ast.Module:
    """Parse one .gest source text; raise GestError on any syntax problem. A text longer
    than MAX_SOURCE characters, or with a line longer than MAX_LINE, is refused before
    parsing."""
    size = len(text)
    if not text.endswith("\n"):
        text += "\n"
    lines = text[:-1].split("\n")  # Lark counts lines by \n only

    def fail(message: str, line: int, column: int, width: int = 1, hint: str | None = None):
        source = lines[line - 1] if 1 <= line <= len(lines) else None
        return GestError(Diagnostic("error", message, Pos(file, line, column, width), hint,
                                    source))

    if size > MAX_SOURCE:
        line = text.count("\n", 0, MAX_SOURCE) + 1
        column = MAX_SOURCE - (text.rfind("\n", 0, MAX_SOURCE) + 1) + 1
        raise fail(f"the file is longer than {MAX_SOURCE:,} characters ({size:,}): "
                   f"it is not parsed", line, column,
                   hint="split it into several files joined with 'use'")
    for number, line_text in enumerate(lines, 1):
        if len(line_text) > MAX_LINE:
            raise fail(f"this line is longer than {MAX_LINE:,} characters "
                       f"({len(line_text):,})", number, MAX_LINE + 1,
                       hint="put one step on each line; build a long pose from smaller "
                       "poses")
    try:
        with _LOCK:
            _TO_AST.file, _TO_AST.depths = file, {}
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
        char = text[exc.pos_in_stream]
        shown = f"'{char}'" if char.isprintable() else f"U+{ord(char):04X}"
        return f"unexpected character {shown}", None, 1
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
        return f"number {_shown(str(tok))}"
    if tok.type in ("NAME", "UNIT"):
        return f"name '{_shown(str(tok))}'"
    return f"'{_shown(str(tok))}'"


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
