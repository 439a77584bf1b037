"""The mouth moving with a sound (pure): the sound's loudness as a viewer sees it, the
opening it asks of the mouth, and the mouth's track, planned for the whole sound at once
under its servo's limits (``mouth.fit``), LEAD ahead of the sound.

The loudness is the RMS of each HOP of sound, averaged over SMOOTH (a syllable's
swell), from 0 (silence: under GATE of the loudest) to 1 (the loudest). The track aims
at the opening the loudness asks LEAD later. A silence of QUIET or more (in the
loudness; about 250 ms of sound, less the averaging) closes the mouth and holds it still
from CLOSING after it begins to the moment the next sound's opening starts.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from ruckig import InputParameter, Ruckig, Trajectory

from ..profiles.data import Profile, Servo, Voice
from ..voice.wav import Sound
from .mouth import fit, runs
from .tracks import Track, TrackBuilder

HOP = 0.010  #: s between loudness values, and between the track's knots
SMOOTH = 0.100  #: s of sound each loudness value averages
GATE = 0.03  #: of the loudest: quieter is silence
LEAD = 0.040  #: s; the mouth's opening leads the sound by this (two servo frames)
QUIET = 0.150  #: s of silent loudness that holds the mouth closed and still...
CLOSING = 0.080  #: ...from this long after the silence begins (the mouth closing)
AFTER = 0.300  #: s the track may take after the sound to close


@dataclass(frozen=True, eq=False)
class Speech:
    """A ``say`` for one profile: its sound, the mouth's servo and the opening the sound
    asks every HOP (closed..open)."""

    sound: Sound
    servo: int  #: the mouth's index in the profile
    voice: Voice
    levels: np.ndarray = field(repr=False)  #: loudness 0..1 every HOP

    @property
    def openings(self) -> np.ndarray:
        """The opening the sound asks, every HOP."""
        v = self.voice
        return v.closed + (v.opened - v.closed) * self.levels


def loudness(sound: Sound) -> np.ndarray:
    """0 (silence) .. 1 (the loudest) every HOP s."""
    hop = max(1, round(sound.rate * HOP))
    x = sound.samples.astype(np.float64)
    count = -(-len(x) // hop)
    x = np.concatenate((x, np.zeros(count * hop - len(x))))
    rms = np.sqrt((x.reshape(count, hop) ** 2).mean(axis=1))
    width = max(1, round(SMOOTH / HOP))
    heard = np.convolve(rms, np.ones(width) / width, mode="same")
    loudest = float(heard.max()) if len(heard) else 0.0
    if loudest <= 0:
        return np.zeros(len(heard))
    levels = heard / loudest
    levels[levels < GATE] = 0.0
    return levels


def _move_time(servo: Servo, start: float, target: float) -> float:
    ruckig, inp, traj = Ruckig(1), InputParameter(1), Trajectory(1)
    inp.max_velocity = [servo.max_velocity]
    inp.max_acceleration = [servo.max_acceleration]
    inp.max_jerk = [servo.max_jerk]
    inp.current_position, inp.target_position = [float(start)], [float(target)]
    ruckig.calculate(inp, traj)
    return traj.duration


def delay(speech: Speech, servo: Servo) -> float:
    """How long the sound waits after the step begins: a sound that starts at once
    waits until the mouth, from rest, could be half open (LEAD before it)."""
    voice = speech.voice
    ready = LEAD + _move_time(servo, voice.closed, (voice.closed + voice.opened) / 2)
    heard = np.flatnonzero(speech.levels)
    onset = (heard[0] * HOP + SMOOTH / 2) if len(heard) else ready
    return max(0, round((ready - onset) / HOP)) * HOP


def track(speech: Speech, servo: Servo, start: float) -> tuple[Track, float, float]:
    """The mouth's track from ``start`` (at rest), how long it moves, and when the
    sound starts (``delay``): aiming LEAD ahead at the opening the sound asks, still
    and closed in each long silence, and closed at rest after the sound."""
    voice = speech.voice
    closed = float(voice.closed)
    wait = delay(speech, servo)
    heard = np.arange(round((wait + speech.sound.duration + LEAD + AFTER) / HOP)) \
        - round((wait - LEAD) / HOP)
    inside = (heard >= 0) & (heard < len(speech.levels))
    target = np.where(inside, speech.openings[np.clip(heard, 0, len(speech.levels) - 1)],
                      closed)
    fixed = np.full(len(target) + 2, np.nan)
    fixed[:3] = start
    free_from = int(np.ceil(_move_time(servo, start, closed) / HOP))
    for a, b in runs(target == closed):
        if b - a < round(QUIET / HOP):
            continue
        a = max(a + round(CLOSING / HOP), free_from)
        fixed[a:b + 2] = closed  # still and closed from knot a to knot b
    fixed[-3:] = closed
    span = (min(closed, voice.opened, start), max(closed, voice.opened, start))
    c = fit(target, fixed, servo, HOP, span, closed)
    p0, p1, p2, p3 = c[:-3], c[1:-2], c[2:-1], c[3:]
    coefs = np.stack(((p0 + 4 * p1 + p2) / 6, (p2 - p0) / (2 * HOP),
                      (p0 - 2 * p1 + p2) / HOP ** 2, (p3 - 3 * p2 + 3 * p1 - p0) / HOP ** 3), 1)
    moving = np.flatnonzero(np.any(np.abs(coefs - [closed, 0, 0, 0]) > 1e-9, axis=1))
    pieces = int(moving[-1]) + 1 if len(moving) else 0
    breaks = np.arange(pieces + 1) * HOP
    rest = np.array([[closed if pieces else float(start), 0.0, 0.0, 0.0]])
    return Track(breaks, np.concatenate((coefs[:pieces], rest))), pieces * HOP, wait


def follow(speech: Speech, profile: Profile, now: float, pose: list[int],
           builders: list[TrackBuilder]) -> tuple[float, float]:
    """Plan ``speech``'s mouth from ``now`` (its servo at rest at ``pose``) into the
    gesture's tracks; the step's length (until the sound ends, or the mouth closes if
    later) and when the sound starts (from ``now``)."""
    i = speech.servo
    mouth, moved, wait = track(speech, profile.servos[i], pose[i])
    builders[i].extend(mouth, now)
    pose[i] = speech.voice.closed
    return max(wait + speech.sound.duration, moved), wait
