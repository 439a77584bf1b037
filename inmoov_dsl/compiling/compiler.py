"""The compiler's entry points: source or file in, Compiled (timed streams) out."""

from __future__ import annotations

import dataclasses
import hashlib
import os
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from contextvars import ContextVar
from pathlib import Path

from ..errors import Diagnostic, GestError, SourceMap, did_you_mean
from ..hardware import Profile
from ..language import snippet
from ..language.load import load
from ..language.program import Program
from . import reaching
from .actions import Action
from .compiled import Compiled, Cue, StepSummary
from .encode import encode
from .plan import Plan, Planner
from .resolve import resolver
from .robot import profile_for
from .speech import Speech
from .valuehint import fitting


def _sha256(text: str) -> str:
    # surrogatepass: a str given as source may hold a lone surrogate (a file never does)
    return hashlib.sha256(text.encode("utf-8", "surrogatepass")).hexdigest()


def source_digests(program: Program) -> tuple[tuple[str, str], ...]:
    """(path, SHA-256) of every text of the program, each hashed once."""
    for path, text in program.texts.items():
        if path not in program.digests:
            program.digests[path] = _sha256(text)
    return tuple((p, program.digests[p]) for p in program.texts)


def pick_gesture(program: Program, name: str | None) -> str:
    """The gesture to compile: the one asked for, or the file's only one, or the one
    named like the file."""
    if name is not None:
        if name not in program.gestures:
            hint = did_you_mean(name, program.gestures) or (
                "it defines: " + ", ".join(program.own) if program.own else None)
            raise GestError(Diagnostic("error", f"no gesture '{name}' in {program.root}",
                                       hint=hint))
        return name
    own = program.own
    if len(own) == 1:
        return own[0]
    stem = Path(program.root).stem
    if stem in own:
        return stem
    if not own:
        raise GestError(Diagnostic("error", f"{program.root} defines no gesture"))
    raise GestError(Diagnostic(
        "error", f"{program.root} defines {len(own)} gestures: {', '.join(own)}",
        hint="choose one with --gesture NAME"))


Start = str | Mapping[str, int] | None  #: ``--from`` text, or servo name -> value

#: a further check of every plan compiled: its warnings (with ``strict``, it raises
#: them as a GestError). The self-collision check (model/collide.py ``check_plan``)
#: is one, given by the commands that want it (``plan_checks``): ``compiling`` does
#: not import ``model``.
PlanCheck = Callable[[Plan, SourceMap, bool], tuple[Diagnostic, ...]]
_CHECKS: ContextVar[tuple[PlanCheck, ...]] = ContextVar("plan_checks", default=())


@contextmanager
def plan_checks(*checks: PlanCheck) -> Iterator[None]:
    """Run ``checks`` on every plan compiled within the ``with`` (in this context only:
    a long-running process, or a test, is left as it was)."""
    token = _CHECKS.set(_CHECKS.get() + checks)
    try:
        yield
    finally:
        _CHECKS.reset(token)


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
    with fitting(profile, program), snippet.parsed(text, file, prefix) as module:
        (item,) = module.items
        targets = resolver(program, profile).targets(item.targets)
    for index, value in targets.items():
        pose[index] = value
    return tuple(pose)


def plan_gesture(program: Program, gesture: str, profile: Profile, start: Start = None,
                 strict: bool = False, side: str | None = None,
                 actions: Sequence[Action] | None = None) -> Plan:
    """Resolve and plan gesture ``gesture`` of ``program`` for ``profile``, from the
    ``start`` pose (see resolve_start); ``strict``: a stretched move is an error;
    ``side``: played on that side of the robot (sides.py); ``actions``: the gesture's,
    when the caller has resolved them already (the gesture is expanded once)."""
    if actions is None:
        actions = resolver(program, profile).gesture(gesture, side)
    pose = resolve_start(program, profile, start)
    actions, noted = reaching.solve(actions, pose, profile, program.sources, strict)
    plan = Planner(profile, program.sources).plan(actions, pose, strict)
    found = noted + tuple(d for check in _CHECKS.get()
                          for d in check(plan, program.sources, strict))
    return dataclasses.replace(plan, warnings=plan.warnings + found) if found else plan


def compile_program(program: Program, gesture: str | None = None,
                    profile: str | Profile | None = None, start: Start = None,
                    strict: bool = False, side: str | None = None,
                    actions: Sequence[Action] | None = None) -> tuple[Compiled, Plan]:
    """Compile one gesture of a loaded program (on ``side`` of the robot, when given;
    ``actions``: its actions, already resolved); also return its plan (for reports).
    ``profile``: a name, a path or a Profile; None is the program's robot (``robot``)."""
    prof = profile_for(program, profile)
    name = pick_gesture(program, gesture)
    plan = plan_gesture(program, name, prof, start, strict, side, actions)
    streams = encode(plan)
    steps = tuple(
        StepSummary(s.where, s.pos.file if s.pos else None, s.pos.line if s.pos else None,
                    s.kind, s.start, s.end, s.asked, s.stretched)
        for s in plan.steps
    )
    compiled = Compiled(
        gesture=name,
        profile=prof.name,
        profile_sha256=prof.sha256,
        sources=source_digests(program),
        servos=prof.names,
        start=plan.start,
        final=plan.final,
        duration=plan.duration,
        steps=steps,
        streams=streams,
        warnings=plan.warnings,
        sounds=tuple(cue(start, s) for start, s in plan.sounds),
    )
    return compiled, plan


def cue(start: float, speech: Speech) -> Cue:
    """What the compiled gesture keeps of a ``say`` that starts at ``start``."""
    sound, v = speech.sound, speech.voice
    return Cue(round(start, 9), sound.source, sound.path or None,  # as its file says it
               None if sound.path else (v.voice, v.speed, v.pitch), sound.digest,
               round(sound.duration, 9), sound)


def compile_source(text: str, gesture: str | None = None,
                   profile: str | Profile | None = None,
                   start: Start = None, strict: bool = False,
                   file: str = "<string>") -> Compiled:
    """Compile .gest source text. ``use`` imports resolve against the library."""
    return compile_program(load(file, text), gesture, profile, start, strict)[0]


def compile_file(path: str | os.PathLike, gesture: str | None = None,
                 profile: str | Profile | None = None, start: Start = None,
                 strict: bool = False) -> Compiled:
    """Compile one gesture of a .gest file."""
    return compile_program(load(str(path)), gesture, profile, start, strict)[0]
