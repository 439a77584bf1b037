"""The sounds one request may make (pure: its ``say`` steps, heard through the service's
``Hearing``, which keeps what was heard within a bound): at most MAX_SOUNDS different
ones, lasting MAX_SPEECH seconds in all. Past that, a step's sound is not made: it is a
``SoundError``, which the compiler tells at the step's string (a 422 at its place)."""

from __future__ import annotations

from collections.abc import Callable

from ..voice.wav import Sound, SoundError

MAX_SOUNDS = 20  #: different sounds one request may say
MAX_SPEECH = 180.0  #: s their sounds may last in all (the mouth's fit: ~55 ms a second)
SPLIT = 'send the rest in another request, with "when": "after"'


class Allowance:
    """What one request has said so far, and the ``hear`` that says more (the program's
    ``hear``: (text, file, voice, speed, pitch) -> Sound)."""

    def __init__(self, hear: Callable[..., Sound], sounds: int = MAX_SOUNDS,
                 seconds: float = MAX_SPEECH):
        self.hear, self.sounds, self.seconds = hear, sounds, seconds
        self.said: dict[tuple, Sound] = {}
        self.lasting = 0.0  #: s the sounds said so far last

    def __call__(self, text: str, file: str, voice: str, speed: int, pitch: int) -> Sound:
        """The sound of ``say "text"`` (once per request, however often it is said), or
        a SoundError once the request has said too much."""
        key = (text, file, voice, speed, pitch)
        if key in self.said:
            return self.said[key]
        if len(self.said) >= self.sounds:
            raise SoundError(f"a request may say at most {self.sounds} different sounds",
                             SPLIT)
        if self.lasting > self.seconds:  # not made: the request says too much already
            raise SoundError(f"a request's sounds may last {self.seconds:g} s in all, and "
                             f"those before this one last {self.lasting:.0f} s", SPLIT)
        sound = self.hear(text, file, voice, speed, pitch)
        self.said[key] = sound
        self.lasting += sound.duration
        if self.lasting > self.seconds:
            raise SoundError(f"a request's sounds may last {self.seconds:g} s in all: with "
                             f"this one, they last {self.lasting:.0f} s", SPLIT)
        return sound
