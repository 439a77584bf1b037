"""Gesture code highlighted: a Pygments lexer for .gest (``pygmentize -l gest``, and
```gest blocks in Sphinx or MkDocs, through the ``pygments.lexers`` entry point), and
text coloured for a terminal (``gestc show``). Needs Pygments (the ``highlight``
extra): the package imports this module only when it colours something.

The lexer reads the terminals of ``grammar/gest.lark`` (a name, a number, a string, a
comment; a robot's profile name may hold dashes); the keywords and the units are the
language's own (``syntax.KEYWORDS``, ``tree.UNITS``), never listed here."""

from __future__ import annotations

import re

from pygments import highlight
from pygments.formatters import TerminalFormatter
from pygments.lexer import RegexLexer, bygroups, this, using
from pygments.token import Comment, Keyword, Name, Number, Operator, Punctuation, String, Whitespace

from ..language.syntax import KEYWORDS
from ..language.tree import LENGTHS, UNITS
from .text import NAME, NUMBER, PROFILE

END = r"(?![A-Za-z0-9_])"  #: a word ends here (the grammar's keywords end so)


def _either(texts) -> str:
    """A regular expression for any of ``texts`` as a whole word, longest first."""
    return "(?:" + "|".join(map(re.escape, sorted(texts, key=lambda t: (-len(t), t)))) \
        + ")" + END


KEYWORD = _either(KEYWORDS)
UNIT = _either(UNITS)
LENGTH = _either(LENGTHS)  #: a place's unit, after its ')'
SIDES = _either(("left", "right"))
ROBOT = "robot"  #: the keyword whose name may hold dashes


class GestLexer(RegexLexer):
    """The .gest language: comments, strings, keywords, numbers and their units, the
    name a gesture, pose or group line defines (``Name.Function``), the other names, the
    punctuation, and the profile a ``robot`` line names (``Name.Namespace``). A
    character the language has no place for is an ``Error`` token."""

    name = "Gest"
    aliases = ["gest"]
    filenames = ["*.gest"]
    mimetypes = ["text/x-gest"]

    tokens = {
        "root": [
            (r"[ \t]+|\r?\n", Whitespace),
            (r"\\[ \t]*\r?\n", Punctuation),  # the line goes on
            (r"#[^\n]*", Comment.Single),
            (r'"[^"\r\n]*"', String.Double),
            (rf"({ROBOT})([ \t]+)({PROFILE})", bygroups(Keyword, Whitespace, Name.Namespace)),
            # pose NAME: ... and group NAME: ...
            (rf"({KEYWORD})([ \t]+)({NAME})([ \t]*)(:)",
             bygroups(Keyword, Whitespace, Name.Function, Whitespace, Punctuation)),
            # NAME: at the start of a line: a gesture
            (rf"^(?!{KEYWORD})({NAME})([ \t]*)(:)",
             bygroups(Name.Function, Whitespace, Punctuation)),
            # right hand to, look at: words of the language only there ('hand' is a group)
            (rf"({SIDES})([ \t]+)(hand)([ \t]+)(to){END}",
             bygroups(Keyword, Whitespace, Keyword, Whitespace, Keyword)),
            (rf"(look)([ \t]+)(at){END}", bygroups(Keyword, Whitespace, Keyword)),
            (KEYWORD, Keyword),
            (rf"({NUMBER})([ \t]*)({UNIT})", bygroups(using(this), Whitespace, Keyword.Type)),
            (rf"(\))([ \t]*)({LENGTH})", bygroups(Punctuation, Whitespace, Keyword.Type)),
            (r"[+-]?(?:\d+\.\d*|\.\d+)", Number.Float),
            (r"[+-]?\d+", Number.Integer),
            (NAME, Name),
            (r"[:,()]", Punctuation),
            (r"&", Operator),
        ],
    }


def terminal(text: str) -> str:
    """``text`` (gesture code) coloured with a terminal's escape sequences."""
    return highlight(text, GestLexer(), TerminalFormatter())
