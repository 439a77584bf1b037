"""What an editor's server remembers between two versions of a text, so that an edit
costs what it touches (pure): the blocks parsed (``language.incremental``) and each
gesture checked, kept for as long as the text it depends on stays the same (the
gesture's block, the blocks of the names it uses, the robot and ``use`` lines, the
files used), wherever that text moves in the file."""

from __future__ import annotations

import bisect
import dataclasses
from collections.abc import Callable
from dataclasses import dataclass

from ..compiling.checking import Checked, check_gesture, checkable
from ..compiling.plan import Plan
from ..errors import Diagnostic, Pos, SourceMap
from ..hardware import Profile
from ..language.incremental import BlockParser, copied, defines, spans
from ..language.program import Program
from .lines import compiler_rows
from .text import WORD, code

Key = tuple  #: what a gesture's check depends on
#: a plan's further check (the robot's parts against each other): its warnings;
#: ``step`` as ``Memo.check``'s
PlanCheck = Callable[[Plan, SourceMap, Callable[[], None] | None], tuple[Diagnostic, ...]]


@dataclass(frozen=True)
class _Kept:
    checked: Checked
    starts: tuple[int, ...]  #: 0-based first line of each block the key holds
    sizes: tuple[int, ...]  #: lines of each
    names: frozenset[str] | None  #: the program's names, when its errors' hints read them
    touched: bool = False  #: ``checked`` has its plan's further check (``Memo.touch``)


class Memo:
    """The blocks and the checks of the last texts analysed."""

    def __init__(self) -> None:
        self.blocks = BlockParser()
        self.checks: dict[Key, _Kept] = {}
        self.last: list[tuple[str, Key, Checked]] = []  #: the last whole check's
        self.words: dict[str, frozenset[str]] = {}  #: a block's text -> the words it writes

    def parse(self, text: str, file: str):
        """``parse.parse``, remembering blocks."""
        return self.blocks.parse(text, file)

    def check(self, program: Program, profile: Profile, path: str,
              step: Callable[[], None] | None = None) -> list[tuple[str, Checked]]:
        """``check_gesture`` of every gesture of the file at ``path`` that can be
        checked (``checkable``), each again only when what it depends on changed.
        ``step`` is called before each gesture: what it raises stops the check, and
        the gestures checked so far are kept for the next."""
        lines = list(compiler_rows(program.texts[path]))
        found = spans(lines)
        starts = [s for s, _ in found]
        here = {n: p.line - 1 for n, p in program.names().items() if p.file == path}
        block_of = {n: bisect.bisect_right(starts, line) - 1 for n, line in here.items()}
        head = [k for k, (s, _) in enumerate(found) if defines(lines[s]) == "*"]
        others = tuple(sorted((f, hash(t)) for f, t in program.texts.items() if f != path))
        names = frozenset(program.names())
        kept: dict[Key, _Kept] = {}
        out, last = [], []
        graph = _Graph(found, lines, block_of, head, self.words)
        try:
            for gesture in checkable(program):
                if step is not None:
                    step()
                deps = graph.depends(block_of[gesture])
                key = (gesture, profile.name, profile.sha256, others,
                       tuple("\n".join(lines[found[k][0]:found[k][1]]) for k in deps))
                checked = self._checked(key, kept, program, gesture, profile, path, names,
                                        tuple(found[k][0] for k in deps),
                                        tuple(found[k][1] - found[k][0] for k in deps))
                out.append((gesture, checked))
                last.append((gesture, key, checked))
        except BaseException:
            self.checks.update(kept)  # cut short: what was checked is kept all the same
            self.words.update(graph.words)
            raise
        self.checks, self.last, self.words = kept, last, graph.words
        return out

    def touch(self, program: Program, check: PlanCheck,
              step: Callable[[], None] | None = None) -> list[tuple[str, Checked]]:
        """The gestures of the last whole ``check`` (of ``program``), each that has a
        plan with ``check``'s warnings added (to its plan's too), made again only when
        its check was. ``step`` as ``check``'s (it is handed to ``check`` too)."""
        out = []
        for gesture, key, checked in self.last:
            kept = self.checks.get(key)
            if kept is not None and kept.touched:
                out.append((gesture, kept.checked))
                continue
            checked = kept.checked if kept is not None else checked
            if checked.plan is not None:
                if step is not None:
                    step()
                if found := check(checked.plan, program.sources, step):
                    plan = copied(checked.plan, warnings=checked.plan.warnings + found)
                    checked = Checked(checked.errors, checked.warnings + found, plan)
            if kept is not None:
                self.checks[key] = dataclasses.replace(kept, checked=checked, touched=True)
            out.append((gesture, checked))
        return out

    def _checked(self, key: Key, kept: dict[Key, _Kept], program: Program, gesture: str,
                 profile: Profile, path: str, names: frozenset[str],
                 now: tuple[int, ...], sizes: tuple[int, ...]) -> Checked:
        """The check of ``gesture`` (its blocks at ``now``, of ``sizes`` lines): kept
        (moved with its blocks), or made and kept in ``kept``."""
        was = self.checks.get(key) or kept.get(key)
        if was is not None and was.names not in (None, names):
            was = None
        if was is None:
            checked = check_gesture(program, gesture, profile)
            if not _within(checked, path, now, sizes):
                return checked  # a place outside its blocks: not kept
            was = _Kept(checked, now, sizes, names if checked.errors else None)
        elif was.starts != now:
            was = dataclasses.replace(was, checked=_moved(was, now, path), starts=now)
        kept[key] = was
        return was.checked


class _Graph:
    """Which blocks each block's words name (the blocks that define them), each block
    read once."""

    def __init__(self, found: list[tuple[int, int]], lines: list[str],
                 block_of: dict[str, int], head: list[int],
                 known: dict[str, frozenset[str]]):
        self.found, self.lines, self.block_of, self.head = found, lines, block_of, head
        self.named: dict[int, set[int]] = {}
        self.known = known  #: a block's text -> its words, from the texts before
        self.words: dict[str, frozenset[str]] = {}  #: this text's blocks' (read or known)

    def names(self, block: int) -> set[int]:
        """The blocks the words of ``block`` name."""
        if block not in self.named:
            start, end = self.found[block]
            text = "\n".join(self.lines[start:end])
            words = self.known.get(text)
            if words is None:
                words = frozenset(w for row in self.lines[start:end]
                                  for w in WORD.findall(code(row)))
            self.words[text] = words
            self.named[block] = {self.block_of[w] for w in words if w in self.block_of}
        return self.named[block]

    def depends(self, block: int) -> list[int]:
        """The blocks the gesture of ``block`` depends on: its own, those of the names
        it writes (and theirs), the robot and ``use`` lines; in the file's order."""
        seen, todo = {block, *self.head}, [block]
        while todo:
            for k in self.names(todo.pop()) - seen:
                seen.add(k)
                todo.append(k)
        return sorted(seen)


def _places(checked: Checked) -> list[Pos]:
    plan = checked.plan
    found = [d.pos for d in (*checked.errors, *checked.warnings) if d.pos is not None]
    if plan is not None:
        found += [s.pos for s in plan.steps if s.pos is not None]
        found += [d.pos for d in plan.warnings if d.pos is not None]
    return found


def _within(checked: Checked, path: str, starts: tuple[int, ...],
            sizes: tuple[int, ...]) -> bool:
    """Whether every place of ``checked`` in the file is in a block it depends on."""
    return all(any(s <= p.line - 1 < s + n for s, n in zip(starts, sizes, strict=True))
               for p in _places(checked) if p.file == path)


def _moved(was: _Kept, now: tuple[int, ...], path: str) -> Checked:
    """``was``'s check with each place in the file moved with its block to ``now``."""
    def move(pos: Pos | None) -> Pos | None:
        if pos is None or pos.file != path:
            return pos
        for old, new, n in zip(was.starts, now, was.sizes, strict=True):
            if old <= pos.line - 1 < old + n:
                return copied(pos, line=pos.line + new - old)
        return pos

    def diag(d: Diagnostic) -> Diagnostic:
        return d if d.pos is None else copied(d, pos=move(d.pos))

    c = was.checked
    plan: Plan | None = c.plan
    if plan is not None:
        plan = copied(plan, steps=tuple(copied(s, pos=move(s.pos)) for s in plan.steps),
                      warnings=tuple(diag(d) for d in plan.warnings))
    return Checked(tuple(diag(d) for d in c.errors), tuple(diag(d) for d in c.warnings), plan)


