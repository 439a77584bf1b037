"""Resolve names (stage 2): files and their imports, poses, groups, calls and repeats.

A gesture becomes a flat tuple of Actions over the profile's servos. File access
goes through an injected ``read`` function, so the stage stays testable.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path

from . import syntax as ast
from .errors import Diagnostic, GestError, Pos, SourceMap, did_you_mean
from .parse import parse
from .profile import Profile

MAX_STEPS = 100_000  #: the most steps one gesture may expand to
MAX_NESTING = 100  #: the deepest chain of calls and repeats, or of poses within poses
MAX_WHERE = 120  #: characters of a step's call chain; a longer one is abbreviated
#: the most steps all the gestures of one program may expand to for one profile, each
#: gesture counted once however often it is compiled (``gestc check`` compiles them all)
MAX_TOTAL_STEPS = 1_000_000


@dataclass(frozen=True)
class Action:
    """What one step of a gesture does once resolved: a move (targets), or a hold
    (``hold`` > 0). (``syntax.Step`` is what was written, ``plan.PlannedStep`` what was
    planned, ``compiled.StepSummary`` what a compiled file reports.)"""

    targets: tuple[tuple[int, int], ...]  #: (servo index, value), in stagger order
    over: float | None = None  #: s; all servos arrive together at this time
    stagger: float = 0.0  #: s between the starts of consecutive targets
    hold: float = 0.0  #: s; a wait step
    pos: Pos | None = None
    over_pos: Pos | None = None
    where: str = ""  #: the call chain, e.g. "demo > peace"


@dataclass
class Program:
    """A .gest file with everything it imports, and the names they define."""

    root: str
    sources: SourceMap = field(default_factory=SourceMap)
    texts: dict[str, str] = field(default_factory=dict)
    gestures: dict[str, ast.GestureDef] = field(default_factory=dict)
    poses: dict[str, ast.PoseDef] = field(default_factory=dict)
    groups: dict[str, ast.GroupDef] = field(default_factory=dict)
    own: list[str] = field(default_factory=list)  #: gestures defined in the root file
    #: one Resolver per profile (see ``resolver``), and the SHA-256 of every text
    resolvers: dict[int, Resolver] = field(default_factory=dict, repr=False)
    digests: dict[str, str] = field(default_factory=dict, repr=False)

    def names(self) -> dict[str, Pos]:
        found: dict[str, Pos] = {}
        for table in (self.groups, self.poses, self.gestures):
            for name, node in table.items():
                found[name] = node.name.pos
        return found


Reader = Callable[[str], str]


def load_program(path: str, read: Reader, search: Sequence[str] = (),
                 text: str | None = None, first_wins: bool = False) -> Program:
    """Parse ``path`` (or ``text`` under that name) and every file it ``use``s.

    Imports are looked up beside the importing file, then in ``search``; each file is
    read once. Duplicate definitions are errors naming both places, unless
    ``first_wins`` (a library along its search path): then a name already defined by
    another file is shadowed, and only one file defining it twice is an error.
    """
    program = Program(path)
    seen: set[str] = set()
    defined: dict[str, Pos] = {}
    errors: list[Diagnostic] = []

    def visit(file: str, source: str, is_root: bool) -> None:
        seen.add(os.path.normcase(os.path.abspath(file)))
        program.sources.add(file, source)
        program.texts[file] = source
        module = parse(source, file)
        for item in module.items:
            if isinstance(item, ast.Use):
                found = _find_import(item, file, search, read, program.sources)
                key = os.path.normcase(os.path.abspath(found[0]))
                if key not in seen:
                    visit(found[0], found[1], False)
                continue
            name = item.name.text
            if name in defined and first_wins and defined[name].file != file:
                continue  # shadowed by a file earlier on the search path
            if name in defined:
                first = defined[name]
                errors.append(program.sources.error(
                    f"'{name}' is defined twice", item.name.pos,
                    f"first defined at {first.file}:{first.line}"))
                continue
            defined[name] = item.name.pos
            if isinstance(item, ast.GestureDef):
                program.gestures[name] = item
                if is_root:
                    program.own.append(name)
            elif isinstance(item, ast.PoseDef):
                program.poses[name] = item
            else:
                program.groups[name] = item

    visit(path, read(path) if text is None else text, True)
    if errors:
        raise GestError(errors)
    return program


GEST_SUFFIX = ".gest"


def _find_import(use: ast.Use, importer: str, search: Sequence[str], read: Reader,
                 sources: SourceMap) -> tuple[str, str]:
    """The file ``use`` names: relative to the importing file's directory, then to each
    directory of the search path (an absolute path as it is). It must be a gesture file,
    its name and (through any symlink) its target's name ending in .gest: so a gesture
    file from someone else cannot make the tools open, or quote a line of, anything else
    (docs/security.md)."""
    if not use.path.endswith(GEST_SUFFIX):
        raise GestError(sources.error(f"use takes a {GEST_SUFFIX} file, not '{use.path}'",
                                      use.pos, f'use "{Path(use.path).stem}{GEST_SUFFIX}"'))
    places = [os.path.join(os.path.dirname(importer), use.path)]
    places += [os.path.join(d, use.path) for d in search]
    for place in places:
        try:
            target = os.path.realpath(place)
            if not target.endswith(GEST_SUFFIX) and os.path.exists(place):
                raise ValueError(f"it links to '{target}', which is not a {GEST_SUFFIX} "
                                 f"file")
            return place, read(place)
        except FileNotFoundError:
            continue
        except (OSError, ValueError) as exc:  # a NUL in the path, not UTF-8, too large
            raise GestError(sources.error(f"cannot read '{place}': {exc}", use.pos)) from None
    raise GestError(sources.error(
        f"cannot find '{use.path}'", use.pos,
        "looked in " + ", ".join(os.path.dirname(p) or "." for p in places)))


class Resolver:
    """Turns a gesture of a Program into Actions for one profile."""

    def __init__(self, program: Program, profile: Profile,
                 elsewhere: Callable[[str], Sequence[str]] | None = None):
        """``elsewhere(name)``: the other profiles that have a servo or group ``name``
        (asked only to word an error)."""
        self.program = program
        self.profile = profile
        self.elsewhere = elsewhere
        self.src = program.sources
        self._sizes: dict[str, tuple[int, int]] = {}
        # what is expanded once and kept: each pose's targets and nesting height, each
        # move's targets (by the node's id; the program keeps the nodes), call chains
        self._poses: dict[str, tuple[dict[int, int], int]] = {}
        self._moves: dict[int, tuple[tuple[int, int], ...]] = {}
        self._wheres: dict[tuple[str, str], str] = {}
        self._counted: set[str] = set()  # gestures expanded, and their steps in all
        self._total = 0
        self._check_names()

    def _check_names(self) -> None:
        errors = []
        servo_names = set(self.profile.names)
        for name, pos in self.program.names().items():
            if name in servo_names:
                errors.append(self.src.error(f"'{name}' is the name of a servo of profile "
                                             f"'{self.profile.name}'", pos))
            elif name in self.profile.groups and name not in self.program.groups:
                errors.append(self.src.error(f"'{name}' is the name of a group of profile "
                                             f"'{self.profile.name}'", pos))
        for group in self.program.groups.values():
            for member in group.members:
                if member.text not in servo_names:
                    errors.append(self.src.error(
                        f"unknown servo '{member.text}' in group '{group.name.text}'",
                        member.pos, did_you_mean(member.text, servo_names)))
        if errors:
            raise GestError(errors)

    # -- names ------------------------------------------------------------------
    def known(self) -> list[str]:
        return [*self.profile.names, *self.profile.groups, *self.program.names()]

    def group(self, name: str) -> tuple[str, ...] | None:
        if name in self.program.groups:
            return tuple(m.text for m in self.program.groups[name].members)
        return self.profile.groups.get(name)

    def unknown(self, name: ast.Name, what: str = "servo, group, pose or gesture") -> GestError:
        others = [p for p in self.elsewhere(name.text) if p != self.profile.name] \
            if self.elsewhere else []
        hint = (f"'{name.text}' is in profile '{others[0]}': add --profile {others[0]}"
                if others else did_you_mean(name.text, self.known()))
        return GestError(self.src.error(f"unknown {what} '{name.text}'", name.pos, hint))

    # -- targets ----------------------------------------------------------------
    def targets(self, targets: Sequence[ast.Target], chain: tuple[str, ...] = ()
                ) -> dict[int, int]:
        """Servo index -> value, in order of first mention; later mentions win."""
        return self._targets(targets, chain)[0]

    def _pose(self, t: ast.Target, chain: tuple[str, ...]) -> dict[int, int]:
        """The targets of the pose ``t`` names, expanded once: poses built from poses
        cost the size of their text, not 2^depth."""
        name = t.name.text
        if t.value is not None:
            raise GestError(self.src.error(f"'{name}' is a pose; it takes no value",
                                           t.value_pos, f"write just '{name}'"))
        if name in chain:
            cycle = " -> ".join([*chain[chain.index(name):], name])
            raise GestError(self.src.error(f"pose '{name}' refers to itself: {cycle}",
                                           t.name.pos))
        if name not in self._poses:
            if len(chain) >= MAX_NESTING:
                raise self._poses_too_deep(t)
            inner, height = self._targets(self.program.poses[name].targets, (*chain, name))
            self._poses[name] = (inner, height + 1)
        inner, height = self._poses[name]
        if len(chain) + height > MAX_NESTING:
            raise self._poses_too_deep(t)
        return inner

    def _poses_too_deep(self, t: ast.Target) -> GestError:
        return GestError(self.src.error(f"poses are nested more than {MAX_NESTING} deep",
                                        t.name.pos))

    def _targets(self, targets: Sequence[ast.Target], chain: tuple[str, ...]
                 ) -> tuple[dict[int, int], int]:
        """The targets, and how deep the poses among them nest."""
        out: dict[int, int] = {}
        direct: set[str] = set()
        height = 0
        for t in targets:
            name = t.name.text
            if name in self.program.poses:
                out.update(self._pose(t, chain))
                height = max(height, self._poses[name][1])
                continue
            if name in self.program.gestures:
                raise GestError(self.src.error(
                    f"'{name}' is a gesture: call it on a line of its own", t.name.pos,
                    "a step can mix servos, groups and poses, not gestures"))
            members = (name,) if name in self.profile.names else self.group(name)
            if members is None:
                what = "servo or group" if t.value is not None else None
                raise self.unknown(t.name, *([what] if what else []))
            kind = "servo" if name in self.profile.names else "group"
            if t.value is None:
                raise GestError(self.src.error(f"{kind} '{name}' needs a value", t.name.pos,
                                               f"for example '{name} 90'"))
            if name in direct:
                raise GestError(self.src.error(f"'{name}' is set twice in this step",
                                               t.name.pos))
            direct.add(name)
            for member in members:
                servo = self.profile.servos[self.profile.index(member)]
                if not servo.lo <= t.value <= servo.hi:
                    raise GestError(self.src.error(
                        f"value {t.value} is outside the range of '{member}' "
                        f"({servo.lo}..{servo.hi})", t.value_pos))
                out[self.profile.index(member)] = t.value
        return out, height

    # -- steps ------------------------------------------------------------------
    def gesture(self, name: str) -> tuple[Action, ...]:
        """The steps of gesture ``name``, with calls and repeats expanded."""
        node = self.program.gestures[name]
        size, _ = self.measure(name, (name,))
        if size > MAX_STEPS:
            raise GestError(self.src.error(
                f"gesture '{name}' expands to more than {MAX_STEPS:,} steps",
                node.name.pos, "lower a repeat count"))
        if name not in self._counted:
            if self._total + size > MAX_TOTAL_STEPS:
                raise GestError(self.src.error(
                    f"with '{name}', the gestures of this program expand to more than "
                    f"{MAX_TOTAL_STEPS:,} steps in all", node.name.pos,
                    "split the file: each gesture's calls and repeats are expanded"))
            self._counted.add(name)
            self._total += size
        out: list[Action] = []
        self._emit(node.steps, name, out)
        return tuple(out)

    def _call(self, move: ast.Move) -> str | None:
        if len(move.targets) == 1 and move.targets[0].name.text in self.program.gestures:
            target = move.targets[0]
            if target.value is not None:
                raise GestError(self.src.error(f"'{target.name.text}' is a gesture; it takes "
                                               f"no value", target.value_pos))
            for timing in (move.over, move.stagger):
                if timing is not None:
                    raise GestError(self.src.error(
                        f"a gesture call takes no timing: '{target.name.text}' sets its own",
                        timing.pos, "give the durations inside the gesture"))
            return target.name.text
        return None

    def measure(self, name: str, chain: tuple[str, ...], depth: int = 0) -> tuple[int, int]:
        """(steps, nesting height) of gesture ``name``; detects call cycles and nesting
        too deep, so that expanding a gesture is bounded whatever the input."""
        if name not in self._sizes:
            self._sizes[name] = self._measure(self.program.gestures[name].steps, chain, depth)
        return self._sizes[name]

    def _measure(self, steps: Sequence[ast.Step], chain: tuple[str, ...], depth: int
                 ) -> tuple[int, int]:
        total = height = 0
        for step in steps:
            inner = 0
            callee = self._call(step) if isinstance(step, ast.Move) else None
            if isinstance(step, ast.Repeat) or callee is not None:
                if depth + 1 > MAX_NESTING:
                    raise self._too_deep(step.pos)
                if isinstance(step, ast.Repeat):
                    size, below = self._measure(step.body, chain, depth + 1)
                    size *= step.count
                else:
                    if callee in chain:
                        cycle = " -> ".join([*chain[chain.index(callee):], callee])
                        raise GestError(self.src.error(
                            f"gesture '{callee}' calls itself: {cycle}", step.pos))
                    size, below = self.measure(callee, (*chain, callee), depth + 1)
                inner = below + 1
                if depth + inner > MAX_NESTING:
                    raise self._too_deep(step.pos)
            else:
                size = 1
            total = min(total + size, MAX_STEPS + 1)  # enough to report; stays bounded
            height = max(height, inner)
        return total, height

    def _too_deep(self, pos: Pos | None) -> GestError:
        return GestError(self.src.error(
            f"calls and repeats are nested more than {MAX_NESTING} deep", pos))

    def _emit(self, steps: Sequence[ast.Step], where: str, out: list[Action]) -> None:
        for step in steps:
            if isinstance(step, ast.Repeat):
                for _ in range(step.count):
                    self._emit(step.body, where, out)
            elif isinstance(step, ast.Wait):
                out.append(Action((), hold=step.duration.seconds, pos=step.pos, where=where))
            elif (callee := self._call(step)) is not None:
                self._emit(self.program.gestures[callee].steps, self._where(where, callee),
                           out)
            else:
                key = id(step)
                if key not in self._moves:
                    self._moves[key] = tuple(self.targets(step.targets).items())
                out.append(Action(
                    self._moves[key],
                    over=step.over.seconds if step.over else None,
                    stagger=step.stagger.seconds if step.stagger else 0.0,
                    pos=step.pos,
                    over_pos=step.over.pos if step.over else None,
                    where=where,
                ))

    def _where(self, where: str, callee: str) -> str:
        """``where > callee``, made once per pair; a chain longer than MAX_WHERE keeps
        its first and last names."""
        key = (where, callee)
        if key not in self._wheres:
            text = f"{where} > {callee}"
            if len(text) > MAX_WHERE:
                root = where.split(" > ", 1)[0]
                half = (MAX_WHERE - 9) // 2
                text = f"{_cut(root, half)} > ... > {_cut(callee, half)}"
            self._wheres[key] = text
        return self._wheres[key]


def _cut(name: str, most: int) -> str:
    return name if len(name) <= most else name[:most - 3] + "..."


def resolver(program: Program, profile: Profile,
             elsewhere: Callable[[str], Sequence[str]] | None = None) -> Resolver:
    """The Resolver of ``program`` for ``profile``, made once and kept in the program:
    names are checked once and what is expanded stays expanded, so compiling every
    gesture of a file costs about the file's size, not its square."""
    found = program.resolvers.get(id(profile))
    if found is None or found.profile is not profile:  # it holds the profile: no id reuse
        found = program.resolvers[id(profile)] = Resolver(program, profile, elsewhere)
    return found


def resolve_start(program: Program, profile: Profile,
                  text: str | Mapping[str, int] | None) -> tuple[int, ...]:
    """The start pose: the profile's rest pose, changed by ``--from`` (a pose or targets
    as text) or by servo name -> value (the pose a board reports)."""
    pose = [s.rest for s in profile.servos]
    if not text:
        return tuple(pose)
    if isinstance(text, Mapping):
        for name, value in text.items():
            pose[profile.index(name)] = value
        return tuple(pose)
    file, prefix = "--from", "pose start__: "
    if len(text.splitlines()) > 1:
        raise GestError(Diagnostic("error", "--from takes one line: a pose name or targets",
                                   hint='--from "fingers 90, wrist 45"'))
    program.sources.add(file, prefix + text)
    try:
        (item,) = parse(prefix + text, file).items
        targets = resolver(program, profile).targets(item.targets)
    except GestError as exc:
        raise GestError([_unwrap(d, file, prefix, text) for d in exc.diagnostics]) from None
    for index, value in targets.items():
        pose[index] = value
    return tuple(pose)


def _unwrap(d: Diagnostic, file: str, prefix: str, text: str) -> Diagnostic:
    """Point a diagnostic about ``--from`` at what the user typed, not at our wrapper."""
    if d.pos is None or d.pos.file != file:
        return d
    column = max(1, d.pos.column - len(prefix))
    return replace(d, pos=replace(d.pos, column=column), source_line=text)
