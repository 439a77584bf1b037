"""From a recorded stream to a short gesture (``gestc record``): pure, no clock, no I/O.

1. ``StreamReader`` reads the bytes as a servo board would (CANCEL, pairs, signals
   skipped) with the time each arrived, and keeps every (time, servo, value): a glove's
   stream, or any stream in the protocol.
2. ``traces`` cleans each servo's samples (a lone wrong one, made by a byte lost in a
   pair, is dropped) and draws a line through them, on every 20 ms servo frame: a
   glove reports a finger once it has moved more than its dead-band, so the finger is
   within that band of the line.
3. ``keyframes`` picks the poses: a move is planned from rest to rest, so keyframes
   belong where the motion pauses or turns; of those frames, a shortest path picks the
   fewest whose moves, planned exactly as the compiler plans them, stay within the
   tolerance of the recording.
4. ``to_gest`` writes them as a gesture in the canonical layout, durations taken from
   the recording.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from .fmt import format_source
from .plan import Planner
from .profile import Profile
from .protocol import MAX_VALUE, SERVO_FRAME, Signal
from .resolve import Action

DEFAULT_TOLERANCE = 3.0  #: command degrees
OUTLIER = 12.0  #: command degrees from both neighbours makes a lone sample an outlier
SILENCE = 0.1  #: s without a report
WINDOW = 40  #: a move spans at most this many candidate pauses


@dataclass
class StreamReader:
    """Bytes in the protocol, as they arrive, to (time, servo ID, value) samples."""

    ids: frozenset[int]  #: the servo IDs to keep
    samples: list[tuple[float, int, int]] = field(default_factory=list)
    skipped: int = 0  #: bytes before the first CANCEL, pairs for other IDs, signals
    pending: int | None = None
    synced: bool = False  #: a CANCEL has come: pairs can be told apart

    def feed(self, t: float, data: Iterable[int]) -> None:
        for byte in data:
            if byte == Signal.CANCEL:
                self.pending = None
                self.synced = True
            elif not self.synced:
                self.skipped += 1  # joined mid-command: wait for the next CANCEL
            elif byte > MAX_VALUE:
                self.skipped += 1  # a signal (WAIT, DUMP...) or noise
                if self.pending is not None and byte < min(Signal):
                    self.pending = None  # not a value: the pair is lost
            elif self.pending is None:
                self.pending = byte
            else:
                sid, self.pending = self.pending, None
                if sid in self.ids:
                    self.samples.append((t, sid, byte))
                else:
                    self.skipped += 1


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


def on_the_clock(samples: Sequence[tuple[float, int, int]], period: float
                 ) -> list[tuple[float, int, int]]:
    """A glove reports on its own clock, every ``period`` s; the computer sees the
    reports late by a varying few ms (a USB-serial chip holds them up to 16 ms). When
    the arrival times fit that clock, each is moved back onto its tick."""
    if len(samples) < 3:
        return list(samples)
    t = np.asarray([s[0] for s in samples])
    t0 = t[0]
    shift = float(np.median(t - t0 - np.round((t - t0) / period) * period))
    ticks = np.round((t - t0 - shift) / period)
    off = t - t0 - shift - ticks * period
    if np.mean(np.abs(off) < period / 3) < 0.9:
        return list(samples)  # not a periodic sender: the arrival times as they are
    return [(t0 + shift + k * period, sid, v)
            for k, (_, sid, v) in zip(ticks.tolist(), samples, strict=True)]


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
    """Where the recorded motion goes: a pose (servo index -> value), reached ``at``;
    the move into it starts its servos ``stagger`` s apart, in ``order``."""

    at: float  #: s
    pose: dict[int, int]
    stagger: float = 0.0
    order: tuple[int, ...] = ()  #: servo indices, when staggered


@dataclass(frozen=True)
class Fit:
    keyframes: tuple[Keyframe, ...]
    error: float  #: degrees the planned motion strays beyond the recording's band, at most
    stretched: tuple[float, ...]  #: times of moves the limits make slower than recorded


def keyframes(tr: Traces, profile: Profile, tolerance: float = DEFAULT_TOLERANCE) -> Fit:
    """The fewest keyframes whose planned moves stay within ``tolerance`` of the
    recording. A move is planned from rest to rest, so keyframes belong where the hand
    pauses or turns: the candidates are the frames where the recorded motion is
    slowest, and a shortest path over them (each hop one move, planned exactly as the
    compiler plans it) picks the fewest that fit: first the least error beyond the
    tolerance (summed over the moves; a move the limits would slow down counts a
    thousand degrees), then the fewest moves."""
    servos = sorted(tr.values)
    if not servos:
        return Fit((), 0.0, ())
    rec = np.stack([tr.values[i] for i in servos], axis=1)  # [frame][servo]
    poses = np.clip(np.floor(rec + 0.5), 0, MAX_VALUE).astype(int)
    planner = Planner(profile)
    last = len(tr.times) - 1
    if last == 0:
        return Fit((Keyframe(0.0, dict(zip(servos, poses[0].tolist(), strict=True))),),
                   0.0, ())
    frames = sorted({0, last, *_pauses(rec, [profile.servos[i].max_velocity
                                             for i in servos])})
    best: list[tuple[float, int, int]] = [(0.0, 0, -1)]  # (excess, hops, previous)
    for j in range(1, len(frames)):
        options = []
        for i in range(max(0, j - WINDOW), j):
            error, slow, _ = _segment(planner, servos, tr.times, rec, poses, frames[i],
                                      frames[j], tr.band)
            excess = max(0.0, error - tolerance) + (1000.0 if slow else 0.0)
            options.append((best[i][0] + excess, best[i][1] + 1, i))
        best.append(min(options))
    path = [len(frames) - 1]
    while best[path[-1]][2] >= 0:
        path.append(best[path[-1]][2])
    path.reverse()
    cuts = [frames[k] for k in path]
    results = [_segment(planner, servos, tr.times, rec, poses, a, b, tr.band)
               for a, b in zip(cuts, cuts[1:], strict=False)]
    worst = max((error for error, _, _ in results), default=0.0)
    stretched = tuple(float(tr.times[a]) for a, (_, slow, _) in zip(cuts, results, strict=False)
                      if slow)
    staggers = [(0.0, ())] + [wave for _, _, wave in results]
    keys = tuple(Keyframe(float(tr.times[k]), dict(zip(servos, poses[k].tolist(), strict=True)),
                          *wave) for k, wave in zip(cuts, staggers, strict=True))
    return Fit(keys, worst, stretched)


def _pauses(rec: np.ndarray, limits: list[float]) -> list[int]:
    """Frames where the recorded motion is slowest: near the local minima of its speed
    (each servo's share of its velocity limit, the largest of them, smoothed over 5
    frames); of a still stretch, near its first and last frame."""
    if len(rec) < 3:
        return []
    velocity = np.gradient(rec, SERVO_FRAME, axis=0) / np.asarray(limits)
    speed = np.convolve(np.abs(velocity).max(axis=1), np.ones(5) / 5, mode="same")
    low = (speed[1:-1] <= speed[:-2] + 1e-9) & (speed[1:-1] <= speed[2:] + 1e-9)
    frames = np.flatnonzero(low) + 1
    # a run of equal minima (a hold) counts by its ends, and the frames around them:
    # smoothing shortens a hold by two frames at each end
    out: set[int] = set()
    for n, k in enumerate(frames):
        inner = 0 < n < len(frames) - 1 and frames[n - 1] == k - 1 and frames[n + 1] == k + 1
        if not inner:
            out.update(range(max(0, k - 2), min(len(rec), k + 3)))
    return sorted(out)


def _segment(planner: Planner, servos: list[int], times: np.ndarray, rec: np.ndarray,
             poses: np.ndarray, a: int, b: int, band: float
             ) -> tuple[float, bool, tuple[float, tuple[int, ...]]]:
    """Plan the move from frame a's pose to frame b's over their time, all servos
    together, or (if that follows the recording better) one after another in the order
    they started, ``stagger`` apart: (how far it strays beyond ``band`` of the
    recording, whether the limits stretch it, (stagger, order))."""
    start = [s.rest for s in planner.profile.servos]
    for k, i in enumerate(servos):
        start[i] = int(poses[a][k])
    span = times[a:b + 1] - times[a]
    total = float(span[-1])

    def try_plan(targets, stagger=0.0):
        over = total - stagger * (len(targets) - 1)
        plan = planner.plan([Action(tuple(targets), over=over, stagger=stagger)], start)
        planned = np.stack([plan.tracks[i].position(span) for i in servos], axis=1)
        error = max(0.0, float(np.abs(planned - rec[a:b + 1]).max()) - band)
        return error, plan.duration > total + 1e-6

    changed = [k for k in range(len(servos)) if poses[b][k] != poses[a][k]]
    best = (*try_plan([(servos[k], int(poses[b][k])) for k in changed]), (0.0, ()))
    if len(changed) > 1 and best[0] > 0:
        moved = np.abs(rec[a:b + 1, changed] - rec[a, changed]) > band + 1
        first = [int(np.argmax(m)) if m.any() else 0 for m in moved.T]
        order = sorted(range(len(changed)), key=lambda n: first[n])
        spread = (first[order[-1]] - first[order[0]]) * SERVO_FRAME
        stagger = round(spread / (len(changed) - 1), 2)
        if stagger >= SERVO_FRAME and total - stagger * (len(changed) - 1) > SERVO_FRAME:
            targets = [(servos[changed[n]], int(poses[b][changed[n]])) for n in order]
            error, slow = try_plan(targets, stagger)
            if (slow, error) < (best[1], best[0]):
                best = (error, slow, (stagger, tuple(i for i, _ in targets)))
    return best


def to_gest(name: str, fit: Fit, profile: Profile, about: Sequence[str] = ()) -> str:
    """The keyframes as a gesture: the first pose, then each move (only the servos that
    change, ``over`` the recorded time) or hold, in the canonical layout."""
    if not fit.keyframes:
        raise ValueError("nothing was recorded")
    names = [s.name for s in profile.servos]
    first = fit.keyframes[0]
    lines = [f"# {line}" for line in about]
    lines.append(f"{name}:")
    lines.append("    " + ", ".join(f"{names[i]} {v}" for i, v in first.pose.items()))
    hold = 0.0
    previous = first
    for key in fit.keyframes[1:]:
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


def start_pose(fit: Fit, profile: Profile) -> Mapping[str, int]:
    """The first recorded pose by servo name: where the recording starts."""
    return {profile.servos[i].name: v for i, v in fit.keyframes[0].pose.items()}
