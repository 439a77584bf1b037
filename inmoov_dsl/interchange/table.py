"""A gesture as a CSV table (pure): ``time`` in s, then a column a servo, named as in the
profile, each the whole value (command degrees) the plan gives the servo at that moment,
rounded as a rig's encoder rounds it (``frames``: the plan, not the link's delay)."""

from __future__ import annotations

import csv
import io
import math

import numpy as np

from ..boards.rig.encode import round_values
from ..compiling.plan import Plan
from ..errors import Diagnostic, GestError

MAX_ROWS = 1_000_000  #: rows read at most


def write(plan: Plan, rate: float) -> str:
    """A row every 1 / ``rate`` s from 0 to the first at or after the gesture's end."""
    times = np.arange(int(math.ceil(plan.duration * rate - 1e-9)) + 1) / rate
    held = np.stack([round_values(t.position(times)) for t in plan.tracks], axis=1)
    lines = [",".join(["time", *(s.name for s in plan.profile.servos)])]
    lines += [",".join([f"{t:.3f}", *map(str, row)]) for t, row in
              zip(times.tolist(), held.tolist(), strict=True)]
    return "\n".join(lines) + "\n"


def read(text: str, where: str) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """(times, servo name -> values) of such a table; a row that is not numbers, or
    times that go back, is an error at its line."""
    rows = csv.reader(io.StringIO(text))
    header = next(rows, None)
    if not header or header[0].strip() != "time" or len(header) < 2:
        raise GestError(Diagnostic("error", f"{where}:1: a CSV of ours begins 'time,' and "
                                   "a servo's name a column", hint="time,index,middle"))
    names = [h.strip() for h in header[1:]]
    data = []
    for n, row in enumerate(rows, 2):
        if not row:
            continue
        if len(data) >= MAX_ROWS or len(row) != len(header):
            raise GestError(Diagnostic("error", f"{where}:{n}: {len(row)} fields, the "
                                       f"header has {len(header)}" if len(data) < MAX_ROWS
                                       else f"{where}:{n}: more than {MAX_ROWS:,} rows"))
        try:
            numbers = [float(x) for x in row]
        except ValueError:
            raise GestError(Diagnostic("error", f"{where}:{n}: not numbers: "
                                       f"{','.join(row)[:80]!r}")) from None
        if not all(math.isfinite(x) for x in numbers) or \
                (data and numbers[0] < data[-1][0]):
            raise GestError(Diagnostic("error", f"{where}:{n}: times go forward and "
                                       "every value is a number"))
        data.append(numbers)
    if not data:
        raise GestError(Diagnostic("error", f"{where}: the table has no rows"))
    array = np.asarray(data)
    return array[:, 0] - array[0, 0], {name: array[:, k + 1] for k, name in enumerate(names)}
