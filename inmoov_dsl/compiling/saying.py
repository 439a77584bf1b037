"""A ``say`` step for one profile (resolve's part): the profile's mouth, the sound the
program hears, and what the mouth follows; every problem an error at the step."""

from __future__ import annotations

from ..errors import GestError
from ..hardware import Profile
from ..language import syntax as ast
from ..language.program import Program
from ..voice.wav import SoundError
from .mouth import NEEDS_SCIPY, solvable
from .speech import Speech, heard


def speech(step: ast.Say, program: Program, profile: Profile) -> Speech:
    """The Speech of ``step``: a GestError at the step (no ``[voice]``) or at its string
    (no sound: a missing file, not a WAV, espeak-ng missing or failing)."""
    voice = profile.voice
    if voice is None:
        raise GestError(program.sources.error(
            f"profile '{profile.name}' has no [voice]: no mouth moves with 'say'", step.pos,
            "play it on a robot whose profile names its mouth in [voice] (robot inmoov)"))
    if program.hear is None:
        raise GestError(program.sources.error("this program cannot hear sounds", step.pos))
    try:
        sound = program.hear(step.text, step.pos.file, voice.voice, voice.speed, voice.pitch)
    except SoundError as exc:
        raise GestError(program.sources.error(exc.message, step.text_pos, exc.hint)) from None
    if not solvable():
        raise GestError(program.sources.error(NEEDS_SCIPY, step.pos,
                                              "python -m pip install 'inmoov-dsl[voice]'"))
    return heard(sound, profile.index(voice.mouth), voice)


def label(part: ast.Move | ast.Say) -> str:
    """What an error calls a part of ``a & b``: its first target, or ``say``."""
    return "say" if isinstance(part, ast.Say) else part.targets[0].name.text
