"""The sound output gestplay plays a gesture's ``say`` steps on: ``--audio DEVICE``
(default: the computer's default output), ``--audio none`` for silence. It is opened when
a gesture first has sounds, and waited for until it flows, so that sounds start on
time."""

from __future__ import annotations

import argparse
from dataclasses import replace

from ...compiling.compiled import Compiled
from ...errors import Diagnostic, GestError
from ...hardware import Profile
from ...voice.hearing import hear_again
from ...voice.wav import SoundError
from ..common import warn


class Audio:
    """``--audio``'s choice, and the speaker once a gesture needs it."""

    def __init__(self, choice: str | None, prog: str):
        self.choice, self.prog, self.speaker = choice, prog, None

    def ready(self, compiled: Compiled, speed: float) -> tuple[Compiled, object | None]:
        """``compiled`` with its sounds (a compiled file's heard again), and the speaker
        to play them on (None: silence, or no sound to play)."""
        if not compiled.sounds or self.choice == "none":
            return compiled, None
        if speed != 1:
            raise GestError(Diagnostic("error", "'say' plays its sound at its own speed: "
                                       "--speed changes the motion only",
                                       hint="--speed 1, or --audio none to stay silent"))
        try:
            cues = tuple(q if q.sound is not None else replace(
                q, sound=hear_again(q.said, q.file, q.voice, q.sha256))
                for q in compiled.sounds)
        except SoundError as exc:
            raise GestError(Diagnostic("error", exc.message, hint=exc.hint)) from None
        if self.speaker is None:
            from ...wire.audio import Speaker

            device = None if self.choice in (None, "default") else \
                int(self.choice) if self.choice.isdigit() else self.choice
            self.speaker = Speaker(device)
            if not self.speaker.wait_flowing():
                warn("the sound output is slow to start: the first sound may be late",
                     self.prog)
        return replace(compiled, sounds=cues), self.speaker

    def close(self) -> None:
        """Close the output, if it was opened."""
        if self.speaker is not None:
            self.speaker.close()


def speaker(choice: str | None, prog: str, profile: Profile):
    """Where a live front end's ``say`` is heard (the repl, the service): the default
    output, ``--audio DEVICE``, or none (``--audio none``; a profile without a mouth,
    which cannot ``say``; or no sound library: then a warning, and ``say`` moves the
    mouth in silence)."""
    if choice == "none" or profile.voice is None:
        return None
    from ...wire.audio import Speaker

    try:
        speaker = Speaker(None if choice in (None, "default") else
                          int(choice) if choice.isdigit() else choice)
    except GestError as exc:
        if choice is not None:
            raise
        warn(f"'say' is silent here: {exc.first.message}", prog)
        return None
    speaker.wait_flowing()
    return speaker


def add_argument(p: argparse.ArgumentParser) -> None:
    """``--audio none|DEVICE``."""
    p.add_argument("--audio", metavar="DEVICE", help="where 'say' steps are heard: the "
                   "default output, a device's name or number (python -m sounddevice lists "
                   "them), or 'none' to stay silent (needs: pip install 'inmoov-dsl[voice]')")
