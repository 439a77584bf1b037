"""Robot profiles: boards, servos, limits and groups, read from TOML."""

from __future__ import annotations

import functools
import hashlib
import os
import re
import tomllib
from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path
from typing import Any

from . import protocol
from .errors import Diagnostic, GestError, Pos, decode_utf8, did_you_mean
from .resources import profiles_dir, read_regular
from .syntax import KEYWORDS

NAME_RE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
MAX_PROFILE = 1_000_000  #: bytes (characters) of a profile; a larger one is not read
MAX_BAUD = 2_000_000  #: the fastest link a board or glove may declare
#: the sane range of each limit, command degrees per second (squared, cubed)
LIMITS = {"max_velocity": (1.0, 1e5), "max_acceleration": (1.0, 1e7), "max_jerk": (1.0, 1e9)}


@dataclass(frozen=True)
class Servo:
    """One servo, in command degrees (0..180 as sent on the wire)."""

    name: str
    id: int
    board: int
    lo: int  #: smallest value a gesture may command
    hi: int  #: largest value a gesture may command
    rest: int
    max_velocity: float  #: command degrees / s
    max_acceleration: float  #: command degrees / s^2
    max_jerk: float  #: command degrees / s^3
    calibration: tuple[int, int]  #: board side: 0..180 is mapped onto these servo angles
    reversed: bool  #: board side: 180..0 is mapped onto the calibration instead
    pin: int | None


@dataclass(frozen=True)
class Board:
    id: int
    name: str
    baud: int
    servos: tuple[str, ...]
    pos: Pos | None = field(default=None, compare=False)  #: its ``id`` in the profile


@dataclass(frozen=True)
class Sensor:
    """One flex sensor of a glove: the servo it commands and how it reads."""

    servo: str
    pin: int  #: analog pin (14 is A0 on an Uno or Nano)
    calibration: tuple[int, int]  #: readings (0..1023) that map to 0 and 180
    reversed: bool = False  #: the low reading maps to 180 instead


@dataclass(frozen=True)
class Glove:
    """A flex-sensor glove: it reads its sensors and commands a servo board."""

    id: int
    name: str
    board: int  #: the servo board it sends to, on its software serial command port
    baud: int  #: USB, to the computer
    command_pins: tuple[int, int]  #: rx, tx of the command port
    deadband: int  #: command degrees a value must move before it is sent again
    frame_ms: int  #: ms between readings
    sensors: tuple[Sensor, ...]


@dataclass(frozen=True)
class Profile:
    name: str
    description: str
    boards: tuple[Board, ...]
    servos: tuple[Servo, ...]  #: board by board, in each board's order
    groups: dict[str, tuple[str, ...]]
    path: str = ""
    sha256: str = ""  #: of the TOML text it was read from
    gloves: tuple[Glove, ...] = ()

    def index(self, name: str) -> int:
        """The position of servo ``name`` in ``servos``; KeyError if there is none."""
        return self._indices[name]

    @cached_property
    def _indices(self) -> dict[str, int]:
        return {servo.name: i for i, servo in enumerate(self.servos)}

    @cached_property
    def names(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.servos)

    @property
    def rest_pose(self) -> dict[str, int]:
        return {s.name: s.rest for s in self.servos}


def builtin_profiles() -> list[str]:
    """Names of the profiles shipped with the package."""
    return sorted(p.stem for p in profiles_dir().glob("*.toml"))


def profiles_with(name: str) -> list[str]:
    """The built-in profiles that have a servo or a group called ``name``."""
    found = []
    for builtin in builtin_profiles():
        try:
            profile = load_profile(builtin)
        except GestError:
            continue
        if name in profile.names or name in profile.groups:
            found.append(builtin)
    return found


def find_profile(name_or_path: str) -> Path:
    """A profile file from a built-in name (``rhand``) or a path."""
    path = Path(name_or_path)
    if path.suffix == ".toml" or len(path.parts) > 1:
        if path.suffix != ".toml" or not os.path.realpath(path).endswith(".toml"):
            raise GestError(Diagnostic("error", f"a profile is a .toml file, not "
                                       f"'{name_or_path}'", hint="--profile rhand, or "
                                       "--profile my_hand.toml"))
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
    """Build a Profile from TOML text. Pure: no file access."""
    if len(text) > MAX_PROFILE:
        raise GestError(Diagnostic("error", f"the profile is longer than {MAX_PROFILE:,} "
                                   f"characters: it is not read", Pos(file, 1, 1)))
    try:
        data = tomllib.loads(text)
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
    profile = _Builder(data, file, text).build()
    digest = hashlib.sha256(text.encode("utf-8", "surrogatepass")).hexdigest()
    return replace(profile, sha256=digest)


_HEADER = re.compile(r"""\s*(\[\[?)\s*([A-Za-z0-9_\-."' ]+?)\s*(\]\]?)\s*(#.*)?$""")
_KEY = re.compile(r"""\s*(["']?)([A-Za-z0-9_\-]+)\1\s*[=.]""")

Where = tuple[tuple[str, ...], int, str | None]  #: a table, which one of its array, a key


class _KeyIndex:
    """Where a profile's text has its table headers and keys, for errors. tomllib gives
    no positions: one scan of the lines for headers (``[servo.index]``, ``[[board]]``)
    and keys (``baud =``), which is what a profile is made of, answers them all."""

    def __init__(self, text: str, file: str):
        self.file = file
        self.lines = text.split("\n")
        self.headers: dict[tuple[tuple[str, ...], int], tuple[int, int, int]] = {}
        self.keys: dict[tuple[tuple[str, ...], int, str], tuple[int, int, int]] = {}
        self.anywhere: dict[str, tuple[int, int, int]] = {}
        current: tuple[tuple[str, ...], int] = ((), 0)
        counts: dict[tuple[str, ...], int] = {}
        for number, line in enumerate(self.lines, 1):
            if found := _HEADER.match(line):
                path = tuple(p.strip().strip("\"'") for p in found[2].split("."))
                index = 0
                if found[1] == "[[":
                    index = counts[path] = counts.get(path, -1) + 1
                current = (path, index)
                self.headers.setdefault(current, (number, found.start(1) + 1,
                                                  found.end(3) - found.start(1)))
            elif found := _KEY.match(line):
                place = (number, found.start(2) + 1, len(found[2]))
                self.keys.setdefault((*current, found[2]), place)
                self.anywhere.setdefault(found[2], place)

    def find(self, table: tuple[str, ...], key: str | None, nth: int = 0
             ) -> tuple[Pos, str | None]:
        """Where ``key`` of ``table`` is set (of the ``nth`` ``[[table]]`` of an array of
        tables), and that line: the key's line, else the table's header, else the key's
        first line anywhere, else line 1."""
        place = (key is not None and self.keys.get((table, nth, key))) \
            or self.headers.get((table, nth)) \
            or (key is not None and self.anywhere.get(key)) or (1, 1, 1)
        return Pos(self.file, *place), self.lines[place[0] - 1]


class _Builder:
    def __init__(self, data: dict[str, Any], file: str, text: str = ""):
        self.data = data
        self.file = file
        self.text = text
        self.errors: list[Diagnostic] = []
        self._index: _KeyIndex | None = None

    def fail(self, message: str, where: Where = ((), 0, None), hint: str | None = None
             ) -> None:
        """An error at the line of the TOML key it is about (``where``)."""
        pos, line = self.place(where)
        self.errors.append(Diagnostic("error", message, pos, hint, line))

    def place(self, where: Where) -> tuple[Pos, str | None]:
        if self._index is None:
            self._index = _KeyIndex(self.text, self.file)
        table, nth, key = where
        return self._index.find(table, key, nth)

    def where(self, where: Where) -> Pos:
        return self.place(where)[0]

    def number(self, where: str, table: dict, key: str, at: Where, limits: tuple[float, float]
               ) -> float:
        low, high = limits
        value = table.get(key)
        if value is None:
            unit = {"max_velocity": "", "max_acceleration": " squared", "max_jerk": " cubed"}
            self.fail(f"{where}: missing '{key}'", at,
                      f"add {key} = N, in command degrees per second{unit.get(key, '')}")
            return 1.0
        if isinstance(value, bool) or not isinstance(value, int | float):
            self.fail(f"{where}: '{key}' must be a number, got {_shown(value)}", at)
            return 1.0
        if not value > 0:
            self.fail(f"{where}: '{key}' must be greater than 0, got {_shown(value)}", at)
            return 1.0
        if not low <= value <= high:
            self.fail(f"{where}: '{key}' must be in {low:,.0f}..{high:,.0f}, got {_shown(value)}",
                      at, "limits are command degrees per second (squared, cubed): see "
                      "docs/profiles.md")
            return 1.0
        return float(value)

    def pair(self, where: str, table: dict, key: str, default: tuple[int, int], at: Where
             ) -> tuple[int, int]:
        value = table.get(key, list(default))
        ok = (
            isinstance(value, list)
            and len(value) == 2
            and all(_whole(v) for v in value)
            and 0 <= value[0] <= value[1] <= protocol.MAX_VALUE
        )
        if not ok:
            self.fail(f"{where}: '{key}' must be [low, high] with 0 <= low <= high <= 180, "
                      f"got {_shown(value)}", at)
            return default
        return (value[0], value[1])

    def build(self) -> Profile:
        data = self.data
        name = data.get("name", Path(self.file).stem)
        if not isinstance(name, str):
            self.fail(f"'name' must be a string, got {_shown(name)}", ((), 0, "name"))
            name = Path(self.file).stem
        description = data.get("description", "")
        if not isinstance(description, str):
            self.fail(f"'description' must be a string, got {_shown(description)}",
                      ((), 0, "description"))
            description = ""
        boards_data = data.get("board", [])
        servos_data = data.get("servo", {})
        if not isinstance(boards_data, list) or not boards_data:
            self.fail("a profile needs at least one [[board]]", ((), 0, "board"))
            raise GestError(self.errors)
        if not isinstance(servos_data, dict):
            self.fail("[servo.NAME] tables expected", ((), 0, "servo"))
            raise GestError(self.errors)

        boards: list[Board] = []
        servos: list[Servo] = []
        owner: dict[str, int] = {}
        low, high = protocol.FIRST_BOARD_ID, min(protocol.Signal) - 1
        for k, b in enumerate(boards_data):
            at = (("board",), k, "id")
            if not isinstance(b, dict):
                self.fail(f"board {k + 1}: expected a [[board]] table, got {_shown(b)}", at)
                continue
            bid = b.get("id")
            where = f"board {bid}"
            if not _whole(bid) or not low <= bid <= high:
                self.fail(f"board id must be a whole number in {low}..{high}, "
                          f"got {_shown(bid)}", at)
                continue
            if any(x.id == bid for x in boards):
                self.fail(f"board {bid} is declared twice", at)
            baud = b.get("baud", 9600)
            at = (("board",), k, "baud")
            if not _whole(baud) or not 0 < baud <= MAX_BAUD:
                self.fail(f"{where}: 'baud' must be a whole number in 1..{MAX_BAUD:,}, "
                          f"got {_shown(baud)}", at)
                baud = 9600
            elif protocol.pairs_per_frame(baud) < 1:
                self.fail(f"{where}: baud {baud} is too slow: not one servo command fits "
                          f"in a 20 ms servo frame", at, hint="use 9600 or more")
            names = b.get("servos", [])
            at = (("board",), k, "servos")
            if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
                self.fail(f"{where}: 'servos' must be a list of servo names", at)
                names = []
            for n in names:
                if n in owner:
                    self.fail(f"servo '{_cut(n)}' is on board {owner[n]} and board {bid}", at)
                owner[n] = bid
            label = b.get("name", f"board {bid}")
            if not isinstance(label, str):
                self.fail(f"{where}: 'name' must be a string, got {_shown(label)}",
                          (("board",), k, "name"))
                label = f"board {bid}"
            boards.append(Board(bid, label, baud, tuple(dict.fromkeys(names)),
                                self.where((("board",), k, "id"))))

        for servo_name, bid in owner.items():
            if servo_name not in servos_data:
                k = next(i for i, b in enumerate(boards) if b.id == bid)
                self.fail(f"board {bid} lists servo '{_cut(servo_name)}' but there is no "
                          f"[servo.{_cut(servo_name)}]", (("board",), k, "servos"),
                          did_you_mean(servo_name, servos_data))
        for servo_name in servos_data:
            if servo_name not in owner:
                self.fail(f"servo '{_cut(servo_name)}' is on no board",
                          (("servo", servo_name), 0, None),
                          hint="add it to the 'servos' list of a [[board]]")

        ids: dict[int, str] = {}
        for board in boards:
            for servo_name in board.servos:
                s = servos_data.get(servo_name)
                if s is None:
                    continue  # reported above
                if not isinstance(s, dict):
                    self.fail(f"servo '{_cut(servo_name)}': expected a [servo."
                              f"{_cut(servo_name)}] table, got {_shown(s)}",
                              (("servo",), 0, servo_name))
                    continue
                servos.append(self.servo(servo_name, s, board.id, ids))

        groups = self.groups(data.get("groups", {}), [s.name for s in servos])
        gloves = self.gloves(data.get("glove", []), boards)
        if self.errors:
            raise GestError(self.errors)
        return Profile(name, description, tuple(boards), tuple(servos), groups, self.file,
                       gloves=gloves)

    def servo(self, name: str, s: dict, board: int, ids: dict[int, str]) -> Servo:
        where = f"servo '{_cut(name)}'"
        table = ("servo", name)

        def at(key: str | None) -> Where:
            return (table, 0, key)

        if not NAME_RE.match(name) or name in KEYWORDS:
            self.fail(f"{where}: a servo name must be a word (letters, digits, _) "
                      f"and not a keyword of the language", at(None))
        sid = s.get("id")
        if not _whole(sid) or not 0 <= sid <= protocol.MAX_SERVO_ID:
            self.fail(f"{where}: 'id' must be a whole number in 0..{protocol.MAX_SERVO_ID}, "
                      f"got {_shown(sid)}", at("id"))
            sid = 0
        elif sid in ids:
            self.fail(f"{where}: id {sid} is already used by servo '{_cut(ids[sid])}'",
                      at("id"))
        ids[sid] = name
        lo, hi = self.pair(where, s, "range", (0, protocol.MAX_VALUE), at("range"))
        rest = s.get("rest", lo)
        if not _whole(rest) or not lo <= rest <= hi:
            self.fail(f"{where}: 'rest' must be a whole number in its range {lo}..{hi}, "
                      f"got {_shown(rest)}", at("rest"))
            rest = lo
        pin = s.get("pin")
        if pin is not None and (not _whole(pin) or not 0 <= pin <= 255):
            self.fail(f"{where}: 'pin' must be a whole number in 0..255, got {_shown(pin)}",
                      at("pin"))
            pin = None
        reverse = s.get("reversed", False)
        if not isinstance(reverse, bool):
            self.fail(f"{where}: 'reversed' must be true or false, got {_shown(reverse)}",
                      at("reversed"))
            reverse = False
        return Servo(
            name=name, id=sid, board=board, lo=lo, hi=hi, rest=rest,
            max_velocity=self.number(where, s, "max_velocity", at("max_velocity"),
                                     LIMITS["max_velocity"]),
            max_acceleration=self.number(where, s, "max_acceleration", at("max_acceleration"),
                                         LIMITS["max_acceleration"]),
            max_jerk=self.number(where, s, "max_jerk", at("max_jerk"), LIMITS["max_jerk"]),
            calibration=self.pair(where, s, "calibration", (0, protocol.MAX_VALUE),
                                  at("calibration")),
            reversed=reverse,
            pin=pin,
        )

    def whole(self, where: str, table: dict, key: str, default: int, low: int, high: int,
              at: Where) -> int:
        value = table.get(key, default)
        if not _whole(value) or not low <= value <= high:
            self.fail(f"{where}: '{key}' must be a whole number in {low}..{high}, "
                      f"got {_shown(value)}", at)
            return default
        return value

    def gloves(self, data: Any, boards: list[Board]) -> tuple[Glove, ...]:
        if not isinstance(data, list) or not all(isinstance(g, dict) for g in data):
            self.fail("[[glove]] tables expected", ((), 0, "glove"))
            return ()
        taken = {b.id for b in boards}
        out = []
        for k, g in enumerate(data):
            def at(key: str | None, k: int = k) -> Where:
                return (("glove",), k, key)

            gid = g.get("id")
            where = f"glove {gid}"
            low, high = protocol.FIRST_BOARD_ID, min(protocol.Signal) - 1
            if not _whole(gid) or not low <= gid <= high or gid in taken:
                self.fail(f"glove id must be a board ID in {low}..{high} that no other "
                          f"board has, got {_shown(gid)}", at("id"))
                continue
            taken.add(gid)
            board = g.get("board")
            target = next((b for b in boards if _whole(board) and b.id == board), None)
            if target is None:
                self.fail(f"{where}: 'board' must be the ID of a servo board of the profile, "
                          f"got {_shown(board)}", at("board"))
                continue
            pins = g.get("command_pins", [10, 11])
            if not (isinstance(pins, list) and len(pins) == 2
                    and all(_whole(p) and 0 <= p <= 255 for p in pins)):
                self.fail(f"{where}: 'command_pins' must be [rx, tx], got {_shown(pins)}",
                          at("command_pins"))
                pins = [10, 11]
            sensors = []
            sensors_data = g.get("sensors", [])
            if not isinstance(sensors_data, list):
                self.fail(f"{where}: 'sensors' must be a list of {{ servo = ..., pin = ..., "
                          f"calibration = [low, high] }}", at("sensors"))
                continue
            for n, sd in enumerate(sensors_data):
                swhere = f"{where}, sensor {n + 1}"
                if not isinstance(sd, dict):
                    self.fail(f"{swhere}: expected {{ servo = ..., pin = ..., "
                              f"calibration = [low, high] }}", at("sensors"))
                    continue
                servo = sd.get("servo")
                if servo not in target.servos:
                    self.fail(f"{swhere}: 'servo' must be a servo of board {board}, "
                              f"got {_shown(servo)}", at("sensors"),
                              did_you_mean(str(servo), target.servos))
                    continue
                cal = sd.get("calibration")
                if not (isinstance(cal, list) and len(cal) == 2
                        and all(_whole(c) for c in cal)
                        and 0 <= cal[0] < cal[1] <= 1023):
                    self.fail(f"{swhere}: 'calibration' must be [low, high] readings with "
                              f"0 <= low < high <= 1023, got {_shown(cal)}", at("sensors"))
                    continue
                reverse = sd.get("reversed", False)
                if not isinstance(reverse, bool):
                    self.fail(f"{swhere}: 'reversed' must be true or false, got "
                              f"{_shown(reverse)}", at("sensors"))
                    reverse = False
                sensors.append(Sensor(servo, self.whole(swhere, sd, "pin", 14, 0, 255,
                                                        at("sensors")),
                                      (cal[0], cal[1]), reverse))
            if not sensors:
                self.fail(f"{where}: a glove needs at least one sensor", at("sensors"))
                continue
            label = g.get("name", f"glove {gid}")
            if not isinstance(label, str):
                self.fail(f"{where}: 'name' must be a string, got {_shown(label)}",
                          at("name"))
                label = f"glove {gid}"
            out.append(Glove(gid, label, board,
                             self.whole(where, g, "baud", 9600, 300, MAX_BAUD, at("baud")),
                             (pins[0], pins[1]),
                             self.whole(where, g, "deadband", 2, 0, 180, at("deadband")),
                             self.whole(where, g, "frame_ms", 20, 1, 1000, at("frame_ms")),
                             tuple(sensors)))
        return tuple(out)

    def groups(self, data: Any, servo_names: list[str]) -> dict[str, tuple[str, ...]]:
        groups: dict[str, tuple[str, ...]] = {}
        if not isinstance(data, dict):
            self.fail("[groups] must map a group name to a list of servo names",
                      ((), 0, "groups"))
            return groups
        for gname, members in data.items():
            at = (("groups",), 0, gname)
            if not isinstance(members, list) or not all(isinstance(m, str) for m in members):
                self.fail(f"group '{_cut(gname)}' must be a list of servo names", at)
                continue
            if not NAME_RE.match(gname) or gname in KEYWORDS:
                self.fail(f"group '{_cut(gname)}': a group name must be a word (letters, "
                          f"digits, _) and not a keyword of the language", at)
            if gname in servo_names:
                self.fail(f"group '{gname}' has the name of a servo", at)
            for m in members:
                if m not in servo_names:
                    self.fail(f"group '{_cut(gname)}' names unknown servo '{_cut(m)}'", at,
                              did_you_mean(m, servo_names))
            groups[gname] = tuple(members)
        groups.setdefault("all", tuple(servo_names))
        return groups


def _whole(value: Any) -> bool:
    """A TOML integer (not a boolean)."""
    return isinstance(value, int) and not isinstance(value, bool)


def _cut(text: str, most: int = 40) -> str:
    return text if len(text) <= most else text[:most - 3] + "..."


def _shown(value: Any) -> str:
    """A value as an error quotes it, cut short."""
    return _cut(repr(value), 60)
