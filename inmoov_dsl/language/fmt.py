"""The canonical layout of a .gest file (``gestc fmt``): pure, text in, text out.

The file is parsed, so only a valid file is formatted, and printed back from its
syntax tree with its comments: four spaces per block level, ``name value`` targets
joined by ``", "``, ``over``, ``stagger``, ``through`` in that order, numbers without a
sign or needless zeros (``.50s`` -> ``0.5s``), continued lines joined, trailing whitespace gone,
trailing comments two spaces after the longest line of their run, at most one blank
line where the source had blank lines, and one around every block gesture. What a
person chose is kept: ``wait`` or ``hold``, ``s`` or ``ms``, a step on the gesture's
line or under it, the comments. Formatting twice changes nothing, and the formatted
file compiles to the same bytes.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from . import syntax as ast
from .parse import parse

INDENT = "    "


@dataclass
class _Comment:
    line: int
    column: int
    text: str
    full: bool  #: alone on its line (not after code)


@dataclass
class _Node:
    """A printable line of the source (an item, a step, a block header) and its block."""

    line: int
    head: str  #: the line's code (a block header ends with ':')
    children: list[_Node] = field(default_factory=list)
    inline: bool = False  #: a block written on its header's line: ``name: step``
    trailing: str | None = None
    before: list[_Comment] = field(default_factory=list)  #: full-line comments above
    after: list[_Comment] = field(default_factory=list)  #: at the end of its block

    def last_line(self) -> int:
        lines = [self.line, *(c.line for c in self.after)]
        lines += [child.last_line() for child in self.children]
        return max(lines)

    def walk(self):
        yield self
        for child in self.children:
            yield from child.walk()

    def is_block(self) -> bool:
        """Printed over several lines: a header, then its steps indented."""
        return bool(self.children) and not self.inline

    def block_at(self, column: int, lines: list[str]) -> _Node:
        """The innermost block ending where this one ends whose steps are indented no
        deeper than ``column`` (where a comment at the end of a block belongs)."""
        node = self
        while node.children and node.children[-1].is_block() and \
                _indent(lines[node.children[-1].children[0].line - 1]) <= column:
            node = node.children[-1]
        return node


def format_source(text: str, file: str = "<string>") -> str:
    """``text`` in the canonical layout; raises GestError if it does not parse."""
    module = parse(text, file)
    lines = [row.rstrip("\r") for row in text.split("\n")]  # as the parser counts
    nodes = [_item(item) for item in module.items]
    tail = _attach(nodes, _comments(lines), lines)
    out = _Printer(lines)
    out.block(nodes, 0, tail, top=True)
    return out.text()


# -- from the syntax tree to printable nodes ---------------------------------------------
def _number(text: str) -> str:
    """A number as written, without a sign, leading zeros or needless decimals."""
    text = text.lstrip("+")
    whole, _, frac = text.partition(".")
    whole = whole.lstrip("0") or "0"
    frac = frac.rstrip("0")
    return f"{whole}.{frac}" if frac else whole


def _duration(d: ast.Duration) -> str:
    return f"{_number(d.number)}{d.unit}"


def _target(t: ast.Target) -> str:
    return t.name.text if t.value is None else f"{t.name.text} {t.value}"


def _targets(targets) -> str:
    return ", ".join(_target(t) if isinstance(t, ast.Target) else
                     ("look at " if t.what == "look" else f"{t.what} hand to ") + point(t.to)
                     for t in targets)


def point(p: ast.Point) -> str:
    """A place as the canonical layout writes it: ``(350, -200, 300) mm``, or its name."""
    numbers = ", ".join("-" * n.startswith("-") + _number(n.lstrip("+-")) for n in p.numbers)
    return p.name.text if p.name else f"({numbers}) {p.unit}".rstrip()


def _step(step: ast.Step) -> _Node:
    if isinstance(step, ast.Wait):
        return _Node(step.pos.line, f"{step.keyword} "
                     f"{_duration(step.duration)}")
    if isinstance(step, ast.Repeat):
        children = [_step(s) for s in step.body]
        inline = len(children) == 1 and children[0].line == step.pos.line
        return _Node(step.pos.line, f"repeat {step.count}:", children, inline)
    if isinstance(step, ast.Together):
        return _Node(step.pos.line, " & ".join(_move(part) for part in step.parts))
    return _Node(step.pos.line, _move(step))


def _move(step: ast.Move | ast.Say) -> str:
    if isinstance(step, ast.Say):
        return f'say "{step.text}"'
    text = _targets(step.items or step.targets)
    if step.side is not None:
        text = f"{step.side.text} {text}"
    if step.over is not None:
        text += f" over {_duration(step.over)}"
    if step.stagger is not None:
        text += f" stagger {_duration(step.stagger)}"
    if step.through is not None:
        text += " through"
    return text


def _item(item: ast.Item) -> _Node:
    if isinstance(item, ast.Robot):
        return _Node(item.pos.line, f'robot "{item.name}"' if item.is_file else
                     f"robot {item.name}")
    if isinstance(item, ast.Use):
        return _Node(item.pos.line, f'use "{item.path}"')
    if isinstance(item, ast.GroupDef):
        members = ", ".join(m.text for m in item.members)
        return _Node(item.name.pos.line, f"group {item.name.text}: {members}")
    if isinstance(item, ast.PoseDef):
        return _Node(item.name.pos.line, f"pose {item.name.text}: "
                     f"{_targets(item.targets)}")
    if isinstance(item, ast.PlaceDef):
        return _Node(item.name.pos.line, f"place {item.name.text} {point(item.point)}")
    children = [_step(s) for s in item.steps]
    inline = len(children) == 1 and children[0].line == item.name.pos.line
    return _Node(item.name.pos.line, f"{item.name.text}:", children, inline)


def _indent(line: str) -> int:
    """The column (from 1) where a line's text starts."""
    return len(line.expandtabs(8)) - len(line.expandtabs(8).lstrip()) + 1


# -- comments ----------------------------------------------------------------------------
def _comments(lines: list[str]) -> list[_Comment]:
    """Every comment: '#' outside a quoted file name, to the end of its line."""
    found = []
    for number, line in enumerate(lines, 1):
        quoted = False
        for column, char in enumerate(line):
            if char == '"':
                quoted = not quoted
            elif char == "#" and not quoted:
                found.append(_Comment(number, column + 1, line[column:].rstrip(),
                                      not line[:column].strip()))
                break
    return found


def _attach(items: list[_Node], comments: list[_Comment], lines: list[str]
            ) -> list[_Comment]:
    """Give each comment to the node it belongs to; returns those after the last item.

    A trailing comment belongs to the outermost node on its line; a full-line comment
    goes above the next node, or, when only an unindented item follows and it is
    indented, to the end of the block before it."""
    nodes = [n for item in items for n in item.walk()]
    by_line: dict[int, _Node] = {}
    for n in nodes:
        by_line.setdefault(n.line, n)
    starts = sorted(by_line)
    tail: list[_Comment] = []
    for c in comments:
        if not c.full:
            owner = max((s for s in starts if s <= c.line), default=None)
            if owner is not None:
                by_line[owner].trailing = c.text
                continue
        following = next((n for n in nodes if n.line > c.line), None)
        previous = [n for n in items if n.line < c.line]
        if c.column > 1 and previous and previous[-1].is_block() and \
                (following is None or following in items):
            previous[-1].block_at(c.column, lines).after.append(c)
        elif following is None:
            tail.append(c)
        else:
            following.before.append(c)
    return tail


# -- printing ----------------------------------------------------------------------------
@dataclass
class _Row:
    indent: int
    code: str  #: "" for a comment alone on its line
    comment: str | None
    block: int  #: rows of one block align their trailing comments


class _Printer:
    def __init__(self, source: list[str]):
        self.source = source
        self.rows: list[_Row | None] = []  # None is a blank line
        self.blocks = 0
        self.last = 0  # the source line the previous entity ended on

    def blank_since(self, first: int) -> bool:
        return any(not line.strip() for line in self.source[self.last:first - 1])

    def separate(self, first: int, force: bool = False) -> None:
        if self.rows and self.rows[-1] is not None and (force or self.blank_since(first)):
            self.rows.append(None)

    def block(self, nodes: list[_Node], depth: int, tail: list[_Comment],
              top: bool = False) -> None:
        """Print a block's nodes (and the comments at its end) at ``depth``. Blank lines
        stay where the source had some; at the top, one goes around every block."""
        self.blocks += 1
        block = self.blocks
        previous: _Node | None = None
        for node in nodes:
            force = top and previous is not None and (node.is_block() or previous.is_block())
            for c in node.before:
                self.separate(c.line, force)
                self.rows.append(_Row(depth, "", c.text, block))
                self.last = c.line
                force = False
            self.separate(node.line, force)
            self.node(node, depth, block)
            previous = node
        force = top and previous is not None and previous.is_block()
        for c in tail:
            self.separate(c.line, force)
            self.rows.append(_Row(depth, "", c.text, block))
            self.last = c.line
            force = False

    def node(self, node: _Node, depth: int, block: int) -> None:
        if node.inline:
            code, inner = node.head, node
            while inner.inline:  # name: repeat 2: index 90
                inner = inner.children[0]
                code += " " + inner.head
            comment = node.trailing or inner.trailing
            self.rows.append(_Row(depth, code, comment, block))
            self.last = node.last_line()
            return
        self.rows.append(_Row(depth, node.head, node.trailing, block))
        self.last = node.line
        if node.children:
            self.block(node.children, depth + 1, node.after)
        self.last = node.last_line()

    def text(self) -> str:
        while self.rows and self.rows[-1] is None:
            self.rows.pop()
        rows = self.rows
        column: dict[int, int] = {}
        run: list[_Row] = []
        for row in [*rows, None]:
            if row is None or not row.code or (run and row.block != run[0].block):
                commented = [r for r in run if r.comment]
                width = max((len(INDENT * r.indent + r.code) for r in commented), default=0)
                for r in commented:
                    column[id(r)] = width + 2
                run = []
            if row is not None and row.code:
                run.append(row)
        out = []
        for row in rows:
            if row is None:
                out.append("")
                continue
            code = INDENT * row.indent + row.code
            if row.comment is None:
                out.append(code)
            elif not row.code:
                out.append(INDENT * row.indent + row.comment)
            else:
                out.append(code.ljust(column[id(row)]) + row.comment)
        return "\n".join(out) + "\n" if out else ""
