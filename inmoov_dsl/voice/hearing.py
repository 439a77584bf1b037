"""How a program hears its ``say`` steps (an edge: it reads files and runs espeak-ng),
in one place: a ``.wav`` is looked for as ``use`` looks for a file (beside the file that
says it, then along the search path), its name and its target's ending in ``.wav``;
other text is spoken with the profile's voice; each sound is made once while it is kept
(the most recently heard, KEPT bytes of samples: a program that lives long, the
service's, holds no more)."""

from __future__ import annotations

import os
import threading
from collections import OrderedDict
from collections.abc import Callable, Sequence
from dataclasses import replace

from ..resources import read_regular
from .wav import MAX_SECONDS, Sound, SoundError, read_wav

MAX_WAV_BYTES = int(MAX_SECONDS * 48_000 * 2 * 4) + 1024  #: the largest file read
WAV_SUFFIX = ".wav"
REQUEST = "<request>"  #: what another program sent: it names no file of this computer
KEPT = 32 * 2 ** 20  #: bytes of samples kept for a sound heard again (~6 min of espeak-ng)


def espeak(text: str, voice: str, speed: int, pitch: int) -> bytes:
    """``speak.speak``, imported when a text is first spoken (it starts programs)."""
    from .speak import speak

    return speak(text, voice, speed, pitch)


class Hearing:
    """The sounds of one program's ``say`` steps; ``Speak(text, voice, speed, pitch)``
    makes WAV bytes of text. Those heard last are kept, ``kept`` bytes of samples at
    most (a sound larger than that is made each time); threads may share it."""

    def __init__(self, search: Sequence[str] = (),
                 speaker: Callable[[str, str, int, int], bytes] = espeak, kept: int = KEPT):
        self.search, self.speaker, self.kept = list(search), speaker, kept
        self.made: OrderedDict[tuple, Sound] = OrderedDict()
        self.lock = threading.Lock()

    def __call__(self, text: str, file: str, voice: str, speed: int, pitch: int) -> Sound:
        """The sound of ``say "text"`` written in ``file`` (a pseudo-file such as
        ``<repl>`` for a typed line: a WAV is then looked for from here)."""
        if text.lower().endswith(WAV_SUFFIX):
            path = self._find(text, file)
            key: tuple = ("file", os.path.realpath(path))
        else:
            key = ("text", text, voice, speed, pitch)
        with self.lock:
            if key in self.made:
                self.made.move_to_end(key)
                return self.made[key]
        if key[0] == "file":
            sound = replace(read_wav(_read(path), text), path=os.path.abspath(path))
        else:
            sound = read_wav(self.speaker(text, voice, speed, pitch), text)
        self._keep(key, sound)
        return sound

    def _keep(self, key: tuple, sound: Sound) -> None:
        """Keep ``sound``, and drop those heard longest ago while they are too many."""
        with self.lock:
            self.made[key] = sound
            total = sum(s.samples.nbytes for s in self.made.values())
            while self.made and total > self.kept:
                total -= self.made.popitem(last=False)[1].samples.nbytes

    def _find(self, name: str, file: str) -> str:
        if file == REQUEST:
            raise SoundError("a request names no file: it may say text, not a .wav",
                             'say "Hello, I am InMoov"')
        here = "" if file.startswith("<") else os.path.dirname(file)
        places = [os.path.join(here, name), *(os.path.join(d, name) for d in self.search)]
        for place in places:
            if os.path.exists(place):
                if not os.path.realpath(place).lower().endswith(WAV_SUFFIX):
                    raise SoundError(f"'{place}' links to '{os.path.realpath(place)}', "
                                     f"which is not a {WAV_SUFFIX} file")
                return place
        raise SoundError(f"cannot find '{name}'", "looked in " + ", ".join(
            os.path.dirname(p) or "." for p in places))


def _read(path: str) -> bytes:
    try:
        data = read_regular(path, MAX_WAV_BYTES)
    except (OSError, ValueError) as exc:
        raise SoundError(f"cannot read '{path}': {exc}") from None
    if len(data) > MAX_WAV_BYTES:
        raise SoundError(f"'{path}' is larger than {MAX_WAV_BYTES:,} bytes: it is not read",
                         "split it into shorter sounds")
    return data


def hear_again(said: str, file: str | None, voice: tuple[str, int, int] | None, sha256: str,
               speaker: Callable[[str, str, int, int], bytes] = espeak) -> Sound:
    """The sound a compiled gesture's cue names (its WAV file, or its text spoken again):
    a SoundError if the file is not the one compiled (its SHA-256 differs)."""
    if file is not None:
        sound = replace(read_wav(_read(file), said), path=file)
        if sound.digest != sha256:
            raise SoundError(f"'{file}' has changed since the gesture was compiled",
                             "compile it again (gestc compile)")
        return sound
    name, speed, pitch = voice
    return read_wav(speaker(said, name, speed, pitch), said)
