"""The gesture library: which gestures exist and in which file."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from . import syntax as ast
from .errors import Diagnostic, GestError
from .parse import parse
from .resources import library_dir


def library_dirs() -> list[Path]:
    """Directories searched for gestures and for ``use`` imports."""
    return [library_dir()]


def load_library(dirs: Sequence[Path] | None = None) -> dict[str, Path]:
    """Gesture name -> the library file that defines it (imports not counted)."""
    found: dict[str, Path] = {}
    for directory in dirs if dirs is not None else library_dirs():
        for path in sorted(Path(directory).glob("*.gest")):
            module = parse(path.read_text(encoding="utf-8"), str(path))
            for item in module.items:
                if not isinstance(item, ast.GestureDef):
                    continue
                name = item.name.text
                if name in found:
                    raise GestError(Diagnostic(
                        "error", f"gesture '{name}' is defined in two library files: "
                        f"{found[name]} and {path}", hint="rename one of them"))
                found[name] = path
    return found
