"""The mouth moving with a sound (pure): the sound's loudness as speech is heard, the
opening it asks of the mouth, and the mouth's track through its servo's limits, planned
ahead of the sound by the time the servo needs, so that the mouth is open when the sound
is loud and closed in silence.

The loudness is the RMS of WINDOW-long windows every HOP, in decibels: at or below a
gate (GATE dB under the loudest window, and never below FLOOR dBFS) it is silence, at
the loudest it is 1. The track is what a controller re-planning with ruckig every HOP
would follow, aiming each time at the opening LEAD later: a jerk-limited, time-optimal
approach to a target that moves.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from ruckig import InputParameter, Result, Ruckig, RuckigError, Trajectory

from ..profiles.data import Profile, Servo, Voice
from ..voice.wav import Sound
from .tracks import Track, TrackBuilder

HOP = 0.010  #: s between loudness values, and between the tracker's plans
WINDOW = 0.110  #: s of sound each loudness value hears: about a syllable
GATE = 30.0  #: dB below the loudest window: quieter is silence
FLOOR = -50.0  #: dBFS: quieter is silence, however quiet the loudest is
EASE = (1.0, 1 - 1e-6, 1 - 1e-3, 1 - 1e-2, 0.95, 0.8)  #: of the acceleration, in turn
RESPONSE = 0.040  #: s; the planned opening leads the sound by this (two servo frames)
#: the tracker's lag behind a moving target, as a share of its servo's full swing time
#: (measured on ten spoken sentences: benchmarks/voice.py)
LAGGING = 0.3


@dataclass(frozen=True, eq=False)
class Speech:
    """A ``say`` for one profile: its sound, the mouth's servo, the opening it follows
    every HOP (closed..open) and how far ahead of the sound the track aims."""

    sound: Sound
    servo: int  #: the mouth's index in the profile
    voice: Voice
    levels: np.ndarray = field(repr=False)  #: loudness 0..1 every HOP
    aim: float  #: s; how far ahead of the planned time the track aims

    @property
    def openings(self) -> np.ndarray:
        """The opening the sound asks, every HOP."""
        v = self.voice
        return v.closed + (v.opened - v.closed) * self.levels


def loudness(sound: Sound) -> np.ndarray:
    """0 (silence) .. 1 (the loudest) every HOP s."""
    hop = max(1, round(sound.rate * HOP))
    half = max(1, round(sound.rate * WINDOW / 2))
    x = sound.samples.astype(np.float64)
    sums = np.concatenate(([0.0], np.cumsum(x * x)))
    centres = np.arange(0, len(x), hop)
    lo, hi = np.maximum(centres - half, 0), np.minimum(centres + half, len(x))
    power = (sums[hi] - sums[lo]) / np.maximum(hi - lo, 1)
    db = 10 * np.log10(power + 1e-12)
    loudest = float(db.max()) if len(db) else FLOOR
    gate = max(loudest - GATE, FLOOR)
    if loudest <= gate:
        return np.zeros(len(db))
    return np.clip((db - gate) / (loudest - gate), 0.0, 1.0)


def aim(servo: Servo, voice: Voice) -> float:
    """How far ahead the track aims: RESPONSE, and what chasing a moving target costs
    the tracker, LAGGING of its servo's time from closed to open (rest to rest, at its
    limits)."""
    return RESPONSE + LAGGING * _move_time(servo, voice.closed, voice.opened)


def _move_time(servo: Servo, start: float, target: float) -> float:
    ruckig, inp, traj = Ruckig(1), InputParameter(1), Trajectory(1)
    _limits(inp, servo)
    inp.current_position, inp.target_position = [float(start)], [float(target)]
    ruckig.calculate(inp, traj)
    return traj.duration


def _limits(inp: InputParameter, servo: Servo) -> None:
    inp.max_velocity = [servo.max_velocity]
    inp.max_acceleration = [servo.max_acceleration]
    inp.max_jerk = [servo.max_jerk]


def track(speech: Speech, servo: Servo, start: float) -> tuple[Track, float]:
    """The mouth's track from ``start`` (at rest), and how long it moves: every HOP it
    plans again towards the opening ``speech.aim`` later, and after the sound it
    closes and comes to rest."""
    aims = speech.openings
    ahead = round(speech.aim / HOP)
    ruckig, inp, traj = Ruckig(1), InputParameter(1), Trajectory(1)
    _limits(inp, servo)
    builder = TrackBuilder(float(start))
    state = (float(start), 0.0, 0.0)
    closed, t, k = float(speech.voice.closed), 0.0, 0
    while True:
        aim = float(aims[k + ahead]) if k + ahead < len(aims) else closed
        inp.target_position = [aim]
        _calculate(ruckig, inp, traj, state)
        if k + ahead >= len(aims) and aim == closed:  # the last aim: all the way
            builder.phases(t, traj.profiles[0][0])
            builder.hold(t + traj.duration, closed)
            return builder.build(), t + traj.duration
        builder.phases_for(t, traj.profiles[0][0], HOP)
        if traj.duration > HOP:
            p, v, a = traj.at_time(HOP)
            state = (p[0], v[0], a[0])
        else:  # there before the next plan: it waits there
            builder.hold(t + traj.duration, aim)
            state = (aim, 0.0, 0.0)
        t, k = t + HOP, k + 1


def _calculate(ruckig: Ruckig, inp: InputParameter, traj: Trajectory,
               state: tuple[float, float, float]) -> None:
    """ruckig's plan from ``state``. Where the last plan left the mouth braking on the
    very edge of its limits (its velocity about to reach the limit, to the last bit),
    ruckig's solver can stumble: the acceleration is eased inside first (by at most a
    fifth, keeping position and velocity: nothing jumps)."""
    p, v, a = state
    inp.current_position, inp.current_velocity = [p], [v]
    for ease in EASE:
        inp.current_acceleration = [a * ease]
        try:
            if ruckig.calculate(inp, traj) in (Result.Working, Result.Finished):
                return
        except RuckigError:
            continue
    raise ValueError(f"the mouth's track cannot be planned from {state}")


def follow(speech: Speech, profile: Profile, now: float, pose: list[int],
           builders: list[TrackBuilder]) -> float:
    """Plan ``speech``'s mouth from ``now`` (its servo at rest at ``pose``) into the
    gesture's tracks; the step's length: the sound's, or the mouth's if it closes
    later."""
    i = speech.servo
    mouth, moved = track(speech, profile.servos[i], pose[i])
    builders[i].extend(mouth, now)
    pose[i] = speech.voice.closed
    return max(speech.sound.duration, moved)
