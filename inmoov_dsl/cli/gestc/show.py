"""gestc show: a gesture's code (coloured on a terminal), its steps, and for each link its
bytes, use, coverage and lag."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ...errors import counted
from ..common import EXIT_OK, add_color, wants_color, warn
from .target import PROG, add_arguments, compile_target, target_of

if TYPE_CHECKING:
    from collections.abc import Callable

    from ...compiling import metrics
    from ...language.program import Program


def run(args: argparse.Namespace) -> int:
    """Print the gesture's code, the step table and each link's figures."""
    from ...compiling.metrics import measure

    target = target_of(args)
    compiled, plan = compile_target(args, target)
    print(f"{compiled.gesture}: {compiled.duration:.3f} s on profile '{compiled.profile}'")
    print()
    code = source_text(target.program, compiled.gesture, _highlighter(args.color))
    if code:
        print(code)
        print()
    print(f"  {'#':>3}  {'step':<24} {'source':<18} {'kind':<5} {'start':>7} {'end':>7} "
          f"{'asked':>7} {'planned':>7}")
    for n, s in enumerate(plan.steps, 1):
        source = f"{Path(s.pos.file).name}:{s.pos.line}" if s.pos else ""
        asked = f"{s.asked:7.3f}" if s.asked is not None else "      -"
        flag = "  stretched" if s.stretched else ""
        print(f"  {n:>3}  {s.where:<24} {source:<18} {s.kind:<5} {s.start:7.3f} "
              f"{s.end:7.3f} {asked} {s.end - s.start:7.3f}{flag}")
        for row in solved_text(s.solved, plan.profile.names):
            print(f"  {'':>3}    {row}")
    for start, speech in plan.sounds:
        print()
        print(sound_text(start, speech, plan))
    for link in measure(plan, compiled.streams):
        print()
        print(link_text(link))
    return EXIT_OK


def solved_text(solved, names: tuple[str, ...]) -> list[str]:
    """A line for each place of a step: ``right hand to cup -> r_omoplate 147, ...``."""
    return [f"{aim.label} -> " + ", ".join(f"{names[i]} {v}" for i, v in values)
            for aim, values in solved]


def source_text(program: Program, gesture: str,
                highlight: Callable[[str], str] | None = None) -> str | None:
    """The lines of its file that define ``gesture`` (the comments right above it
    too), under the file's name and their line numbers; coloured by ``highlight``."""
    found = program.source(gesture)
    if found is None:
        return None
    pos, lines = found
    code = "\n".join(lines)
    if highlight is not None:
        code = highlight(code).rstrip("\n")
    last = pos.line + len(lines) - 1
    where = f"line {last}" if last == pos.line else f"lines {pos.line}-{last}"
    rows = [f"    {row}" if row else "" for row in code.split("\n")]
    return "\n".join([f"  {Path(pos.file).name}, {where}", *rows])


def _highlighter(choice: str) -> Callable[[str], str] | None:
    """What colours gesture code for standard output (``--color``), or None: plain text
    (and a warning when colours were asked for and pygments is missing)."""
    if not wants_color(choice):
        return None
    try:
        from ...editor.lexer import terminal
    except ImportError:
        if choice == "always":
            warn("--color always: colours need pygments (pip install "
                 "'inmoov-dsl[highlight]')", PROG)
        return None
    return terminal


BLOCKS = " ▁▂▃▄▅▆▇█"  #: a value from nothing to the most, in one character
SHOWN = 0.05  #: s a character stands for
WIDTH = 60  #: characters on a line


def sound_text(start: float, speech, plan) -> str:
    """A ``say``: its sound, and its loudness beside the mouth's planned opening, a
    character per SHOWN s (blank: silence or closed)."""
    from ...compiling.speech import HOP, LEAD

    sound, voice = speech.sound, speech.voice
    every = round(SHOWN / HOP)
    count = -(-len(speech.levels) // every)
    levels = [max(speech.levels[k * every:(k + 1) * every], default=0) for k in range(count)]
    times = start + (np.arange(count) + 0.5) * SHOWN
    track = plan.tracks[speech.servo].position(times)
    opening = (track - voice.closed) / (voice.opened - voice.closed)
    rows = [f'say "{sound.source}" at {start:.3f} s: {sound.duration:.2f} s of sound; '
            f"the {voice.mouth} opens {voice.closed}..{voice.opened}, leading the sound by "
            f"{LEAD * 1000:.0f} ms"]
    for at in range(0, count, WIDTH):
        cut = slice(at, at + WIDTH)
        rows.append(f"  {start + at * SHOWN:7.2f} s  loudness  {_bars(levels[cut])}")
        rows.append(f"  {'':9}  {voice.mouth:<9} {_bars(opening[cut])}")
    return "\n".join(rows)


def _bars(values) -> str:
    top = len(BLOCKS) - 1
    return "".join(BLOCKS[min(top, max(0, round(float(v) * top)))] for v in values)


def link_text(r: metrics.LinkReport) -> str:
    """One link's figures, a line each; one line for a board the gesture leaves idle."""
    head = f"board {r.board} at {r.baud} baud, {r.servos} servo{'' if r.servos == 1 else 's'}"
    if r.idle:
        return f"{head}: idle, none of its servos moves (it is sent CANCEL only)"
    saved = 100 * (1 - r.bytes / r.naive_bytes) if r.naive_bytes else 0.0
    lag = (f"{r.worst_lag:.2f} deg ({r.worst_lag_servo} at {r.worst_lag_time:.3f} s)"
           if r.worst_lag_servo else "0.00 deg")
    rows = [
        head,
        f"  bytes        {r.bytes:,} (every servo every frame: {r.naive_bytes:,}; "
        f"{saved:.0f}% fewer)",
        f"  link use     {100 * r.utilisation:.0f}% over the gesture, "
        f"{100 * r.peak_utilisation:.0f}% in the busiest frame",
        f"  coverage     {100 * r.coverage:.1f}% ({r.covered:,} of {r.needed:,} servo-frames "
        f"that needed a value)",
        f"  worst lag    {lag}",
        f"  max error    {r.max_error:.2f} deg (value sent vs plan at arrival)",
    ]
    rows += _shortfall(r)
    return "\n".join(rows)


FULL = 0.9  #: a frame this busy has no room left for the values a plan needs


def _shortfall(r: metrics.LinkReport) -> list[str]:
    """What keeps coverage below 100%, and what would help: a link full in its busiest
    frame is too slow; one with room to spare sends each value at its pair's slot in the
    run, which at a sharp turn of a servo's plan can fall just after the frame it was
    due in (the servo gets it a frame late: a faster link only moves the slot)."""
    if r.coverage >= 1:
        return []
    missed = r.needed - r.covered
    if r.peak_utilisation >= FULL:
        return ["  the link is the bottleneck: its busiest frame is full; raise the baud "
                "or split the servos over more boards"]
    late = counted(missed, "servo-frame")
    servo = f"the {r.worst_lag_servo}'s" if r.worst_lag_servo else "a servo's"
    return [f"  {late} got the value a frame late: at a sharp turn of {servo} plan, "
            "the value lands on its pair's slot just after the frame began; the link has "
            "room to spare: nothing to change"]


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestc show GESTURE``."""
    p = sub.add_parser("show", help="the gesture's code, steps, bytes, link use, coverage "
                       "and lag")
    add_arguments(p)
    add_color(p)
    p.set_defaults(func=run)
