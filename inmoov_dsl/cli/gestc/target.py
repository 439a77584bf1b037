"""The gesture a gestc command works on: the arguments that name it, compiling it
(with --strict's checks), and where the command's output goes."""

from __future__ import annotations

import argparse
from pathlib import Path

from ...compiling.compiled import Compiled
from ...compiling.compiler import compile_program, plan_checks
from ...compiling.plan import Plan
from ...errors import Diagnostic, GestError
from ...hardware import Profile
from ...language.program import Program
from ...model import collisions
from ..common import add_lib, report
from ..target import Target, load_target
from . import PROG  # noqa: F401 (the commands take it from here)


def add_arguments(p: argparse.ArgumentParser, target: bool = True) -> None:
    """The arguments every compiling command takes (and the gesture's, if ``target``)."""
    if target:
        p.add_argument("target", metavar="FILE",
                       help="a .gest file, or the name of a library gesture")
        p.add_argument("-g", "--gesture", help="the gesture to use from FILE")
        p.add_argument("--from", dest="start", metavar="POSE",
                       help="start pose: a pose name or targets such as 'fingers 90' "
                       "(default: the profile's rest pose)")
    p.add_argument("-p", "--profile",
                   help="robot profile: a built-in name or a .toml path (default: the "
                   "file's robot line, else rhand)")
    p.add_argument("--strict", action="store_true",
                   help="treat warnings as errors: a stretched move, and a link that "
                   "cannot send every value the plan needs (coverage below 100%%)")
    add_lib(p)


def target_of(args: argparse.Namespace) -> Target:
    """Find the gesture the arguments name (a file, or a name on the search path:
    ``load_target``) and load it."""
    return load_target(args.target, args.gesture, args.profile, args.lib, PROG)


def compile_target(args: argparse.Namespace, target: Target | None = None
                   ) -> tuple[Compiled, Plan]:
    """Compile the gesture the arguments name (``target``, if it is loaded already)."""
    target = target or target_of(args)
    return compile_one(target.program, target.gesture, target.profile, args.start,
                       args.strict)


def compile_one(program: Program, gesture: str | None, profile: str | Profile,
                start: str | None, strict: bool) -> tuple[Compiled, Plan]:
    """Compile one gesture and report its warnings; if ``strict``, a link that cannot
    keep up is an error too. The robot's parts are checked against each other
    (``collisions``)."""
    with plan_checks(collisions):
        compiled, plan = compile_program(program, gesture, profile, start, strict)
    report(compiled.warnings, PROG)
    if strict:
        link_keeps_up(program, compiled, plan)
    return compiled, plan


def link_keeps_up(program: Program, compiled: Compiled, plan: Plan) -> None:
    """A link that cannot send every value the plan needs (frame coverage below 100%)
    is an error at the gesture's name."""
    from ...compiling.metrics import measure

    node = program.gestures[compiled.gesture]
    errors = [program.sources.error(
        f"gesture '{compiled.gesture}': the link to board {r.board} carries "
        f"{100 * r.coverage:.1f}% of the values the plan needs ({r.covered:,} of "
        f"{r.needed:,} servo-frames at {r.baud} baud)", node.name.pos,
        hint="slow the moves down, stagger them, raise the baud or split the servos over "
        f"more boards; gestc show {compiled.gesture} gives the figures")
        for r in measure(plan, compiled.streams) if r.coverage < 1]
    if errors:
        raise GestError(errors)


def output_path(output: str | None, gesture: str, suffixes: tuple[str, ...],
                any_suffix: bool = False) -> str:
    """Where a command writes: ``-o FILE``; into ``-o DIR`` (an existing directory, or a
    name ending in /) as GESTURE plus the first suffix; GESTURE plus it by default.
    A file whose suffix is none of ``suffixes`` is refused unless ``any_suffix``."""
    if output is None or output == "-":
        return output or f"{gesture}{suffixes[0]}"
    path = Path(output)
    if path.is_dir() or output.endswith(("/", "\\")):
        if not path.is_dir():
            raise GestError(Diagnostic("error", f"-o {output}: no such directory",
                                       hint=f"create it first: mkdir {output}"))
        return str(path / f"{gesture}{suffixes[0]}")
    if not any_suffix and path.suffix.lower() not in suffixes:
        kinds = " or ".join(", ".join(suffixes).rsplit(", ", 1))
        raise GestError(Diagnostic("error", f"-o {output}: write a {kinds} file, or into a "
                                   f"directory", hint=f"-o {path.with_suffix(suffixes[0])}"))
    return output
