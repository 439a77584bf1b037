"""A MIDI backend for mido (``MIDO_BACKEND=midi_backend``): input ports a test names,
each playing a script of control changes to whoever opens it with a callback, as a
controller would. mido's own backend interface (``get_devices``, ``Input``): the same
calls the rtmidi backend answers on a machine with a controller plugged in.

``MIDI_PORTS``: the ports' names, ``|`` between them; ``MIDI_SCRIPT``: a file of
"<seconds> <channel 1..16> <control> <value>" lines, played from the port's opening;
``MIDI_SENT``: a file that gets, for each message, the monotonic clock as it is handed
over (a line each; benchmarks/puppet.py)."""

import os
import threading
import time
from pathlib import Path

import mido


def get_devices(**_kwargs):
    names = [n for n in os.environ.get("MIDI_PORTS", "").split("|") if n]
    return [{"name": n, "is_input": True, "is_output": False} for n in names]


class Input:
    def __init__(self, name=None, virtual=False, callback=None, **_kwargs):
        if name not in [d["name"] for d in get_devices()]:
            raise OSError(f"unknown port {name!r}")
        self.name, self.closed = name, False
        script = os.environ.get("MIDI_SCRIPT")
        lines = Path(script).read_text().split("\n") if script else []
        self.script = [tuple(float(x) for x in line.split()) for line in lines if line]
        if callback is not None:
            threading.Thread(target=self._play, args=(callback,), daemon=True).start()

    def _play(self, callback):
        start, sent = time.monotonic(), os.environ.get("MIDI_SENT")
        for t, channel, control, value in self.script:
            time.sleep(max(0.0, start + t - time.monotonic()))
            if self.closed:
                return
            message = mido.Message("control_change", channel=int(channel) - 1,
                                   control=int(control), value=int(value))
            now = time.monotonic()
            callback(message)
            if sent:
                with open(sent, "a") as log:
                    log.write(f"{now:.6f}\n")

    def close(self):
        self.closed = True
