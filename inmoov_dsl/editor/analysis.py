"""What the compiler makes of an editor's text (pure but for reading the files it
``use``s): the program, its robot, its names, every error and warning as ``gestc check``
tells them, and the plan of each gesture that compiles. Every request of the server
reads one Analysis of the text as it is now: ``loaded`` (its program and names) is
what most read, ``checked`` (every diagnostic and plan) is what takes long on a long
file, in steps; ``touched`` adds the contacts of the robot's parts in each plan (the
check ``gestc check`` makes too: costly on a long motion, so told after the rest)."""

from __future__ import annotations

import contextlib
import dataclasses
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from ..compiling.checking import check_gesture, checkable, tell
from ..compiling.names import NameTable
from ..compiling.plan import Plan
from ..compiling.robot import DEFAULT, profile_for
from ..errors import Diagnostic, GestError
from ..hardware import Profile
from ..language.library import library_dirs
from ..language.load import load
from ..language.program import Program
from ..profiles.profile import profiles_with
from .lines import compiler_line, rows
from .memo import Memo


@dataclass
class Analysis:
    """One text of one file, as the compiler sees it (``program`` None: it does not
    load; ``names`` None: its names do not resolve; ``checked`` False: loaded, its
    gestures not yet checked: no diagnostics but the loading's, no plans)."""

    text: str
    path: str
    program: Program | None = None
    profile: Profile | None = None
    names: NameTable | None = None
    diagnostics: list[Diagnostic] = field(default_factory=list)  #: errors, then warnings
    plans: dict[str, Plan] = field(default_factory=dict)  #: the file's gestures, planned
    checked: bool = True
    touched: bool = False  #: each plan's contacts looked for (``touched``)


def analyse(text: str, path: str, robot: str = DEFAULT, lib: Sequence[str] = (),
            memo: Memo | None = None) -> Analysis:
    """Analyse ``text``, the file at ``path`` (its ``use`` lines and robot line read
    beside it; ``robot``: the profile of a file that names none; ``lib``: more gesture
    folders; ``memo``: what is kept of the texts analysed before, so that an edit costs
    what it touches): ``loaded``, then ``checked``, then ``touched``."""
    memo = Memo() if memo is None else memo
    return touched(checked(loaded(text, path, robot, lib, memo), memo), memo)


def loaded(text: str, path: str, robot: str = DEFAULT, lib: Sequence[str] = (),
           memo: Memo | None = None) -> Analysis:
    """The first half of ``analyse``: the program, its robot and its names (what hover,
    completion, definition, references, the outline and the tokens read); its
    gestures not checked yet, unless it does not load (then its errors are all)."""
    path = str(Path(path))
    found = Analysis(text, path, checked=False)
    memo = Memo() if memo is None else memo
    try:
        program = load(path, text, search=library_dirs(list(lib)), parser=memo.parse,
                       partly=memo.blocks.parse_partly)
        profile = profile_for(program, default=robot)
    except GestError as exc:
        found.diagnostics, found.checked = list(exc.diagnostics), True
        return found
    found.program, found.profile = program, profile
    with contextlib.suppress(GestError):  # told again by the check below, at their places
        found.names = NameTable(program, profile, profiles_with)
    return found


def checked(found: Analysis, memo: Memo, step: Callable[[], None] | None = None
            ) -> Analysis:
    """The second half of ``analyse``: ``found`` (``loaded``) with each gesture checked:
    every diagnostic, the plans. ``step`` is called before each gesture (what it raises
    stops the check; ``Memo.check``)."""
    if found.checked or found.program is None or found.profile is None:
        return dataclasses.replace(found, checked=True)
    each = memo.check(found.program, found.profile, found.path, step)
    errors, warnings = tell(found.program, [c for _, c in each], profile=found.profile)
    return dataclasses.replace(found, diagnostics=errors + warnings, checked=True,
                               plans={g: c.plan for g, c in each if c.plan})


def touched(found: Analysis, memo: Memo, step: Callable[[], None] | None = None
            ) -> Analysis:
    """The third part of ``analyse``: ``found`` (``checked``, the last ``memo`` checked)
    with each plan's contacts (``model.guard``) among its warnings, and its plans';
    ``step`` as ``checked``'s, called within a long plan's check too."""
    if found.touched or found.program is None or not found.checked:
        return dataclasses.replace(found, touched=True)
    from ..model import collisions

    each = memo.touch(found.program, lambda plan, sources, step: collisions(
        plan, sources, False, step), step)
    errors, warnings = tell(found.program, [c for _, c in each], profile=found.profile)
    return dataclasses.replace(found, diagnostics=errors + warnings, touched=True,
                               plans={g: c.plan for g, c in each if c.plan})


def planned_at(found: Analysis, line: int) -> Analysis:
    """``found`` with the plan of the gesture of the file written on protocol line
    ``line`` (0-based) too, when its gestures are not checked yet: what a hover there
    reads, without waiting for the whole file's check."""
    program = found.program
    if found.checked or program is None or found.profile is None or \
            not 0 <= line < len(rows(found.text)):
        return found
    row = compiler_line(found.text, line)
    mine = [(p.line, g) for g, node in program.gestures.items()
            if (p := node.name.pos).file == found.path and p.line <= row]
    if not mine or (gesture := max(mine)[1]) not in checkable(program):
        return found
    plan = check_gesture(program, gesture, found.profile).plan
    return found if plan is None else dataclasses.replace(found, plans={gesture: plan})
