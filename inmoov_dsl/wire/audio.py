"""The computer's sound output (an edge: sounddevice, the optional extra ``voice``):
sounds played at given times of the clock the boards' bytes go out on.

One output stream stays open, playing silence between sounds, so a sound starts on
time: its first sample goes to the place in a buffer that PortAudio says will be heard
at the sound's time (its own timing: the time each buffer reaches the output). What was
planned and when it was heard is kept (``heard``), so that it can be measured.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass

import numpy as np

from .. import clock
from ..errors import Diagnostic, GestError
from ..voice.wav import Sound

INSTALL = "pip install 'inmoov-dsl[voice]' (on Linux also: sudo apt-get install libportaudio2)"
RATE = 48_000  #: samples per second of the output
FLOWING = 40  #: callbacks counted to know the output flows
STEADY = 0.2  #: s in which the last half of them came


def need_sounddevice():
    """sounddevice, or a GestError saying how to get it (or to stay silent)."""
    try:
        import sounddevice
    except (ImportError, OSError) as exc:  # OSError: PortAudio itself is missing
        raise GestError(Diagnostic("error", f"playing sound needs sounddevice and PortAudio "
                                   f"({exc})", hint=f"{INSTALL}; or --audio none to stay "
                                   "silent")) from None
    return sounddevice


@dataclass
class Playing:
    """One sound in the stream: its samples at RATE, when it starts (clock time), and how
    far it has gone."""

    samples: np.ndarray
    at: float
    done: int = 0


class Speaker:
    """Sounds on the output ``device`` (None: the default; a name or a number)."""

    def __init__(self, device: str | int | None = None, now: clock.Clock = clock.now):
        sounddevice = need_sounddevice()
        self.now, self.lock = now, threading.Lock()
        self.playing: list[Playing] = []
        self.heard: list[tuple[float, float]] = []  #: (planned, heard) of each sound's start
        self.calls: list[float] = []  #: when the first callbacks came (to know it flows)
        try:
            self.stream = sounddevice.OutputStream(samplerate=RATE, channels=1, device=device,
                                                   dtype="float32", latency="low",
                                                   callback=self._fill)
            self.stream.start()
        except (sounddevice.PortAudioError, ValueError) as exc:
            raise GestError(Diagnostic("error", f"cannot open the sound output "
                                       f"{device if device is not None else '(default)'}: "
                                       f"{exc}", hint="--audio DEVICE (python -m sounddevice "
                                       "lists them), or --audio none")) from None

    def wait_flowing(self, sleep: clock.Sleep = clock.sleep, timeout: float = 5.0) -> bool:
        """Wait until the output asks for samples steadily (a sound server may take a
        second to start): FLOWING calls in the last STEADY s. False after ``timeout``."""
        deadline = self.now() + timeout
        while self.now() < deadline:
            calls = self.calls
            if len(calls) >= FLOWING and calls[-1] - calls[-FLOWING // 2] < STEADY:
                return True
            sleep(0.01)
        return False

    def play(self, sound: Sound, at: float) -> None:
        """Play ``sound`` from ``at`` (the clock's time) on."""
        samples = _resampled(sound.samples, sound.rate)
        with self.lock:
            self.playing.append(Playing(samples, at))

    def stop(self) -> None:
        """Silence: every sound stops now."""
        with self.lock:
            self.playing.clear()

    def busy(self) -> bool:
        """Is a sound still to be heard?"""
        with self.lock:
            return bool(self.playing)

    def _fill(self, out: np.ndarray, frames: int, time, status) -> None:
        """PortAudio's callback: the next ``frames`` samples, heard from the moment its
        ``time`` says (turned into the clock's time)."""
        now = self.now()
        heard_at = now + (time.outputBufferDacTime - time.currentTime)
        if len(self.calls) < FLOWING:
            self.calls.append(now)
        out.fill(0)
        with self.lock:
            for p in self.playing:
                first = max(0, round((p.at - heard_at) * RATE)) if p.done == 0 else 0
                if first >= frames:
                    continue
                n = min(frames - first, len(p.samples) - p.done)
                out[first:first + n, 0] += p.samples[p.done:p.done + n]
                if p.done == 0:
                    self.heard.append((p.at, heard_at + first / RATE))
                p.done += n
            self.playing = [p for p in self.playing if p.done < len(p.samples)]

    def close(self) -> None:
        """Stop the output."""
        self.stream.stop()
        self.stream.close()


def _resampled(samples: np.ndarray, rate: int) -> np.ndarray:
    """``samples`` at RATE (linear interpolation: speech needs no more)."""
    if rate == RATE:
        return samples.astype(np.float32)
    count = int(round(len(samples) * RATE / rate))
    t = np.arange(count) * (rate / RATE)
    return np.interp(t, np.arange(len(samples)), samples).astype(np.float32)
