"""Where the grammar, the gesture library and the profiles are, installed or not."""

from __future__ import annotations

from pathlib import Path

_PACKAGE = Path(__file__).resolve().parent


def data_dir(name: str) -> Path:
    """The shipped directory ``name`` (``grammar``, ``gestures`` or ``firmware``).

    A wheel carries them in ``inmoov_dsl/_data``; a source checkout (or an editable
    install) has them at the top of the repository.
    """
    for candidate in (_PACKAGE / "_data" / name, _PACKAGE.parent / name):
        if candidate.is_dir():
            return candidate
    raise FileNotFoundError(f"inmoov-dsl is installed without its {name}/ directory")


def grammar_path() -> Path:
    return data_dir("grammar") / "gest.lark"


def library_dir() -> Path:
    return data_dir("gestures")


def profiles_dir() -> Path:
    return library_dir() / "profiles"
