"""The hint of a value the parser refused as outside 0..180, fitted to the servo it was
written for once the profile is known: the servo's own range (a group's, member by
member), and what its ends mean where the profile says (the mouth's, in ``[voice]``).
The parser, which knows no profile, gives the range every servo is within."""

from __future__ import annotations

import re
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import replace

from ..errors import Diagnostic, GestError
from ..hardware import Profile
from ..language.program import Program
from ..protocol import MAX_VALUE

#: the parser's message for a value outside every servo's range (``language.tree``)
_REFUSED = re.compile(rf"value \S+ is outside 0\.\.{MAX_VALUE}")
#: the name a value is written after: ``neck 190``
_NAME = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)\s+$")


def refused(d: Diagnostic) -> bool:
    """Is ``d`` the parser's refusal of a value outside 0..180?"""
    return _REFUSED.fullmatch(d.message) is not None


def fitted(found: Sequence[Diagnostic], profile: Profile, program: Program | None = None
           ) -> list[Diagnostic]:
    """``found`` with the hint of each value outside 0..180 fitted to the servo or group
    it is written for on ``profile`` (``program``'s groups too); the others as they are."""
    return [_fit(d, profile, program) if refused(d) else d for d in found]


@contextmanager
def fitting(profile: Profile, program: Program | None = None) -> Iterator[None]:
    """The errors raised within, their hints ``fitted`` to ``profile``."""
    try:
        yield
    except GestError as exc:
        raise GestError(fitted(exc.diagnostics, profile, program)) from None


def _fit(d: Diagnostic, profile: Profile, program: Program | None) -> Diagnostic:
    """``d`` with the hint of the servo or group named before its value, if known."""
    if d.pos is None or d.source_line is None:
        return d
    written = _NAME.search(d.source_line[:d.pos.column - 1])
    hint = written and servo_hint(written[1], profile, program)
    return replace(d, hint=hint) if hint else d


def servo_hint(name: str, profile: Profile, program: Program | None = None) -> str | None:
    """What ``name`` (a servo or a group) takes on ``profile``: ``neck takes 0..180 on
    inmoov``, ``jaw takes 0..180 on inmoov (0 is closed, 150 open: its [voice])``,
    ``eyes (eye_x, eye_y) take 0..180 on inmoov``; None if it is neither."""
    members = _members(name, profile, program)
    if not members:
        return None
    servos = [profile.servos[profile.index(m)] for m in members]
    ranges = {(s.lo, s.hi) for s in servos}
    if members == [name]:
        said = f"{name} takes {servos[0].lo}..{servos[0].hi}"
    elif len(ranges) == 1:
        (lo, hi), = ranges
        said = f"{name} ({', '.join(members)}) take{'s' * (len(members) == 1)} {lo}..{hi}"
    else:
        said = f"{name}: " + ", ".join(f"{s.name} takes {s.lo}..{s.hi}" if k == 0 else
                                       f"{s.name} {s.lo}..{s.hi}"
                                       for k, s in enumerate(servos))
    voice = profile.voice
    ends = (f" ({voice.closed} is closed, {voice.opened} open: its [voice])"
            if voice is not None and members == [voice.mouth] else "")
    return f"{said} on {profile.name}{ends}"


def _members(name: str, profile: Profile, program: Program | None) -> list[str]:
    """The servos ``name`` stands for on ``profile``: itself, a profile's group's or a
    program's group's members (the servos of those the profile has)."""
    have = {s.name for s in profile.servos}
    if name in have:
        return [name]
    if program is not None and name in program.groups:
        members = [m.text for m in program.groups[name].members]
    else:
        members = list(profile.groups.get(name, ()))
    out: list[str] = []
    for member in members:  # a group of groups: its servos
        inner = [member] if member in have else list(profile.groups.get(member, ()))
        out += [m for m in inner if m in have and m not in out]
    return out
