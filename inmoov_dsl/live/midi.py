"""MIDI input (the edge: a file or a port; mido, the ``midi`` extra): control changes,
each with its time in seconds and its channel 1..16, as ``controls`` takes them. A take
read from a ``.mid`` file (recorded in a DAW, or written by a test), whole or played on
the clock (``TakeFile``); a controller's port, live (``PortInput``: mido's default
backend, python-rtmidi, or the one ``MIDO_BACKEND`` names)."""

from __future__ import annotations

import os
import queue
from typing import Any

from .. import clock
from ..errors import Diagnostic, GestError, Pos, did_you_mean
from .controls import Message
from .puppet import Got

INSTALL = "pip install 'inmoov-dsl[midi]' (mido, python-rtmidi)"
NO_PORTS = ("is the computer's MIDI system there (on Linux, ALSA's sequencer: "
            "/dev/snd/seq)? A take recorded in a DAW plays as well: --midi take.mid; "
            "and the ports need " + INSTALL)
MAX_BATCH = 4096  #: messages taken from a port at one wait (a flood waits for the next)
MAX_FILE = 16 * 1024 * 1024  #: bytes of one .mid file read
MAX_MESSAGES = 1_000_000  #: control changes of one take


def read_take(path: str) -> list[Message]:
    """The control changes of the MIDI file ``path``; a GestError naming the file when
    it cannot be read as one (missing, too large, not MIDI, mido missing)."""
    mido = _mido()
    try:
        size = os.path.getsize(path)
    except OSError as exc:
        raise GestError(Diagnostic("error", f"cannot read '{path}': {exc.strerror}",
                                   Pos(path, 1, 1))) from None
    if size > MAX_FILE:
        raise GestError(Diagnostic("error", f"'{path}' is {size:,} bytes: a MIDI take is "
                                   f"read up to {MAX_FILE:,}", Pos(path, 1, 1)))
    try:
        take = mido.MidiFile(path)
        found, now = [], 0.0
        for message in take:  # each with the seconds since the one before
            now += message.time
            if message.type == "control_change":
                found.append((now, message.channel + 1, message.control, message.value))
                if len(found) > MAX_MESSAGES:
                    raise ValueError(f"more than {MAX_MESSAGES:,} control changes")
    except Exception as exc:  # noqa: BLE001 (mido's many ways of refusing a file)
        raise GestError(Diagnostic("error", f"'{path}' is not a MIDI take that can be read: "
                                   f"{exc}", Pos(path, 1, 1),
                                   "a standard MIDI file (.mid) of control changes, as a "
                                   "DAW or mido writes it")) from None
    return found


def open_input(spec: str, now: clock.Clock | None = None, sleep: clock.Sleep | None = None
               ) -> TakeFile | PortInput:
    """``spec``: a ``.mid`` file (played on the clock) or a MIDI input port's name."""
    if spec.lower().endswith((".mid", ".midi")) or os.path.isfile(spec):
        return TakeFile(read_take(spec), now, sleep)
    return PortInput(spec, now)


class TakeFile:
    """A take's control changes given as their time comes, from the first wait on."""

    def __init__(self, messages: list[Message], now: clock.Clock | None = None,
                 sleep: clock.Sleep | None = None):
        self.messages, self.k = messages, 0
        self.now, self.sleep = now or clock.now, sleep or clock.sleep
        self.start: float | None = None

    def wait(self, timeout: float) -> Got:
        """The messages due within ``timeout`` s (after sleeping until the first)."""
        if self.start is None:
            self.start = self.now()
        if self.k >= len(self.messages):
            return None
        due = self.start + self.messages[self.k][0]
        if due > self.now() + timeout:
            self.sleep(max(timeout, 0.0))
            return False
        if due > self.now():
            self.sleep(due - self.now())
        t, batch = self.now() - self.start, []
        while self.k < len(self.messages) and self.messages[self.k][0] <= t:
            batch.append(self.messages[self.k])
            self.k += 1
        return batch or False

    def close(self) -> None:
        """Nothing to close: the file was read whole."""


class PortInput:
    """A controller's MIDI input port, its control changes queued as they come (mido's
    callback thread) with the time they came."""

    def __init__(self, name: str, now: clock.Clock | None = None):
        mido = _mido()
        try:
            names = mido.get_input_names()
        except Exception as exc:  # noqa: BLE001 (a backend missing, or no MIDI system)
            raise GestError(Diagnostic("error", f"cannot list MIDI input ports: {exc}",
                                       hint=NO_PORTS)) from None
        self.name = _port_named(name, names)
        self.now = now or clock.now
        self.start = self.now()
        self.came: queue.SimpleQueue[Message] = queue.SimpleQueue()
        try:
            self.port = mido.open_input(self.name, callback=self._came)
        except Exception as exc:  # noqa: BLE001 (the backend's own words)
            raise GestError(Diagnostic("error", f"cannot open MIDI port '{self.name}': {exc}",
                                       hint="is another program holding it?")) from None

    def _came(self, message: Any) -> None:
        if message.type == "control_change":
            self.came.put((self.now() - self.start, message.channel + 1, message.control,
                           message.value))

    def wait(self, timeout: float) -> Got:
        """The control changes that came: waits up to ``timeout`` s for the first."""
        try:
            batch = [self.came.get(timeout=timeout) if timeout > 0 else
                     self.came.get_nowait()]
        except queue.Empty:
            return False
        while len(batch) < MAX_BATCH:
            try:
                batch.append(self.came.get_nowait())
            except queue.Empty:
                break
        return batch

    def close(self) -> None:
        """Stop listening to the port."""
        self.port.close()


def take_from(port: PortInput, seconds: float | None) -> list[Message]:
    """What comes from ``port`` for ``seconds`` (None: until Ctrl-C), then closed."""
    found: list[Message] = []
    try:
        while seconds is None or port.now() - port.start < seconds:
            got = port.wait(0.05)
            found.extend(got or ())
    except KeyboardInterrupt:
        pass
    finally:
        port.close()
    return found


def _mido() -> Any:
    try:
        import mido
    except ImportError:
        raise GestError(Diagnostic("error", "MIDI needs mido, which is not installed",
                                   hint=INSTALL)) from None
    return mido


def _port_named(name: str, names: list[str]) -> str:
    """The port ``name`` is: itself, or the one port whose name holds it (a system adds
    numbers: "nanoKONTROL2:nanoKONTROL2 MIDI 1 20:0"); an error listing the ports."""
    if name in names:
        return name
    holding = [n for n in names if name.lower() in n.lower()]
    if len(holding) == 1:
        return holding[0]
    ports = ", ".join(f"'{n}'" for n in names) or "none (is the controller plugged in?)"
    what = "names more than one" if holding else "is neither a .mid file nor"
    raise GestError(Diagnostic("error", f"'{name}' {what} MIDI input port; the ports: "
                               f"{ports}", hint=did_you_mean(name, names) or "gestplay "
                               "puppet --midi 'PORT NAME' (or a take: --midi take.mid)"))
