"""The mouth moving with a sound (pure): the sound's loudness as a viewer sees it, the
opening it asks of the mouth, and the mouth's track, planned for the whole sound at once
under its servo's limits (``mouth.fit``), LEAD ahead of the sound.

The loudness is the RMS of each HOP of sound, averaged over SMOOTH (a syllable's
swell), from 0 (silence) to 1 (the loudest). Silence is judged against the sound's own
noise floor, its hiss (``hiss``: the RMS its quietest hops reach; about none in a
synthetic voice, a recording's noise in a recording): a loudness under GATE of the
loudest or under HISS times the hiss is 0. The track aims at the opening the loudness
asks LEAD later. A silence (hops whose own RMS is under GATE of the loudest hop's and
under STILL times the hiss) of QUIET or more closes the mouth and holds it still, from
CLOSING after it begins to OPENING before the next sound. STILL is lower than HISS: a
consonant a little above the hiss ends a silence, so the mouth is free in time to open
for the vowel after it, while it opens nothing itself.

A track is fitted once while it is kept (the last TRACKS): a player that plans a ``say``
again after its check (the service) does not fit it twice.
"""

from __future__ import annotations

import math
import threading
from collections import OrderedDict
from dataclasses import dataclass, field

import numpy as np
from ruckig import InputParameter, Ruckig, Trajectory

from ..hardware import Profile, Servo, Voice
from ..voice.wav import Sound
from .mouth import fit, runs
from .tracks import Track, TrackBuilder

HOP = 0.010  #: s between loudness values, and between the track's knots
SMOOTH = 0.100  #: s of sound each loudness value averages
GATE = 0.03  #: of the loudest: quieter is silence; so is what is near the sound's hiss:
HISS = 5.0  #: a loudness under this many times the hiss opens nothing (+14 dB)...
STILL = 2.5  #: ...a HOP under this many times it may hold the mouth still (+8 dB)...
FLOOR = 5  #: ...the hiss: the RMS the quietest hops reach (this percentile of them)
LEAD = 0.040  #: s; the mouth's opening leads the sound by this (two servo frames)
QUIET = 0.250  #: s of silence that holds the mouth closed and still...
CLOSING = 0.080  #: ...from this long after the silence begins (the mouth closing)...
OPENING = 0.080  #: ...to this long before the next sound (the mouth opening ahead)
#: s after a silence held still in which the jaw, starting from rest, cannot be fully
#: where the sound wants it: the fit's shape is not judged there (``mouth.fit``)
ONSET = 0.150
AFTER = 0.300  #: s the track may take after the sound to close
#: mouth tracks kept (a say planned again, by a player after its check, is fitted once)
TRACKS = 64
_tracks: OrderedDict[tuple, tuple[Track, float, float]] = OrderedDict()
_tracks_lock = threading.Lock()


@dataclass(frozen=True, eq=False)
class Speech:
    """A ``say`` for one profile (``heard``): its sound, the mouth's servo, the opening
    the sound asks every HOP (closed..open) and its long silences."""

    sound: Sound
    servo: int  #: the mouth's index in the profile
    voice: Voice
    levels: np.ndarray = field(repr=False)  #: loudness 0..1 every HOP
    silent: np.ndarray = field(repr=False)  #: each HOP: is it silence?

    @property
    def openings(self) -> np.ndarray:
        """The opening the sound asks, every HOP."""
        v = self.voice
        return v.closed + (v.opened - v.closed) * self.levels


def heard(sound: Sound, servo: int, voice: Voice) -> Speech:
    """The Speech of ``sound`` said by ``voice`` through servo ``servo`` (an index)."""
    rms = _rms(sound.samples, sound.rate)
    loudest = float(rms.max()) if len(rms) else 0.0
    noise = hiss(rms)
    return Speech(sound, servo, voice, loudness(rms, quiet(noise)),
                  rms <= quiet(noise, STILL) * loudest)


def hiss(rms: np.ndarray) -> float:
    """A sound's hiss, as a share of its loudest HOP's RMS (``_rms``): the FLOOR
    percentile of its hops' RMS. A clean sound's is about 0."""
    loudest = float(rms.max()) if len(rms) else 0.0
    return float(np.percentile(rms, FLOOR)) / loudest if loudest > 0 else 0.0


def quiet(noise: float, above: float = HISS) -> float:
    """The share of the loudest under which a sound whose ``hiss`` is ``noise`` is
    silent: GATE, or ``above`` times the hiss if that is more, but at most halfway, in
    decibels, from the hiss to the loudest (so that a voice in loud hiss still opens the
    mouth)."""
    return max(GATE, min(above * noise, math.sqrt(noise)))


def loudness(rms: np.ndarray, gate: float) -> np.ndarray:
    """0 (silence: under ``gate`` of the loudest, ``quiet`` of the sound's ``hiss``) ..
    1 (the loudest) every HOP s, from each HOP's RMS (``_rms``)."""
    width = max(1, round(SMOOTH / HOP))
    swell = np.convolve(rms, np.ones(width) / width, mode="same")
    loudest = float(swell.max()) if len(swell) else 0.0
    if loudest <= 0:
        return np.zeros(len(swell))
    levels = swell / loudest
    levels[levels < gate] = 0.0
    return levels


def _rms(x: np.ndarray, rate: float) -> np.ndarray:
    """The RMS of each HOP of ``x`` (the hops' edges on the nearest sample, so that a
    rate that is no multiple of 100 does not drift), 10 s at a time."""
    count = max(1, int(np.ceil(len(x) / (rate * HOP) - 1e-9)))
    edges = np.minimum(np.round(np.arange(count + 1) * rate * HOP).astype(np.int64), len(x))
    power = np.zeros(count)
    for first in range(0, count, 1000):
        last = min(count, first + 1000)
        lo, hi = int(edges[first]), int(edges[last])
        if hi <= lo:
            break
        part = x[lo:hi].astype(np.float64)
        starts = edges[first:last] - lo
        some = int(np.count_nonzero(starts < hi - lo))  # (the last hops may hold none)
        power[first:first + some] = np.add.reduceat(part * part, starts[:some])
    widths = np.diff(edges)
    return np.sqrt(np.where(widths > 0, power / np.maximum(widths, 1), 0.0))


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
    sounding = np.flatnonzero(~speech.silent)
    onset = sounding[0] * HOP if len(sounding) else ready
    return max(0, round((ready - onset) / HOP)) * HOP


def track(speech: Speech, servo: Servo, start: float) -> tuple[Track, float, float]:
    """The mouth's track from ``start`` (at rest), how long it moves, and when the
    sound starts (``delay``): aiming LEAD ahead at the opening the sound asks, still
    and closed in each long silence, and closed at rest after the sound. The last
    TRACKS are kept: the same sound, voice, servo and start give the same track."""
    sound = speech.sound
    key = (sound.digest, sound.rate, len(sound.samples), speech.voice, servo, float(start))
    with _tracks_lock:
        if key in _tracks:
            _tracks.move_to_end(key)
            return _tracks[key]
    made = _fit(speech, servo, start)
    with _tracks_lock:
        _tracks[key] = made
        while len(_tracks) > TRACKS:
            _tracks.popitem(last=False)
    return made


def _fit(speech: Speech, servo: Servo, start: float) -> tuple[Track, float, float]:
    """``track``, fitted."""
    voice = speech.voice
    closed = float(voice.closed)
    wait = delay(speech, servo)
    knots = np.arange(round((wait + speech.sound.duration + LEAD + AFTER) / HOP))
    # the opening the sound asks LEAD after each knot; whether it is silent at each
    target = _per_knot(speech.openings, knots - round((wait - LEAD) / HOP), closed)
    silent = _per_knot(speech.silent, knots - round(wait / HOP), True)
    fixed = np.full(len(target) + 2, np.nan)
    fixed[:3] = start
    free_from = int(np.ceil(_move_time(servo, start, closed) / HOP))
    judged = np.ones(len(target), bool)
    for a, b in runs(silent):
        if b - a < round(QUIET / HOP):
            continue
        a = max(a + round(CLOSING / HOP), free_from)
        b = b - round(OPENING / HOP) if b < len(silent) else b
        fixed[a:b + 2] = closed  # still and closed from knot a to knot b
        judged[b:b + round(ONSET / HOP)] = False
    fixed[-3:] = closed
    span = (min(closed, voice.opened, start), max(closed, voice.opened, start))
    c = fit(target, fixed, servo, HOP, span, closed, judged)
    p0, p1, p2, p3 = c[:-3], c[1:-2], c[2:-1], c[3:]
    coefs = np.stack(((p0 + 4 * p1 + p2) / 6, (p2 - p0) / (2 * HOP),
                      (p0 - 2 * p1 + p2) / HOP ** 2, (p3 - 3 * p2 + 3 * p1 - p0) / HOP ** 3), 1)
    moving = np.flatnonzero(np.any(np.abs(coefs - [closed, 0, 0, 0]) > 1e-9, axis=1))
    pieces = int(moving[-1]) + 1 if len(moving) else 0
    breaks = np.arange(pieces + 1) * HOP
    rest = np.array([[closed if pieces else float(start), 0.0, 0.0, 0.0]])
    return Track(breaks, np.concatenate((coefs[:pieces], rest))), pieces * HOP, wait


def _per_knot(values: np.ndarray, hops: np.ndarray, outside) -> np.ndarray:
    """``values`` (one a HOP of the sound) at the sound's hop ``hops``, ``outside``
    before and after the sound."""
    inside = (hops >= 0) & (hops < len(values))
    return np.where(inside, values[np.clip(hops, 0, len(values) - 1)], outside)


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
