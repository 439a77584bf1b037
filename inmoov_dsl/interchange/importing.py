"""Another tool's animation as the samples the recorder reduces (pure): Blender Servo
Animation's JSON or header, Bottango's commands, or our CSV, read into (time, servo ID,
value) on every frame, each ID mapped to a servo of the profile by its place on the
board (pin or channel) or by a map, each width to the servo's nearest whole value."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from ..boards.pulses import widths
from ..errors import Diagnostic, GestError, did_you_mean
from ..hardware import Board, Profile, Servo
from ..protocol import SERVO_FRAME
from . import FORMATS_IN, UNITS, bottango, bsa, table
from .frames import from_units, place

MAX_SECONDS = 3600.0  #: an animation longer than a gesture may be is refused
US_RANGE = (400, 2700)  #: us: a width outside it is not a servo's pulse


@dataclass
class Animation:
    """What a file says: for each ID (a place) or servo name, its widths (us) or values
    on a frame grid."""

    times: np.ndarray
    series: dict[int | str, np.ndarray] = field(default_factory=dict)
    values: bool = False  #: the series are command values (our CSV), not widths


def detect(name: str, text: str) -> str:
    """The format of a file called ``name`` holding ``text``: by its suffix, else by what
    it begins with."""
    lower, head = name.lower(), text.lstrip()[:4096]
    for suffix, fmt in ((".json", "bsa-json"), (".h", "bsa-h"), (".csv", "csv")):
        if lower.endswith(suffix):
            return fmt
    if head.startswith("{"):
        return "bsa-json"
    if "ANIMATION_DATA" in head:
        return "bsa-h"
    if "sC," in head or head.startswith("rSVPin"):
        return "bottango"
    if head.startswith("time,"):
        return "csv"
    raise GestError(Diagnostic("error", f"{name}: which animation is it? not Blender Servo "
                               "Animation's JSON or header, Bottango's commands, or a CSV "
                               "of ours", hint="name its format: --format " +
                               "|".join(FORMATS_IN)))


def read(text: str, where: str, fmt: str, unit: str, tick: float) -> Animation:
    """The animation in ``text`` (format ``fmt``; positions in ``unit``)."""
    if fmt == "csv":
        times, columns = table.read(text, where)
        _no_longer_than_a_gesture(float(times[-1]), where)
        return Animation(times, dict(columns), values=True)
    if fmt == "bottango":
        setups, found = bottango.read(text, where)
        end = max(c.start + c.duration for cs in found.values() for c in cs) / 1000
        times = _grid(end, 1 / SERVO_FRAME, where)
        ms = [int(round(t * 1000)) for t in times]
        series = {pin: np.asarray(bottango.evaluate(_setup(setups, pin, cs, where), cs, ms),
                                  dtype=float) for pin, cs in found.items()}
        return Animation(times, series)
    fps, frames = (bsa.read_json if fmt == "bsa-json" else bsa.read_header)(text, where)
    times = _grid((len(frames) - 1) / fps, fps, where)
    series: dict[int | str, np.ndarray] = {}
    for servo in sorted(bsa.ids(frames)):
        held, first = [], next(f[servo] for f in frames if servo in f)
        for frame in frames:
            first = frame.get(servo, first)
            held.append(first)
        series[servo] = from_units(np.asarray(held), unit, tick)
    _check_widths(series, unit, where)
    return Animation(times, series)


def _grid(end: float, rate: float, where: str) -> np.ndarray:
    _no_longer_than_a_gesture(end, where)
    return np.arange(int(round(end * rate)) + 1) / rate


def _no_longer_than_a_gesture(end: float, where: str) -> None:
    if end > MAX_SECONDS:
        raise GestError(Diagnostic("error", f"{where}: the animation lasts {end:.0f} s: a "
                                   f"gesture lasts at most {MAX_SECONDS:.0f} s"))


def _setup(setups: Mapping[int, bottango.Setup], pin: int, found, where: str
           ) -> bottango.Setup:
    if pin not in setups:
        raise GestError(Diagnostic("error", f"{where}: pin {pin} has curves but no "
                                   f"'rSVPin,{pin},...' to say its widths"))
    return setups[pin]


def _check_widths(series: Mapping[int | str, np.ndarray], unit: str, where: str) -> None:
    for key, us in series.items():
        if len(us) and (us.min() < US_RANGE[0] or us.max() > US_RANGE[1]):
            raise GestError(Diagnostic(
                "error", f"{where}: servo ID {key} goes from {us.min():.0f} to "
                f"{us.max():.0f} us, not a servo's pulse (read as {unit})",
                hint="say what its positions are: --units " + "|".join(UNITS) +
                " (Blender Servo Animation's default 150..600 are PCA9685 ticks)"))


def samples(animation: Animation, profile: Profile, board: Board | None,
            ids: Mapping[int, str] | None = None, where: str = "") -> tuple[
                list[tuple[float, int, int]], list[str]]:
    """(time, servo ID, value) on every frame of every servo the animation moves, and
    what was changed on the way (a value outside a servo's range, brought within)."""
    out: list[tuple[float, int, int]] = []
    told = []
    for key, series in animation.series.items():
        servo = _servo(key, profile, board, ids, where)
        if animation.values:
            values = np.round(np.clip(series, -1000, 1000)).astype(int)  # (a wild one told)
        else:
            w = widths(servo)
            values = np.array([w.value(us) for us in series.tolist()])
        clipped = np.clip(values, servo.lo, servo.hi)
        if np.any(clipped != values):
            told.append(f"{servo.name} goes to {values.min()}..{values.max()}, beyond its "
                        f"range {servo.lo}..{servo.hi}: brought within it")
        out += [(t, servo.id, int(v)) for t, v in zip(animation.times.tolist(),
                                                        clipped.tolist(), strict=True)]
    out.sort(key=lambda s: s[0])
    return out, told


def _servo(key: int | str, profile: Profile, board: Board | None,
           ids: Mapping[int, str] | None, where: str) -> Servo:
    """The servo an ID (or a CSV column's name) means."""
    if isinstance(key, str):
        if key not in profile.names:
            raise GestError(Diagnostic("error", f"{where}: column '{key}' is no servo of "
                                       f"profile '{profile.name}'",
                                       hint=did_you_mean(key, profile.names)))
        return profile.servos[profile.index(key)]
    if ids is not None:
        if key not in ids:
            raise GestError(Diagnostic("error", f"{where}: servo ID {key} is not in the map",
                                       hint=f'add {key} = "SERVO" to its [ids]'))
        return profile.servos[profile.index(ids[key])]
    on = [profile.servos[profile.index(n)] for n in board.servos] if board else []
    for servo in on:
        if place(servo) == key:
            return servo
    known = ", ".join(f"{place(s)} ({s.name})" for s in on)
    raise GestError(Diagnostic("error", f"{where}: servo ID {key} is no servo of board "
                               f"{board.id if board else '?'}: its places are {known}",
                               hint="map the animation's IDs to servos: --map ids.toml "
                               "with [ids] 0 = \"index\""))
