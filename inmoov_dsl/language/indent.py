"""The indentation of a .gest file, for the parser: Lark's indenter (blocks from
indentation), which also refuses mixed indentation and keywords where a name is."""

from __future__ import annotations

import re
from collections.abc import Iterator

from lark import Token
from lark.indenter import Indenter

from .parse_errors import Span, SyntaxProblem, keyword_problem
from .syntax import KEYWORDS

#: the line a message about mixed indentation names (moved with the text it is about)
STYLE_LINE = re.compile(r"(, line )(\d+)( with (?:spaces|tabs))")


class GestIndenter(Indenter):
    """Lark's indenter, which also refuses mixed indentation and keywords as names."""

    NL_type = "_NL"
    OPEN_PAREN_types: list[str] = []
    CLOSE_PAREN_types: list[str] = []
    INDENT_type = "_INDENT"
    DEDENT_type = "_DEDENT"
    tab_len = 8

    def process(self, stream: Iterator[Token]) -> Iterator[Token]:
        """The tokens of a file, with its blocks' INDENT and DEDENT."""
        self.style: tuple[str, int] | None = None  # the first indentation: its char, line
        return self._no_keyword_names(super().process(stream))

    def _no_keyword_names(self, tokens: Iterator[Token]) -> Iterator[Token]:
        """Where the grammar takes a name and not a keyword, the lexer makes a keyword a
        NAME (``wait: index 90``): an error here, before it means anything."""
        before = None
        for tok in tokens:
            if tok.type == "NAME" and str(tok) in KEYWORDS:
                raise keyword_problem(tok, before, self.indent_level[-1] == 0)
            before = tok
            yield tok

    def handle_NL(self, token: Token) -> Iterator[Token]:
        """A newline and the indentation after it: the same style throughout, and a
        level that some enclosing block has."""
        indent_str = token.rsplit("\n", 1)[1]
        if indent_str:
            self._check_style(token, indent_str)
        indent = indent_str.count(" ") + indent_str.count("\t") * self.tab_len
        if indent < self.indent_level[-1] and indent not in self.indent_level:
            raise SyntaxProblem(
                "this line's indentation matches no enclosing block",
                _next_line_pos(token, indent_str),
                "indent each step of a block by the same amount",
            )
        yield from super().handle_NL(token)

    def _check_style(self, token: Token, indent_str: str) -> None:
        """One file indents with spaces or with tabs, never both (widths would be guesses)."""
        pos = _next_line_pos(token, indent_str)
        hint = "indent with spaces only (four per level), or with tabs only"
        if " " in indent_str and "\t" in indent_str:
            raise SyntaxProblem("this line's indentation mixes tabs and spaces",
                                (pos[0], 1, len(indent_str)), hint)
        char = indent_str[0]
        if self.style is None:
            self.style = (char, pos[0])
        elif self.style[0] != char:
            kinds = {" ": "spaces", "\t": "tabs"}
            raise SyntaxProblem(f"this line is indented with {kinds[char]}, line "
                                f"{self.style[1]} with {kinds[self.style[0]]}",
                                (pos[0], 1, len(indent_str)), hint)


def _next_line_pos(token: Token, indent_str: str) -> Span:
    """The start of the line after the newline ``token``, indented by ``indent_str``."""
    return (token.end_line or token.line, len(indent_str.expandtabs(1)) + 1, 1)
