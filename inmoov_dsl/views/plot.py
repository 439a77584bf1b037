"""Pictures of a compiled gesture (``gestc plot``); needs matplotlib (the ``plot`` extra).

One row per servo that moves: on the left its planned position over time, the values
actually sent (as the board holds them, a step each time a pair arrives) and the
keyframes, numbered like ``gestc show``'s steps; on the right its planned velocity
between the profile's limits. Holds are shaded. Above them, a row per ``say``: the
sound's waveform, its loudness and the mouth as its board receives it, so a person sees
where they part.
"""

from __future__ import annotations

import os
import textwrap
from collections.abc import Sequence

import numpy as np

from ..compiling.compiled import Compiled
from ..compiling.metrics import sent_values
from ..compiling.plan import Plan
from ..errors import Diagnostic, GestError

PLAN_COLOUR = "#1f77b4"
SENT_COLOUR = "#d62728"
LIMIT_COLOUR = "#7f7f7f"
HOLD_COLOUR = "#eeeeee"
SOUND_COLOUR = "#2ca02c"
CONTACT_COLOUR = "#9c36b5"
TITLE_WIDTH = 110  #: characters of the title's line at most (13 pt across 12 inches)


def _matplotlib():
    try:
        from matplotlib.figure import Figure
        from matplotlib.patches import Patch
    except ImportError:
        raise GestError(Diagnostic(
            "error", "gestc plot needs matplotlib, which is not installed",
            hint="pip install 'inmoov-dsl[plot]'")) from None
    return Figure, Patch


def moving_servos(plan: Plan, sent: dict) -> list[int]:
    """The servos the gesture moves or sends a value to, in profile order."""
    moved = {i for step in plan.steps for i in step.servos}
    return [i for i in range(len(plan.tracks)) if i in moved or i in sent]


def plot(plan: Plan, compiled: Compiled, path: str | os.PathLike,
         contacts: Sequence[tuple[float, str]] = ()) -> None:
    """Draw the gesture to ``path`` (the suffix picks the format: .png, .svg, .pdf);
    ``contacts``: (time, what) of each place the robot meets itself, marked."""
    figure(plan, compiled, contacts).savefig(path, dpi=110)


def figure(plan: Plan, compiled: Compiled, contacts: Sequence[tuple[float, str]] = ()):
    """The gesture drawn: a matplotlib ``Figure``; each of ``contacts`` a line across
    the rows at its time."""
    Figure, Patch = _matplotlib()  # noqa: N806 (classes)
    sent = sent_values(plan, compiled)
    rows = [None] * len(plan.sounds) + (moving_servos(plan, sent) or [0])
    end = max(plan.duration, max((float(t[-1]) for t, _ in sent.values() if len(t)),
                                 default=0.0))
    end += 0.03 * end + 0.05  # room for the last keyframe's number
    t = np.linspace(0.0, end, max(200, int(end / 0.002)))
    fig = Figure(figsize=(12, 1.2 + 1.7 * len(rows)), layout="constrained")
    grid = fig.add_gridspec(len(rows), 2, width_ratios=(3, 1.3))
    total = sum(len(s.data) for s in compiled.streams)
    title = (f"{compiled.gesture} on {plan.profile.name}: {compiled.duration:.2f} s, "
             f"{total:,} bytes")  # a long name wraps, within the figure's width
    fig.suptitle(textwrap.fill(title, TITLE_WIDTH, break_on_hyphens=False), fontsize=13,
                 x=0.01, ha="left")
    first_pos = first_vel = None
    timed = []  #: the rows' position axes, where a contact is marked
    for k, (start, speech) in enumerate(plan.sounds):
        ax = fig.add_subplot(grid[k, 0], sharex=first_pos)
        timed.append(ax)
        first_pos = first_pos or ax
        _sound_row(ax, start, speech, sent.get(speech.servo, (np.empty(0), np.empty(0))),
                   plan.start[speech.servo], end)
        key = fig.add_subplot(grid[k, 1])
        key.axis("off")
        key.legend(*ax.get_legend_handles_labels(), loc="center left", fontsize=9,
                   frameon=False)
    for row, i in enumerate(rows[len(plan.sounds):], len(plan.sounds)):
        pos = fig.add_subplot(grid[row, 0], sharex=first_pos)
        vel = fig.add_subplot(grid[row, 1], sharex=first_vel)
        timed.append(pos)
        first_pos, first_vel = first_pos or pos, first_vel or vel
        _servo_row(pos, vel, plan, i, sent.get(i, (np.empty(0), np.empty(0))), t)
        if row < len(rows) - 1:
            pos.tick_params(labelbottom=False)
            vel.tick_params(labelbottom=False)
        if row == len(plan.sounds):
            pos.set_title("position (command degrees)", fontsize=10, loc="left")
            vel.set_title("velocity (command degrees / s)", fontsize=10, loc="left")
    pos.set_xlabel("time (s)")
    vel.set_xlabel("time (s)")
    for ax in timed:
        for k, (at, _) in enumerate(contacts):
            ax.axvline(at, color=CONTACT_COLOUR, lw=1.6, ls="-.",
                       label="the robot meets itself (gestc check says where)" if not k
                       else None)
    _legend(fig, fig.axes[2 * len(plan.sounds)], first_vel, plan, Patch)
    return fig


def _servo_row(pos, vel, plan: Plan, i: int, sent: tuple[np.ndarray, np.ndarray],
               t: np.ndarray) -> None:
    """Servo ``i``'s row: its position (planned, as the board holds the values
    ``sent``, keyframes) on ``pos``, its planned velocity between its limits on ``vel``;
    ``t`` samples the time axis, to its end."""
    servo, track, end = plan.profile.servos[i], plan.tracks[i], float(t[-1])
    for ax in (pos, vel):
        for step in plan.steps:
            if step.kind == "hold":
                ax.axvspan(step.start, step.end, color=HOLD_COLOUR, lw=0)
        ax.grid(True, color="#dddddd", lw=0.6)
        ax.set_xlim(0, end)
    held_t, held_v = _held(sent, plan.start[i], end)
    pos.plot(t, track.position(t), color=PLAN_COLOUR, lw=2.4, alpha=0.55,
             label="planned position")
    pos.step(held_t, held_v, where="post", color=SENT_COLOUR, lw=0.9,
             label="values sent (as the board holds them)")
    _keyframes(pos, plan, i)
    _sounds(pos, plan, i)
    pos.set_ylim(-12, 192)
    pos.set_yticks([0, 90, 180])
    pos.set_ylabel(f"{servo.name}\n(id {servo.id})", rotation=0, ha="right",
                   va="center", fontsize=10)
    vel.plot(t, track.velocity(t), color=PLAN_COLOUR, lw=1.4, label="planned velocity")
    for sign in (1, -1):
        vel.axhline(sign * servo.max_velocity, color=LIMIT_COLOUR, ls="--", lw=1,
                    label="velocity limit" if sign > 0 else None)
    vel.set_ylim(-1.15 * servo.max_velocity, 1.15 * servo.max_velocity)


def _held(sent: tuple[np.ndarray, np.ndarray], first: float, end: float
          ) -> tuple[np.ndarray, np.ndarray]:
    """The values a board holds, to draw as steps up to ``end``: ``first`` (the start
    pose), then each value ``sent`` as it arrives."""
    times, values = sent
    return (np.concatenate(([0.0], times, [end])),
            np.concatenate(([first], values, [values[-1] if len(values) else first])))


def _sound_row(ax, start: float, speech, sent: tuple[np.ndarray, np.ndarray],
               first: float, end: float) -> None:
    """A ``say``'s row: its waveform (-1..1), its loudness (0..1) and the mouth as its
    board receives it, from closed (0) to open (1)."""
    from ..compiling.speech import HOP

    sound, voice = speech.sound, speech.voice
    bins = max(1, len(sound.samples) // 3000)
    count = len(sound.samples) // bins
    cut = sound.samples[:count * bins].reshape(count, bins)
    at = start + (np.arange(count) + 0.5) * bins / sound.rate
    ax.fill_between(at, cut.min(axis=1), cut.max(axis=1), color="#999999", lw=0,
                    label="the sound")
    ax.plot(start + np.arange(len(speech.levels)) * HOP, speech.levels, color=SOUND_COLOUR,
            lw=1.6, label="its loudness")
    held_t, held_v = _held(sent, first, end)
    ax.step(held_t, (held_v - voice.closed) / (voice.opened - voice.closed), where="post",
            color=SENT_COLOUR, lw=1.2, label=f"the {voice.mouth} as its board receives it\n"
            "(0 closed, 1 open)")
    ax.set_xlim(0, end)
    ax.set_ylim(-1.05, 1.15)
    ax.grid(True, color="#dddddd", lw=0.6)
    ax.set_title(f'say "{sound.source}" at {start:.2f} s', fontsize=10, loc="left")
    ax.tick_params(labelbottom=False)


def _sounds(ax, plan: Plan, servo: int) -> None:
    """Where this servo is a mouth: each sound's loudness, as the opening it asks (a
    shaded envelope behind the track)."""
    from ..compiling.speech import HOP

    for start, speech in plan.sounds:
        if speech.servo != servo:
            continue
        t = start + np.arange(len(speech.levels)) * HOP
        ax.fill_between(t, speech.voice.closed, speech.openings, color=SOUND_COLOUR,
                        alpha=0.25, lw=0, label="the sound's loudness, as an opening")


def _legend(fig, pos, vel, plan: Plan, Patch) -> None:  # noqa: N803 (a class)
    """One legend for the figure, below the rows (the title has the top to itself, however
    long the gesture's name): the lines of the first row, keyframes, holds."""
    handles, labels = (pos.get_legend_handles_labels()[k] + vel.get_legend_handles_labels()[k]
                       for k in (0, 1))
    if plan.sounds and "the sound's loudness, as an opening" not in labels:
        handles.append(Patch(color=SOUND_COLOUR, alpha=0.25))
        labels.append("the sound's loudness, as an opening")
    handles.append(pos.scatter([], [], color="black", s=18))
    labels.append("keyframe, numbered as the steps of gestc show")
    if any(step.kind == "hold" for step in plan.steps):
        handles.append(Patch(color=HOLD_COLOUR))
        labels.append("hold")
    fig.legend(handles, labels, loc="outside lower center", ncols=3, fontsize=9,
               frameon=False)


def _keyframes(ax, plan: Plan, servo: int) -> None:
    """Mark where each move of this servo ends, numbered like ``gestc show``."""
    for n, step in enumerate(plan.steps, 1):
        if step.kind != "move" or servo not in step.servos:
            continue
        value = float(plan.tracks[servo].position(step.end))
        ax.scatter([step.end], [value], color="black", s=18, zorder=5)
        below = value > 150
        ax.annotate(str(n), (step.end, value), xytext=(0, -11 if below else 5),
                    textcoords="offset points", ha="center", fontsize=8,
                    va="top" if below else "bottom")
