"""The places already solved, kept in the user's private cache between programs: a
hand's place costs the Robotics Toolbox's import (seconds) before its milliseconds of
solving, so a file checked again, a gesture played again, a library gesture each
command compiles, solves nothing twice.

One JSON file per robot model (a digest of its parts, frames, servos' travel and
clearance: what the values depend on), its entries keyed by the rest: this code's
``VERSION``, whether the toolbox is installed (the fallback finds other values), the aim
and the pose before it. Only values are kept, never
an error (an error is told again, solved again). A file that cannot be read, or was
written by another user, is passed over; one that cannot be written is left as it is.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import tempfile
from collections.abc import Sequence
from pathlib import Path

from ..compiling.reaching import Aim
from ..hardware import Profile
from ..resources import private_cache_dir, private_file
from . import ik
from .urdf import body

VERSION = 1  #: of the solve: a change that gives other values changes it
MOST = 20_000  #: entries one file keeps (the oldest go first)
FOLDER = "places"
_KEPT: dict[Path, dict[str, dict[str, int]]] = {}  #: each file read once per process


_MODELS: dict[tuple[str, str], str] = {}  #: (name, text digest) -> the model's digest


def _path(profile: Profile) -> Path | None:
    folder = private_cache_dir()
    if folder is None:
        return None
    key = (profile.name, profile.sha256)
    if key not in _MODELS:
        what = repr(body(profile)) + repr([(s.joint, s.rest, s.lo, s.hi, s.calibration)
                                           for s in profile.servos]) + \
            repr(profile.clearance_mm)
        _MODELS[key] = hashlib.sha256(what.encode()).hexdigest()[:24]
    return folder / FOLDER / f"{_MODELS[key]}.json"


def _key(aim: Aim, pose: Sequence[int]) -> str:
    what = repr((VERSION, ik.installed(), aim.what, tuple(round(c, 9) for c in aim.xyz),
                 aim.servos, tuple(int(v) for v in pose)))
    return hashlib.sha256(what.encode()).hexdigest()[:32]


def _entries(path: Path) -> dict[str, dict[str, int]]:
    if path not in _KEPT:
        try:
            ok = path.is_file() and private_file(path)
            data = json.loads(path.read_text(encoding="utf-8")) if ok else {}
            _KEPT[path] = data if isinstance(data, dict) else {}
        except (OSError, ValueError, RecursionError):
            _KEPT[path] = {}
    return _KEPT[path]


def found(profile: Profile, aim: Aim, pose: Sequence[int]) -> dict[int, int] | None:
    """The values kept for ``aim`` from ``pose``, or None."""
    path = _path(profile)
    if path is None:
        return None
    kept = _entries(path).get(_key(aim, pose))
    try:
        values = {int(i): int(v) for i, v in kept.items()} if isinstance(kept, dict) else None
    except (TypeError, ValueError):
        return None
    if values is None or set(values) != set(aim.servos) or not all(
            profile.servos[i].lo <= v <= profile.servos[i].hi for i, v in values.items()):
        return None  # not this aim's servos, or out of their range: not used
    return values


def keep(profile: Profile, aim: Aim, pose: Sequence[int], values: dict[int, int]) -> None:
    """Keep ``values`` for ``aim`` from ``pose`` (written whole or not at all)."""
    path = _path(profile)
    if path is None:
        return
    entries = _entries(path)
    entries[_key(aim, pose)] = {str(i): v for i, v in values.items()}
    while len(entries) > MOST:
        entries.pop(next(iter(entries)))
    try:
        path.parent.mkdir(mode=0o700, parents=True, exist_ok=True)
        fd, temporary = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
    except OSError:
        return
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            json.dump(entries, f)
        os.replace(temporary, path)
    except OSError:
        with contextlib.suppress(OSError):
            os.unlink(temporary)
