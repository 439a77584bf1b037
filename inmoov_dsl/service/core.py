"""The service's rules without HTTP (pure): what a play request may say, the ``Order``
it becomes for the drive loop, what the library offers, and events and poses as JSON.

A request reaches only the library and the profile: steps are one line of the language,
a text is a gesture file's text (its definitions over the library's; no ``use``, no
file), a gesture is a library gesture's name (or one of the text's). A request that does not
compile is a ``GestError``, worded as the command line words it; a request that is not
one (not JSON, an unknown field, a wrong type) is a ``BadRequest``.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Sequence
from typing import Any

from ..compiling.actions import Action, Steps
from ..errors import Diagnostic, GestError, Pos, did_you_mean
from ..hardware import Profile
from ..language.program import Program
from ..live.orders import Order
from ..live.session import line_steps, text_steps
from ..profiles.tables import SIDES

MAX_BODY = 64 * 1024  #: bytes of a request's body; a larger one is refused
MAX_LOOP = 1000  #: passes a request may ask for (``"loop": true`` plays until stopped)
PLAY_FIELDS = ("gesture", "steps", "text", "side", "when", "loop", "allow_contact")
REQUEST = "<request>"  #: the file a request's steps are, in diagnostics


class BadRequest(Exception):
    """A request that is not one the service takes (HTTP 400)."""

    def __init__(self, message: str, hint: str | None = None):
        super().__init__(message)
        self.message, self.hint = message, hint

    def json(self) -> dict[str, Any]:
        """The answer's body (a hint only where there is one)."""
        return {"error": self.message, **({"hint": self.hint} if self.hint else {})}


def read_json(body: bytes) -> dict[str, Any]:
    """A request's body as a JSON object."""
    if len(body) > MAX_BODY:
        raise BadRequest(f"the body is larger than {MAX_BODY:,} bytes")
    try:
        doc = json.loads(body.decode("utf-8"))
    except (UnicodeDecodeError, ValueError, RecursionError):
        raise BadRequest("the body is not JSON", 'send {"gesture": "peace"} or '
                         '{"steps": "index 90 over 0.5s"}') from None
    if not isinstance(doc, dict):
        raise BadRequest("the body is not a JSON object", 'send {"gesture": "peace"}')
    return doc


def play_order(doc: dict[str, Any], program: Program, profile: Profile, id: str) -> Order:
    """The Order a play request asks for: its steps resolved for ``profile`` (a
    GestError when they do not compile)."""
    unknown = [k for k in doc if k not in PLAY_FIELDS]
    if unknown:
        raise BadRequest(f"unknown field '{_cut(unknown[0])}'", did_you_mean(
            unknown[0], PLAY_FIELDS) or f"fields: {', '.join(PLAY_FIELDS)}")
    if ("gesture" in doc or "text" in doc) == ("steps" in doc):
        raise BadRequest("give one of 'gesture', 'steps' and 'text'", 'send {"gesture": '
                         '"peace"} or {"steps": "index 90 over 0.5s"} (a text may come with '
                         "the 'gesture' of it to play)")
    what = "text" if "text" in doc else "gesture" if "gesture" in doc else "steps"
    text = _field(doc, what, str)
    side = _choice(doc, "side", (None, *SIDES))
    when = _choice(doc, "when", ("now", "after"), "now")
    loop = _loop(doc.get("loop", 1))
    allow = doc.get("allow_contact")
    if allow is not None and not isinstance(allow, bool):
        raise BadRequest("'allow_contact' must be true or false",
                         "true plays it though the robot's parts meet (padded parts)")
    if what == "text":
        gesture = _field(doc, "gesture", str) if "gesture" in doc else None
        steps, sources, name = text_steps(text, gesture, program, profile, REQUEST, side)
    else:
        if what == "gesture":
            _library_gesture(text, program)
        steps, sources = line_steps(_one_line(text), program, profile, REQUEST, 1, side)
        name = text if what == "gesture" else "steps"
    return Order(Steps(tuple(steps), name, sources), id, when == "after", loop, allow)


def boards_of(actions: Sequence[Action], profile: Profile) -> set[int]:
    """The boards that ``actions`` drive."""
    return {profile.servos[i].board for a in actions for i in a.servos()}


def _field(doc: dict[str, Any], key: str, kind: type) -> Any:
    value = doc[key]
    if not isinstance(value, kind):
        raise BadRequest(f"'{key}' must be a {kind.__name__ if kind is not str else 'string'}")
    return value


def _choice(doc: dict[str, Any], key: str, choices: Sequence[str | None],
            default: str | None = None) -> str | None:
    value = doc.get(key, default)
    if value not in choices:
        names = ", ".join(f'"{c}"' for c in choices if c is not None)
        raise BadRequest(f"'{key}' must be one of {names}")
    return value


def _loop(value: Any) -> int:
    """``true``: until stopped (0); ``false``: once; a whole number of passes."""
    if value is True or value is False:
        return 0 if value else 1
    if not isinstance(value, int) or not 1 <= value <= MAX_LOOP:
        raise BadRequest(f"'loop' must be true, false or a whole number from 1 to {MAX_LOOP:,}")
    return value


def _library_gesture(name: str, program: Program) -> None:
    """A GestError unless ``name`` is a library gesture."""
    if name not in program.gestures:
        pos = Pos(REQUEST, 1, 1, max(1, len(name)))
        hint = did_you_mean(name, program.gestures) or "GET /api/gestures lists them"
        raise GestError(Diagnostic("error", f"no library gesture '{_cut(name)}'", pos, hint,
                                   name if "\n" not in name else None))


def _one_line(text: str) -> str:
    """Steps are one line: a GestError at a line break."""
    cut = min((text.find(c) for c in "\r\n" if c in text), default=-1)
    if cut >= 0:
        raise GestError(Diagnostic(
            "error", "steps are one line", Pos(REQUEST, 1, cut + 1), 'send the next ones '
            'in another request with "when": "after", or name a library gesture',
            text[:cut]))
    return text


def _cut(text: str, most: int = 40) -> str:
    return text if len(text) <= most else text[:most - 3] + "..."


def problem(exc: GestError) -> dict[str, Any]:
    """A GestError as an answer's body: each diagnostic's fields, and the text the
    command line prints (the line, the caret and the hint)."""
    return {"error": exc.first.message,
            "diagnostics": [diagnostic(d) for d in exc.diagnostics],
            "text": "\n".join(d.format() for d in exc.diagnostics)}


def diagnostic(d: Diagnostic) -> dict[str, Any]:
    """One diagnostic's fields."""
    where = d.pos
    return {"severity": d.severity, "message": d.message,
            **({"hint": d.hint} if d.hint else {}), "line": where.line if where else None,
            "column": where.column if where else None,
            "width": where.width if where else None, "source": d.source_line,
            "text": d.format()}


#: the drive loop's notes and the events they are
EVENTS = {"started": "started", "finished": "done", "stopped": "stopped",
          "warning": "warning", "error": "error"}


def note_event(kind: str, id: str | None, diagnostics: Sequence[Diagnostic] = ()
               ) -> dict[str, Any] | None:
    """The event a drive-loop note (``live.drive.Note``: its kind, id and diagnostics)
    is, or None (notes only the loop needs)."""
    event_kind = EVENTS.get(kind)
    if event_kind is None:
        return None
    event: dict[str, Any] = {"event": event_kind, "id": id}
    if diagnostics:
        event["diagnostics"] = [diagnostic(d) for d in diagnostics]
    return event


def pose(profile: Profile, held: Sequence[int], velocity: Sequence[float],
         playing: str | None) -> dict[str, Any]:
    """Each servo by name: the value its board holds and whether it moves; the id of
    what plays."""
    return {"servos": {s.name: {"value": v, "moving": abs(w) > 1e-9}
                       for s, v, w in zip(profile.servos, held, velocity, strict=True)},
            "playing": playing}


def listing(program: Program, profile: Profile, files: dict[str, tuple[str, str]],
            duration: Callable[[str], float | None]) -> list[dict[str, Any]]:
    """The library as the service sees it: each gesture that plays on ``profile``,
    with its file and first comment line (``files``: name -> (file, description)) and
    its duration from the rest pose (``duration``: None where it does not play)."""
    out = []
    for name in sorted(program.gestures):
        seconds = duration(name)
        if seconds is None or name not in files:
            continue
        file, description = files[name]
        out.append({"name": name, "file": file, "profile": profile.name,
                    "duration": round(seconds, 3), "description": description})
    return out
