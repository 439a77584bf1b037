"""A servo's planned track: piecewise cubic, built from ruckig's phases and
evaluated with numpy (pure)."""

from __future__ import annotations

from array import array
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np
from ruckig import Profile as RuckigProfile

POSITION_DECIMALS = 9  #: a planned position is evaluated to 1e-9 degree


@dataclass(frozen=True)
class Track:
    """One servo's planned position: piece k starts at ``breaks[k]`` with
    position, velocity, acceleration and jerk ``coefs[k]``. The last piece holds."""

    breaks: np.ndarray
    coefs: np.ndarray

    def _locate(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        t = np.asarray(t, dtype=float)
        k = np.clip(np.searchsorted(self.breaks, t, side="right") - 1, 0, len(self.breaks) - 1)
        return k, np.maximum(t - self.breaks[k], 0.0)

    def position(self, t: np.ndarray | float) -> np.ndarray:
        """The planned position at ``t``, to a nanodegree: float noise below that would
        otherwise decide a tie at a half degree (where the encoder rounds) one way at
        one instant and the other way a frame later, making a step one degree too big."""
        k, dt = self._locate(t)
        p, v, a, j = self.coefs[k].T
        return np.round(p + dt * (v + dt * (a / 2 + dt * j / 6)), POSITION_DECIMALS)

    def velocity(self, t: np.ndarray | float) -> np.ndarray:
        """The planned velocity at ``t`` (degrees per second)."""
        k, dt = self._locate(t)
        _, v, a, j = self.coefs[k].T
        return v + dt * (a + dt * j / 2)

    def acceleration(self, t: np.ndarray | float) -> np.ndarray:
        """The planned acceleration at ``t`` (degrees per second squared)."""
        k, dt = self._locate(t)
        _, _, a, j = self.coefs[k].T
        return a + dt * j


class TrackBuilder:
    """A track piece by piece, in flat float arrays (no object per piece: a long
    gesture's millions of pieces would otherwise keep the garbage collector busy)."""

    def __init__(self, value: float):
        self.breaks = array("d", [0.0])
        self.coefs = array("d", [value, 0.0, 0.0, 0.0])

    def hold(self, t: float, value: float) -> None:
        """From ``t`` on (never before the last piece), hold ``value``."""
        self.breaks.append(max(t, self.breaks[-1]))
        self.coefs.extend((value, 0.0, 0.0, 0.0))

    def phases(self, t0: float, profile: RuckigProfile) -> None:
        """Append ruckig's phases (after its brake phases, when it had to brake)."""
        t = t0
        parts = [profile.brake, profile] if profile.brake.duration > 0 else [profile]
        for part in parts:
            for dt, j, a, v, p in zip(part.t, part.j, part.a, part.v, part.p, strict=False):
                if dt > 1e-12:
                    self.breaks.append(t)
                    self.coefs.extend((p, v, a, j))
                    t += dt

    def phases_for(self, t0: float, profile: RuckigProfile, length: float) -> None:
        """Append ruckig's phases (``phases``) for ``length`` s only: what a controller
        that plans again every ``length`` s follows of each plan."""
        t, end = t0, t0 + length
        parts = [profile.brake, profile] if profile.brake.duration > 0 else [profile]
        for part in parts:
            for dt, j, a, v, p in zip(part.t, part.j, part.a, part.v, part.p, strict=False):
                if dt > 1e-12 and t < end - 1e-12:
                    self.breaks.append(t)
                    self.coefs.extend((p, v, a, j))
                    t += dt

    def extend(self, track: Track, t0: float) -> None:
        """Append ``track`` (planned from 0) from ``t0`` on."""
        self.breaks.extend((track.breaks + t0).tolist())
        self.coefs.extend(track.coefs.ravel().tolist())

    def build(self) -> Track:
        """The track made so far."""
        return Track(np.frombuffer(self.breaks, dtype=float).copy(),
                     np.frombuffer(self.coefs, dtype=float).reshape(-1, 4).copy())


class HasTracks(Protocol):
    """A plan: one track per servo."""

    tracks: tuple[Track, ...]


@dataclass(frozen=True)
class MotionState:
    """Every servo's position, velocity and acceleration at one moment."""

    position: tuple[float, ...]
    velocity: tuple[float, ...]
    acceleration: tuple[float, ...]

    @classmethod
    def resting(cls, pose: Sequence[float]) -> MotionState:
        """Every servo standing still at ``pose``."""
        still = (0.0,) * len(pose)
        return cls(tuple(float(x) for x in pose), still, still)

    @classmethod
    def at(cls, plan: HasTracks, t: float) -> MotionState:
        """Where ``plan`` (a ``plan.Plan``) has the hand at ``t`` (s from its start)."""
        return cls(tuple(float(tr.position(t)) for tr in plan.tracks),
                   tuple(float(tr.velocity(t)) for tr in plan.tracks),
                   tuple(float(tr.acceleration(t)) for tr in plan.tracks))
