"""The gesture a command names, found and loaded once for every tool: a .gest file or
a library gesture (gestc's commands, gestplay), or a compiled .gestc file (gestplay)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from ..compiling.compiled import Compiled
from ..compiling.compiler import pick_gesture
from ..compiling.playable import check_profile
from ..compiling.robot import profile_for
from ..errors import Diagnostic, GestError
from ..hardware import Profile
from ..language.library import find_gesture, library_dirs
from ..language.load import load
from ..language.program import Program
from ..profiles.profile import load_profile
from .common import report


@dataclass
class Target:
    """A gesture named on the command line, loaded for its profile: a gesture of a
    program (``program``), or a compiled file (``compiled``)."""

    profile: Profile
    gesture: str  #: the gesture's name (picked: the one asked for, or the file's)
    program: Program | None = None
    compiled: Compiled | None = None


def load_target(name: str, gesture: str | None, profile: str | None,
                lib: Sequence[str] | None, prog: str, compiled: bool = False,
                side: str | None = None) -> Target:
    """Find ``name`` (a .gest file, or a gesture on the search path: ``lib``, then the
    library), load it for ``profile`` (default: the file's robot line, else rhand) and
    pick ``gesture`` of it (``pick_gesture``); what is noticed on the way is ``prog``'s
    warning. With ``compiled``, a .gestc file is read instead, for its profile
    (default the one it was compiled for, and checked against it); played on a
    ``side``, refused."""
    if compiled and name.endswith(".gestc"):
        return _compiled(name, profile, side)
    dirs = library_dirs(lib or [])
    path, picked = find_gesture(name, gesture, dirs, lambda d: report([d], prog))
    try:
        program = load(path, search=dirs)
    except GestError as exc:
        raise _fitted(exc, path, dirs, profile) from None
    return Target(profile_for(program, profile), pick_gesture(program, picked),
                  program=program)


def _fitted(exc: GestError, path: str, dirs: list[str], profile: str | None) -> GestError:
    """``exc`` with the hint of each value outside 0..180 fitted to its servo, on the
    profile the file is for (its text loaded again with what of it parses, for its
    robot line and groups); as it is when that cannot be told."""
    from ..compiling.valuehint import fitted, refused
    from ..language.incremental import BlockParser

    if not any(refused(d) for d in exc.diagnostics):
        return exc
    try:
        program = load(path, search=dirs, partly=BlockParser().parse_partly)
        return GestError(fitted(exc.diagnostics, profile_for(program, profile), program))
    except GestError:
        return exc


def _compiled(name: str, profile: str | None, side: str | None) -> Target:
    """A compiled file, for its profile (checked against it)."""
    from ..compiling.compiled_reader import read_compiled

    if side is not None:
        raise GestError(Diagnostic("error", "--hand plays a gesture on the other side; a "
                                   "compiled file is for the side it was compiled for",
                                   hint="play the .gest file"))
    done = read_compiled(name)
    loaded = load_profile(profile or done.profile)
    check_profile(done, loaded)
    return Target(loaded, done.gesture, compiled=done)
