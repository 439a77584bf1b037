"""inmoov-dsl: gestures for the InMoov hand, compiled to jerk-limited, timed byte streams.

    >>> from inmoov_dsl import compile_source
    >>> c = compile_source("peace: index 180, middle 180 over 0.6s")
    >>> c.streams[0].data[0]   # every stream opens with CANCEL
    255

The names below are imported when first used, so that a command pays only for the
modules it needs.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

_WHERE = {
    "Compiled": "compiled", "from_json": "compiled", "to_json": "compiled",
    "to_timed": "compiled", "compile_file": "compiler", "compile_program": "compiler",
    "compile_source": "compiler", "load": "compiler", "plan_gesture": "compiler",
    "Stream": "encode", "encode": "encode", "Diagnostic": "errors", "GestError": "errors",
    "load_library": "library", "LinkReport": "metrics", "measure": "metrics", "Plan": "plan",
    "Profile": "profile", "load_profile": "profile",
}
__all__ = [
    "Compiled", "Diagnostic", "GestError", "LinkReport", "Plan", "Profile", "Stream",
    "compile_file", "compile_program", "compile_source", "encode", "from_json", "load",
    "load_library", "load_profile", "measure", "plan_gesture", "to_json", "to_timed",
]
__version__ = "0.1.0"

if TYPE_CHECKING:
    from .compiled import Compiled, from_json, to_json, to_timed
    from .compiler import compile_file, compile_program, compile_source, load, plan_gesture
    from .encode import Stream, encode
    from .errors import Diagnostic, GestError
    from .library import load_library
    from .metrics import LinkReport, measure
    from .plan import Plan
    from .profile import Profile, load_profile


def __getattr__(name: str) -> Any:
    if name not in _WHERE:
        raise AttributeError(f"module 'inmoov_dsl' has no attribute '{name}'")
    value = getattr(importlib.import_module(f".{_WHERE[name]}", __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted([*globals(), *_WHERE])
