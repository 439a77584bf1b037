"""The live preview's play head (pure): where in the gesture the page is, playing or
paused, at a speed, looping or not. Times are the caller's clock (``now``, s); this
module has none."""

from __future__ import annotations

from dataclasses import dataclass

SPEEDS = (0.25, 0.5, 1.0, 1.5, 2.0)  #: the speeds a page offers


@dataclass
class Clock:
    """The play head over a gesture of ``duration`` seconds."""

    duration: float = 0.0
    speed: float = 1.0
    loop: bool = False
    playing: bool = False
    _at: float = 0.0  #: the gesture's time at ``_since``
    _since: float = 0.0  #: the caller's time when it was
    session: int = 0  #: counts each start, seek and change of speed (a sound restarts)

    def time(self, now: float) -> float:
        """The gesture's time at ``now``: it runs at ``speed`` while playing, wraps
        round at the end while looping, else stops there (and stops playing)."""
        if not self.playing:
            return self._at
        t = self._at + (now - self._since) * self.speed
        if t < self.duration:
            return t
        if self.loop and self.duration > 0:
            passes = int(t // self.duration)
            self._at, self._since = t - passes * self.duration, now
            self.session += 1
            return self._at
        self._at, self._since, self.playing = self.duration, now, False
        return self._at

    def play(self, now: float) -> None:
        """Play from where it is (from the start when it is at the end)."""
        if self.playing:
            return
        if self._at >= self.duration:
            self._at = 0.0
        self._since, self.playing = now, True
        self.session += 1

    def pause(self, now: float) -> None:
        """Hold where it is."""
        self._at = self.time(now)
        self._since, self.playing = now, False

    def seek(self, t: float, now: float) -> None:
        """Go to ``t`` (within the gesture), playing on if it was playing."""
        self._at, self._since = min(max(t, 0.0), self.duration), now
        self.session += 1

    def set_speed(self, speed: float, now: float) -> None:
        """Play at ``speed`` from now on."""
        self._at, self._since, self.speed = self.time(now), now, speed
        self.session += 1

    def set_duration(self, duration: float, now: float) -> None:
        """A new gesture's length: the head stays where it is, within it."""
        t = self.time(now)
        self.duration = max(duration, 0.0)
        self._at, self._since = min(t, self.duration), now
