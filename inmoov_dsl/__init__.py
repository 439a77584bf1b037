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
    "Compiled": "compiling.compiled", "from_json": "compiling.compiled_reader",
    "to_json": "compiling.compiled", "to_timed": "compiling.compiled",
    "compile_file": "compiling.compiler", "compile_program": "compiling.compiler",
    "compile_source": "compiling.compiler", "load": "language.load",
    "plan_gesture": "compiling.compiler", "Stream": "compiling.compiled",
    "encode": "compiling.encode", "Diagnostic": "errors", "GestError": "errors",
    "load_library": "language.library", "LinkReport": "compiling.metrics",
    "measure": "compiling.metrics", "Plan": "compiling.plan", "Profile": "profiles.profile",
    "load_profile": "profiles.profile",
}
__all__ = [
    "Compiled", "Diagnostic", "GestError", "LinkReport", "Plan", "Profile", "Stream",
    "compile_file", "compile_program", "compile_source", "encode", "from_json", "load",
    "load_library", "load_profile", "measure", "plan_gesture", "to_json", "to_timed",
]
__version__ = "0.1.0"

if TYPE_CHECKING:
    from .compiling.compiled import Compiled, Stream, to_json, to_timed
    from .compiling.compiled_reader import from_json
    from .compiling.compiler import compile_file, compile_program, compile_source, plan_gesture
    from .compiling.encode import encode
    from .compiling.metrics import LinkReport, measure
    from .compiling.plan import Plan
    from .errors import Diagnostic, GestError
    from .hardware import Profile
    from .language.library import load_library
    from .language.load import load
    from .profiles.profile import load_profile


def __getattr__(name: str) -> Any:
    if name not in _WHERE:
        raise AttributeError(f"module 'inmoov_dsl' has no attribute '{name}'")
    if _WHERE[name].startswith("compiling."):
        importlib.import_module(".model", __name__)  # the compiler's solver of places
    value = getattr(importlib.import_module(f".{_WHERE[name]}", __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted([*globals(), *_WHERE])
