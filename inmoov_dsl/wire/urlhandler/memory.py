"""The virtual boards' EEPROM between processes: the pose each ``sim://`` board stored,
kept as a small JSON file per profile and board in the user's private state directory
(``resources.private_state_dir``), never in a shared temporary one.

A file that is missing, unreadable, someone else's, or for other servos is no memory:
the board powers up at rest, as a new one would. Nothing here raises.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
from pathlib import Path

from ...boards.rig.core import BoardCore
from ...hardware import Profile
from ...profiles.profile import builtin_profiles, find_profile
from ...protocol import MAX_VALUE
from ...resources import private_file, private_state_dir
from ..sim import VirtualBoard, settled

MAX_FILE = 4096  #: bytes; a board's memory is far smaller


def _file(profile: Profile, board: int) -> Path | None:
    """Where the board ``board`` of ``profile`` keeps its pose: by name for a built-in
    profile, by the profile file's path otherwise."""
    where = private_state_dir()
    if where is None:
        return None
    name = profile.name
    with contextlib.suppress(Exception):
        if not (name in builtin_profiles() and
                find_profile(name).resolve() == Path(profile.path).resolve()):
            digest = hashlib.sha256(str(Path(profile.path).resolve()).encode()).hexdigest()
            name = f"{Path(profile.path).stem}-{digest[:12]}"
    safe = "".join(c if c.isalnum() or c in "-_" else "_" for c in name)
    return where / "sim" / f"{safe}-{board}.json"


def recall(profile: Profile, core: BoardCore) -> list[int] | None:
    """The pose board ``core`` of ``profile`` last stored, or None."""
    path = _file(profile, core.board_id)
    if path is None or not private_file(path):
        return None
    try:
        with open(path, "rb") as f:
            kept = json.loads(f.read(MAX_FILE + 1)[:MAX_FILE])
        ids, pose = kept["servos"], kept["pose"]
    except (OSError, ValueError, TypeError, KeyError):
        return None
    if ids != [s.id for s in core.servos] or not isinstance(pose, list) or \
            len(pose) != len(ids) or not all(type(v) is int and 0 <= v <= MAX_VALUE
                                              for v in pose):
        return None
    return pose


def keep(profile: Profile, board: VirtualBoard) -> None:
    """Keep the pose ``board`` will have stored (``VirtualBoard.settled``); a board that
    never stored one (a ``fresh`` one) leaves no memory."""
    pose = settled(board)
    path = _file(profile, board.core.board_id)
    if path is None:
        return
    if pose is None:
        with contextlib.suppress(OSError):
            path.unlink()
        return
    text = json.dumps({"servos": [s.id for s in board.core.servos], "pose": list(pose)})
    with contextlib.suppress(OSError):
        path.parent.mkdir(mode=0o700, exist_ok=True)
        spare = path.with_suffix(f".{os.getpid()}.tmp")
        fd = os.open(spare, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
        with open(fd, "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(spare, path)
