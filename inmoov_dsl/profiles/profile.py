"""Robot profiles: boards, servos, limits and groups, read from TOML.

This module finds a profile (a built-in name or a path), reads its text and builds it:
the loops over its tables and the checks across tables are here, each table is read
by its validator in ``tables``, each value checked in ``fields``, and every error
placed at its key by ``keys``. What a profile is made of is in ``data``."""

from __future__ import annotations

import functools
import hashlib
import os
import re
import tomllib
from dataclasses import replace
from pathlib import Path
from typing import Any

from ..errors import Diagnostic, GestError, Pos, decode_utf8, did_you_mean
from ..hardware import Board, Glove, Profile, Sensor, Servo
from ..resources import files_in, profiles_dir, read_regular
from . import collisiontable, kinds, placetable, tables, voicetable
from .fields import LIMITS, NAME_RE, cut
from .keys import Report

__all__ = ["LIMITS", "MAX_PROFILE", "NAME_RE", "Board", "Glove", "Profile",
           "Sensor", "Servo", "builtin_profiles", "find_profile", "load_profile",
           "parse_profile", "profiles_with"]


MAX_PROFILE = 1_000_000  #: bytes (characters) of a profile; a larger one is not read

def builtin_profiles() -> list[str]:
    """Names of the profiles shipped with the package."""
    return sorted(p.stem for p in profiles_dir().glob("*.toml"))


def profiles_with(name: str) -> list[str]:
    """The built-in profiles that have a servo or a group called ``name`` (each read
    again only when its file's size or time changes: every unknown name asks)."""
    found, folder = [], str(profiles_dir())
    for builtin in builtin_profiles():
        path = os.path.join(folder, f"{builtin}.toml")
        try:
            st = os.stat(path)
        except OSError:
            continue
        if name in _names_in(path, st.st_size, st.st_mtime_ns, st.st_ctime_ns):
            found.append(builtin)
    return found


@functools.lru_cache(maxsize=64)
def _names_in(path: str, *stamp: int) -> frozenset[str]:
    """The servos' and groups' names of the profile at ``path`` (none if it is wrong),
    as it was when its file had ``stamp``."""
    try:
        profile = load_profile(path)
    except GestError:
        return frozenset()
    return frozenset((*profile.names, *profile.groups))


def profile_arg(profile: Profile) -> str:
    """What ``--profile`` takes to load ``profile`` again: a built-in's name, else its
    file's path."""
    builtin = profiles_dir() / f"{profile.name}.toml"
    if profile.path and os.path.realpath(profile.path) == os.path.realpath(builtin):
        return profile.name
    return profile.path or profile.name


def find_profile(name_or_path: str) -> Path:
    """A profile file from a built-in name (``rhand``) or a path."""
    path = Path(name_or_path)
    if path.suffix == ".toml" or len(path.parts) > 1:
        if path.suffix != ".toml" or not os.path.realpath(path).endswith(".toml"):
            raise GestError(Diagnostic("error", f"a profile is a .toml file, not "
                                       f"'{name_or_path}'", hint="--profile rhand, or "
                                       "--profile my_hand.toml"))
        if path.is_dir():
            files = files_in(path, ".toml")
            raise GestError(Diagnostic("error", f"'{name_or_path}' is a folder, not a "
                                       "profile file", hint=f"give a .toml file in it: "
                                       f"{', '.join(files)}" if files else "give a .toml "
                                       "file, or a built-in profile's name (rhand)"))
        if not path.is_file():
            raise GestError(Diagnostic("error", f"profile file '{name_or_path}' not found"))
        return path
    builtin = profiles_dir() / f"{name_or_path}.toml"
    if builtin.is_file():
        return builtin
    names = builtin_profiles()
    hint = did_you_mean(name_or_path, names) or f"built-in profiles: {', '.join(names)}"
    raise GestError(Diagnostic("error", f"unknown profile '{name_or_path}'", hint=hint))


def load_profile(name_or_path: str) -> Profile:
    """Read and check a profile; any problem is a GestError naming the file. A file of
    more than MAX_PROFILE bytes is not read. The same text is checked once per process
    (a profile is read for every gesture ``gestc check`` compiles)."""
    path = find_profile(name_or_path)
    try:
        data = read_regular(path, MAX_PROFILE)
    except (OSError, ValueError) as exc:
        raise GestError(Diagnostic("error", f"cannot read profile '{path}': "
                                   f"{getattr(exc, 'strerror', None) or exc}")) from None
    if len(data) > MAX_PROFILE:
        raise GestError(Diagnostic("error", f"profile '{path}' is larger than "
                                   f"{MAX_PROFILE:,} bytes: it is not read",
                                   Pos(str(path), 1, 1)))
    return _parse_once(decode_utf8(data, str(path)), str(path))


@functools.lru_cache(maxsize=32)
def _parse_once(text: str, file: str) -> Profile:
    return parse_profile(text, file)


def parse_profile(text: str, file: str = "<profile>") -> Profile:
    """Build a Profile from TOML text. Pure: no file access. A byte-order mark at the
    start (what Notepad writes; TOML has none) is not part of the text."""
    text = text.removeprefix("\ufeff")
    if len(text) > MAX_PROFILE:
        raise GestError(Diagnostic("error", f"the profile is longer than {MAX_PROFILE:,} "
                                   f"characters: it is not read", Pos(file, 1, 1)))
    data = read_toml(text, file)
    profile = _build(data, Report(text, file), file)
    digest = hashlib.sha256(text.encode("utf-8", "surrogatepass")).hexdigest()
    return replace(profile, sha256=digest)


def read_toml(text: str, file: str) -> dict[str, Any]:
    """The data of TOML text (a profile, a control map); invalid TOML is an error at its
    place."""
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        match = re.search(r"\(at line (\d+), column (\d+)\)", str(exc))
        pos = Pos(file, int(match[1]), int(match[2])) if match else Pos(file, 1, 1)
        message = re.sub(r"\s*\(at line.*\)", "", str(exc))
        lines = text.split("\n")
        line = lines[pos.line - 1] if pos.line <= len(lines) else None
        raise GestError(Diagnostic("error", f"invalid TOML: {message}", pos, None, line)) from None
    except RecursionError:
        raise GestError(Diagnostic("error", "invalid TOML: arrays or tables nested too deep",
                                   Pos(file, 1, 1))) from None
    except ValueError:  # an integer of more than 4,300 digits
        found = re.search(r"\d{100}", text)
        offset = found.start() if found else 0
        line = text.count("\n", 0, offset) + 1
        column = offset - (text.rfind("\n", 0, offset) + 1) + 1
        raise GestError(Diagnostic("error", "invalid TOML: a number of thousands of digits",
                                   Pos(file, line, column),
                                   source_line=text.split("\n")[line - 1])) from None


def _build(data: dict[str, Any], report: Report, file: str) -> Profile:
    """The profile of TOML ``data``: its tables in order, each read by its validator in
    ``tables`` with what the tables before it hold (the IDs, servos and joints taken),
    and the checks across tables. Every problem is reported at its key, and all of
    them are raised together."""
    name, description = tables.top(report, data, Path(file).stem)
    boards_data = tables.board_tables(report, data)
    servos_data = tables.servo_tables(report, data)
    boards: list[Board] = []
    listed: dict[str, int] = {}  # the servos the boards list, each by its board's ID
    for k, table in enumerate(boards_data):
        if (board := tables.board(report, k, table, {b.id for b in boards}, listed,
                                  servos_data)) is not None:
            boards.append(board)
            listed.update(dict.fromkeys(board.servos, board.id))
    for servo_name in servos_data:
        if servo_name not in listed:
            report.error(("servo", servo_name), f"servo '{cut(servo_name)}' is on no board",
                         hint="add it to the 'servos' list of a [[board]]")
    servos: list[Servo] = []  # board by board, in each board's order
    ids: dict[int, str] = {}  # servo IDs are unique in the robot, and so are joints
    joints: dict[str, str] = {}
    for board in boards:
        for servo_name in board.servos:
            if servo_name in servos_data and (servo := tables.servo(
                    report, servo_name, servos_data[servo_name], board.id, ids)) is not None:
                if servo.joint in joints:
                    report.error(("servo", servo_name, "joint"), f"servo '{servo_name}' turns "
                                 f"joint '{servo.joint}', as servo '{joints[servo.joint]}' does")
                servos.append(servo)
                ids[servo.id] = servo_name
                joints[servo.joint] = servo_name
    kinds.check_places(report, boards, servos)
    names = tuple(s.name for s in servos)
    groups = tables.groups(report, data.get("groups", {}), names)
    sides = tables.sides(report, data["sides"], names) if "sides" in data else {}
    by_id = {board.id: board for board in reversed(boards)}  # the first of an ID
    taken = set(by_id)  # a glove's ID is no board's and no other glove's
    gloves: list[Glove] = []
    for k, table in enumerate(tables.glove_tables(report, data)):
        if (glove := tables.glove(report, k, table, by_id, taken)) is not None:
            gloves.append(glove)
            taken.add(glove.id)
    voice = voicetable.voice(report, data["voice"], servos) if "voice" in data else None
    clearance = (collisiontable.collision(report, data["collision"]) if "collision" in data
                 else collisiontable.CLEARANCE_MM)
    places = placetable.places(report, data["place"]) if "place" in data else {}
    report.stop()
    return Profile(name, description, tuple(boards), tuple(servos), groups, file,
                   gloves=tuple(gloves), sides=sides, voice=voice, clearance_mm=clearance,
                   places=places)
