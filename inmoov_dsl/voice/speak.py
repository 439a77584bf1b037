"""Text spoken by espeak-ng (an edge: it runs the program), as WAV bytes."""

from __future__ import annotations

import shutil
import subprocess

from .wav import SoundError

PROGRAM = "espeak-ng"
MAX_TEXT = 1000  #: characters one ``say`` may speak
TIMEOUT = 60.0  #: s espeak-ng may take for one text


def speak(text: str, voice: str, speed: int, pitch: int) -> bytes:
    """The WAV bytes of espeak-ng speaking ``text`` with ``voice`` (a name such as
    ``en``), ``speed`` words per minute and ``pitch`` (0..99)."""
    if not text.strip():
        raise SoundError("there is nothing to say", 'say "Hello", or say "hello.wav"')
    if len(text) > MAX_TEXT:
        raise SoundError(f"the text to speak has {len(text):,} characters, more than "
                         f"{MAX_TEXT:,}", "split it into several say steps")
    exe = shutil.which(PROGRAM)
    if exe is None:
        raise SoundError("speaking text needs espeak-ng, which is not installed",
                         "Debian/Ubuntu: sudo apt-get install espeak-ng; macOS: brew "
                         "install espeak-ng; Windows: the installer from "
                         "github.com/espeak-ng/espeak-ng/releases; or say a .wav file")
    try:
        done = subprocess.run([exe, "-v", voice, "-s", str(speed), "-p", str(pitch),
                               "--stdout", "--stdin"], input=text.encode("utf-8"),
                              capture_output=True, timeout=TIMEOUT, check=False)
    except (OSError, subprocess.TimeoutExpired) as exc:
        raise SoundError(f"espeak-ng failed: {exc}") from None
    if done.returncode != 0 or not done.stdout.startswith(b"RIFF"):
        why = done.stderr.decode("utf-8", "replace").strip().splitlines()
        raise SoundError(f"espeak-ng failed: {why[0] if why else f'exit {done.returncode}'}",
                         f"is '{voice}' one of its voices? espeak-ng --voices lists them")
    return _fixed(done.stdout)


def _fixed(data: bytes) -> bytes:
    """espeak-ng writing to a pipe cannot go back to fill in the WAV's sizes: fill them
    in, so that any reader takes the file."""
    body = len(data) - 44
    if body < 0 or data[36:40] != b"data":
        return data
    return (data[:4] + (len(data) - 8).to_bytes(4, "little") + data[8:40]
            + body.to_bytes(4, "little") + data[44:])
