"""What the compiler makes of an editor's text (pure but for reading the files it
``use``s): the program, its robot, its names, every error and warning as ``gestc check``
tells them, and the plan of each gesture that compiles. Every request of the server
reads one Analysis of the text as it is now."""

from __future__ import annotations

import contextlib
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from ..compiling.checking import tell
from ..compiling.names import NameTable
from ..compiling.plan import Plan
from ..compiling.robot import DEFAULT, profile_for
from ..errors import Diagnostic, GestError
from ..hardware import Profile
from ..language.library import library_dirs
from ..language.load import load
from ..language.program import Program
from ..profiles.profile import profiles_with
from .memo import Memo


@dataclass
class Analysis:
    """One text of one file, as the compiler sees it (``program`` None: it does not
    load; ``names`` None: its names do not resolve)."""

    text: str
    path: str
    program: Program | None = None
    profile: Profile | None = None
    names: NameTable | None = None
    diagnostics: list[Diagnostic] = field(default_factory=list)  #: errors, then warnings
    plans: dict[str, Plan] = field(default_factory=dict)  #: the file's gestures, planned


def analyse(text: str, path: str, robot: str = DEFAULT, lib: Sequence[str] = (),
            memo: Memo | None = None) -> Analysis:
    """Analyse ``text``, the file at ``path`` (its ``use`` lines and robot line read
    beside it; ``robot``: the profile of a file that names none; ``lib``: more gesture
    folders; ``memo``: what is kept of the texts analysed before, so that an edit costs
    what it touches)."""
    path = str(Path(path))
    found = Analysis(text, path)
    memo = Memo() if memo is None else memo
    try:
        program = load(path, text, search=library_dirs(list(lib)), parser=memo.parse,
                       partly=memo.blocks.parse_partly)
        profile = profile_for(program, default=robot)
    except GestError as exc:
        found.diagnostics = list(exc.diagnostics)
        return found
    found.program, found.profile = program, profile
    with contextlib.suppress(GestError):  # told again by the check below, at their places
        found.names = NameTable(program, profile, profiles_with)

    each = memo.check(program, profile, path)
    found.plans = {g: c.plan for g, c in each if c.plan}
    errors, warnings = tell(program, [c for _, c in each])
    found.diagnostics = errors + warnings
    return found
