"""From a recorded stream to a short gesture (``gestc record``): pure, no clock, no I/O.

1. The samples: every (time, servo, value) of a glove's stream, a MIDI take or another
   tool's animation (``interchange.importing``).
2. ``traces`` cleans each servo's samples (a lone wrong one, made by a byte lost in a
   pair, is dropped) and draws a line through them on every 20 ms servo frame (a glove's
   finger is within its dead-band of the line).
3. ``keyframes`` picks the poses: a move is planned from rest to rest, so keyframes
   belong where the motion pauses or turns (``Recording.candidates``); of those frames,
   ``shortest_path`` picks the fewest whose moves (``Recording.segment``), planned
   exactly as the compiler plans them, stay within the tolerance of the recording.
4. ``to_gest`` writes them as a gesture in the canonical layout, timed as recorded.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ..boards.rig.encode import round_values
from ..compiling.actions import Action
from ..compiling.plan import Planner
from ..hardware import Profile
from ..language.fmt import format_source
from ..protocol import SERVO_FRAME

DEFAULT_TOLERANCE = 3.0  #: command degrees
OUTLIER = 12.0  #: command degrees from both neighbours makes a lone sample an outlier
SILENCE = 0.1  #: s without a report
WINDOW = 40  #: a move spans at most this many candidate pauses
SLOW = 1000.0  #: degrees of error a move the limits would slow down counts as


@dataclass(frozen=True)
class Traces:
    """Each servo's recorded value on every servo frame from the first sample on."""

    times: np.ndarray  #: s from the first sample, every SERVO_FRAME
    values: dict[int, np.ndarray]  #: servo index -> command degrees, one per frame
    samples: int  #: samples kept
    dropped: int  #: outliers dropped
    band: float = 0.0  #: command degrees the true value may be from the line


def _drop_spikes(t: np.ndarray, v: np.ndarray, vmax: float
                 ) -> tuple[np.ndarray, np.ndarray, int]:
    """Drop lone samples (a byte lost in a pair makes one): far from the median of
    their neighbourhood and reached faster than three times the servo's limit."""
    n = len(v)
    if n < 3:
        return t, v, 0
    window = np.stack([v[np.clip(np.arange(n) + d, 0, n - 1)] for d in (-1, 0, 1)])
    window[:, 0], window[:, -1] = v[:3], v[-3:]
    median = np.median(window, axis=0)
    dt = np.clip(np.abs(np.diff(t)), SERVO_FRAME, SILENCE)  # a jump after a silence counts
    speed = np.abs(np.diff(v)) / dt
    fast = np.concatenate(([speed[0]], np.minimum(speed[:-1], speed[1:]), [speed[-1]]))
    spike = (np.abs(v - median) > OUTLIER) & (fast > 3 * vmax)
    return t[~spike], v[~spike], int(spike.sum())


def traces(samples: Sequence[tuple[float, int, int]], profile: Profile,
           deadband: float = 0.0) -> Traces:
    """The samples of each of ``profile``'s servos, cleaned, on the servo frame grid.
    A glove reports a finger only once it has moved more than its ``deadband``, so the
    finger is anywhere within that band of the line drawn through its reports."""
    if not samples:
        return Traces(np.zeros(1), {}, 0, 0, deadband)
    t0 = samples[0][0]
    end = samples[-1][0] - t0
    grid = np.arange(int(np.ceil(end / SERVO_FRAME + 1e-9)) + 1) * SERVO_FRAME
    index = {s.id: i for i, s in enumerate(profile.servos)}
    heard = np.unique([s[0] - t0 for s in samples])  # when anything came
    values: dict[int, np.ndarray] = {}
    kept = dropped = 0
    for sid in sorted({sid for _, sid, _ in samples}):
        t = np.asarray([s[0] - t0 for s in samples if s[1] == sid])
        v = np.asarray([s[2] for s in samples if s[1] == sid], dtype=float)
        t, v, lost = _drop_spikes(t, v, profile.servos[index[sid]].max_velocity)
        kept, dropped = kept + len(v), dropped + lost
        # close samples are a motion: straight from one to the next (arrival times
        # jitter by a few ms, a held value would lag a whole frame behind); after a
        # silence, a small change ends a hold (held until a frame before it), a big one
        # means reports were lost (straight across the stream's longest silence)
        lost_jump = deadband + 2 * SERVO_FRAME * profile.servos[index[sid]].max_velocity
        knots_t, knots_v = list(t), list(v)
        for k in np.flatnonzero(np.diff(t) > SILENCE):
            if abs(v[k + 1] - v[k]) > lost_jump:
                inside = heard[(heard >= t[k]) & (heard <= t[k + 1])]
                m = int(np.argmax(np.diff(inside)))
                knots_t.append(inside[m])
            else:
                knots_t.append(t[k + 1] - SERVO_FRAME)
            knots_v.append(v[k])
        order = np.argsort(knots_t, kind="stable")
        values[index[sid]] = np.interp(grid, np.asarray(knots_t)[order],
                                       np.asarray(knots_v)[order])
    return Traces(grid, values, kept, dropped, deadband)


@dataclass(frozen=True)
class Keyframe:
    """A pose (servo index -> value) reached ``at``, its servos started ``stagger`` s
    apart in ``order``."""

    at: float  #: s
    pose: dict[int, int]
    stagger: float = 0.0
    order: tuple[int, ...] = ()  #: servo indices, when staggered


@dataclass(frozen=True)
class Fit:
    """The keyframes chosen for a recording, and how well their moves follow it."""

    keyframes: tuple[Keyframe, ...]
    error: float  #: degrees the planned motion strays beyond the recording's band, at most
    stretched: tuple[float, ...]  #: times of moves the limits make slower than recorded


@dataclass(frozen=True)
class Segment:
    """A move between two frames of a recording, planned as the compiler plans it."""

    error: float  #: degrees it strays beyond the recording's band, at most
    slow: bool  #: the limits make it slower than recorded
    stagger: float = 0.0  #: s between its servos' starts
    order: tuple[int, ...] = ()  #: servo indices, when staggered

    def cost(self, tolerance: float) -> tuple[float, float]:
        """What the keyframe choice minimises: degrees beyond tolerance (SLOW if slow)."""
        return max(0.0, self.error - tolerance) + (SLOW if self.slow else 0.0), self.error


def shortest_path(count: int, cost: Callable[[int, int], tuple[float, float]],
                  window: int = WINDOW) -> list[int]:
    """Nodes 0 to ``count - 1``: the least total of ``cost(i, j)[0]``, then the fewest
    hops, then the least worst ``cost(i, j)[1]`` (then the earliest nodes), each hop at
    most ``window`` ahead."""
    best = [(0.0, 0, 0.0, -1)]  # (cost, hops, worst, previous)
    for j in range(1, count):
        best.append(min((best[i][0] + c, best[i][1] + 1, max(best[i][2], e), i)
                        for i in range(max(0, j - window), j) for c, e in [cost(i, j)]))
    path = [count - 1]
    while best[path[-1]][3] >= 0:
        path.append(best[path[-1]][3])
    return path[::-1]


def keyframes(tr: Traces, profile: Profile, tolerance: float = DEFAULT_TOLERANCE) -> Fit:
    """The fewest keyframes whose moves stay within ``tolerance`` of the recording: the
    least error beyond it summed (a move the limits slow counts SLOW), then fewest moves."""
    return Recording(tr, profile, tolerance).fit()


class Recording:
    """A recording's traces, ready for the keyframe choice: the recorded values and
    their poses (whole degrees) on every frame, for the servos it has."""

    def __init__(self, traces: Traces, profile: Profile, tolerance: float = DEFAULT_TOLERANCE):
        self.traces, self.profile, self.tolerance = traces, profile, tolerance
        self.servos = sorted(traces.values)  #: servo indices
        self.values = np.stack([traces.values[i] for i in self.servos], axis=1) \
            if self.servos else np.zeros((len(traces.times), 0))  #: [frame][servo]
        self.poses = round_values(self.values)
        self.planner = Planner(profile)

    def fit(self) -> Fit:
        """The keyframes: those of ``candidates`` that ``shortest_path`` picks."""
        if not self.servos:
            return Fit((), 0.0, ())
        if len(self.traces.times) == 1:
            return Fit((self.keyframe(0),), 0.0, ())
        frames = self.candidates()
        path = shortest_path(len(frames), lambda i, j: self.segment(
            frames[i], frames[j]).cost(self.tolerance))
        cuts = [frames[k] for k in path]
        moves = [self.segment(a, b) for a, b in zip(cuts, cuts[1:], strict=False)]
        keys = (self.keyframe(cuts[0]),
                *(self.keyframe(b, move) for b, move in zip(cuts[1:], moves, strict=True)))
        stretched = tuple(float(self.traces.times[a])
                          for a, move in zip(cuts, moves, strict=False) if move.slow)
        return Fit(keys, max((move.error for move in moves), default=0.0), stretched)

    def candidates(self) -> list[int]:
        """The frames a keyframe may fall on: the first, the last, and where the motion
        is slowest: near the local minima of its speed (each servo's share of its
        velocity limit, the largest of them, smoothed over 5 frames); of a still
        stretch, near its first and last frame, and where the poses stop or start."""
        rec = self.values
        out = {0, len(rec) - 1}
        if len(rec) < 3:
            return sorted(out)
        limits = [self.profile.servos[i].max_velocity for i in self.servos]
        velocity = np.gradient(rec, SERVO_FRAME, axis=0) / np.asarray(limits)
        speed = np.convolve(np.abs(velocity).max(axis=1), np.ones(5) / 5, mode="same")
        low = (speed[1:-1] <= speed[:-2] + 1e-9) & (speed[1:-1] <= speed[2:] + 1e-9)
        frames = np.flatnonzero(low) + 1
        # a run of equal minima (a hold) counts by its ends, and the frames around
        # them: smoothing shortens a hold by two frames at each end
        for n, k in enumerate(frames):
            if not (0 < n < len(frames) - 1 and frames[n - 1] == k - 1
                    and frames[n + 1] == k + 1):
                out.update(range(max(0, k - 2), min(len(rec), k + 3)))
        still = np.all(np.diff(self.poses, axis=0) == 0, axis=1)  # an animation's move
        for k in (np.flatnonzero(still[1:] != still[:-1]) + 1).tolist():  # ends on a frame
            out.update(range(max(0, k - 1), min(len(rec), k + 2)))
        return sorted(out)

    def keyframe(self, k: int, into: Segment = Segment(0.0, False)) -> Keyframe:
        """Frame ``k``'s pose as a keyframe, reached by the move ``into``."""
        return Keyframe(float(self.traces.times[k]),
                        dict(zip(self.servos, self.poses[k].tolist(), strict=True)),
                        into.stagger, into.order)

    def segment(self, a: int, b: int) -> Segment:
        """The move from frame a's pose to frame b's over their time, all servos
        together, or (if that follows the recording better) one after another in the
        order they started."""
        changed = [k for k in range(len(self.servos)) if self.poses[b][k] != self.poses[a][k]]
        together = self._plan(a, b, [(self.servos[k], int(self.poses[b][k]))
                                     for k in changed])
        if len(changed) > 1 and together.error > 0:
            staggered = self._staggered(a, b, changed)
            if staggered is not None and \
                    (staggered.slow, staggered.error) < (together.slow, together.error):
                return staggered
        return together

    def _staggered(self, a: int, b: int, changed: list[int]) -> Segment | None:
        """The move with the ``changed`` servos started ``stagger`` apart in the order
        the recording moved them, or None if they moved together."""
        moved = np.abs(self.values[a:b + 1, changed] - self.values[a, changed]) \
            > self.traces.band + 1
        first = [int(np.argmax(m)) if m.any() else 0 for m in moved.T]
        order = sorted(range(len(changed)), key=lambda n: first[n])
        spread = (first[order[-1]] - first[order[0]]) * SERVO_FRAME
        stagger = round(spread / (len(changed) - 1), 2)
        total = float(self.traces.times[b] - self.traces.times[a])
        if stagger < SERVO_FRAME or total - stagger * (len(changed) - 1) <= SERVO_FRAME:
            return None
        targets = [(self.servos[changed[n]], int(self.poses[b][changed[n]])) for n in order]
        return self._plan(a, b, targets, stagger)

    def _plan(self, a: int, b: int, targets: list[tuple[int, int]], stagger: float = 0.0
              ) -> Segment:
        """``targets`` planned from frame a's pose over the time to frame b, as recorded."""
        start = [s.rest for s in self.profile.servos]
        for k, i in enumerate(self.servos):
            start[i] = int(self.poses[a][k])
        span = self.traces.times[a:b + 1] - self.traces.times[a]
        total = float(span[-1])
        over = total - stagger * (len(targets) - 1)
        plan = self.planner.plan([Action(tuple(targets), over=over, stagger=stagger)], start)
        planned = np.stack([plan.tracks[i].position(span) for i in self.servos], axis=1)
        error = max(0.0, float(np.abs(planned - self.values[a:b + 1]).max()) - self.traces.band)
        return Segment(error, plan.duration > total + 1e-6, stagger,
                       tuple(i for i, _ in targets) if stagger else ())


def to_gest(name: str, keys: Sequence[Keyframe], profile: Profile,
            about: Sequence[str] = ()) -> str:
    """The keyframes as a gesture: the first pose, then each move (only the servos that
    change, ``over`` the recorded time) or hold, in the canonical layout; ``about`` are
    comment lines above it."""
    if not keys:
        raise ValueError("nothing was recorded")
    names = [s.name for s in profile.servos]
    first = keys[0]
    lines = [*(f"# {line}" for line in about), f"{name}:"]
    lines.append("    " + ", ".join(f"{names[i]} {v}" for i, v in first.pose.items()))
    hold, previous = 0.0, first
    for key in keys[1:]:
        ms = round((key.at - previous.at) * 1000)
        changed = {i: v for i, v in key.pose.items() if previous.pose[i] != v}
        if not changed:
            hold += ms
        else:
            if hold:
                lines.append(f"    hold {round(hold)}ms")
                hold = 0
            order = key.order or tuple(changed)
            targets = ", ".join(f"{names[i]} {changed[i]}" for i in order if i in changed)
            if key.stagger:
                stagger = round(key.stagger * 1000)
                over = ms - stagger * (len(changed) - 1)
                lines.append(f"    {targets} over {over}ms stagger {stagger}ms")
            else:
                lines.append(f"    {targets} over {ms}ms")
        previous = key
    if hold:
        lines.append(f"    hold {round(hold)}ms")
    return format_source("\n".join(lines) + "\n")


def start_pose(keys: Sequence[Keyframe], profile: Profile) -> Mapping[str, int]:
    """The first keyframe's pose by servo name: where the recording starts."""
    return {profile.servos[i].name: v for i, v in keys[0].pose.items()}
