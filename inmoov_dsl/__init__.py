"""inmoov-dsl: gestures for the InMoov hand, compiled to jerk-limited, timed byte streams.

    >>> from inmoov_dsl import compile_source
    >>> c = compile_source("peace: index 180, middle 180 over 0.6s")
    >>> c.streams[0].data[0]   # every stream opens with CANCEL
    255
"""

from .compiled import Compiled, from_json, to_json, to_timed
from .compiler import compile_file, compile_program, compile_source, load, plan_gesture
from .encode import Stream, encode
from .errors import Diagnostic, GestError
from .library import load_library
from .metrics import LinkReport, measure
from .plan import Plan
from .profile import Profile, load_profile

__all__ = [
    "Compiled", "Diagnostic", "GestError", "LinkReport", "Plan", "Profile", "Stream",
    "compile_file", "compile_program", "compile_source", "encode", "from_json", "load",
    "load_library", "load_profile", "measure", "plan_gesture", "to_json", "to_timed",
]
__version__ = "0.1.0"
