"""``gestc check`` of a file full of unknown calls, with the real CLI (a subprocess each):
one unknown call, 250 and 1,000, each a name of its own (``nope0``, ``nope1``...).

Each unknown name gets its hint in ``names.NameTable.hint``: the built-in profile that
has it, the library file that defines it, or the closest name. The library was read
again for each name (``library.scan``: every file parsed, ~30 ms a name); it is read once
per process now (``language/catalog.py``), and again only when one of its files changes
(an ``os.stat`` of each, ~0.2 ms a name); the built-in profiles, asked for each name too,
are read again only when one changes.

Measured 2026-11-29 on the shared two-core machine, the code before (its commit's tree)
and after, interleaved in one run, medians of 5; the machine was busy (load 4 to 9: one
unknown call takes 0.5 s when it is quiet):

| code | 1 unknown call | 250 | 1,000 |
|---|---|---|---|
| before | 1.13 s | 17.87 s | 59.43 s |
| after | 1.16 s | 1.69 s | 3.14 s |

Earlier the same day, quieter, the code before alone (medians of 3): 0.49 s, 7.42 s,
28.79 s.

    python benchmarks/unknown_names.py [TREE ...]

TREE: another source tree to measure beside this one, interleaved (the code before:
``git archive HEAD~1 inmoov_dsl gestures grammar | tar -x -C /tmp/before``).
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from common import ROOT

RUNS = 5
COUNTS = (1, 250, 1000)
ENV = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}


def unknown_calls(count: int) -> str:
    """A gesture file for the right hand whose one gesture calls ``count`` names that
    nothing defines, a name a line."""
    lines = ["robot rhand", "", "big:", *(f"    nope{i}" for i in range(count))]
    return "\n".join(lines) + "\n"


def checked(path: Path, count: int, tree: str) -> float:
    """Seconds ``gestc check path`` takes, the package of source tree ``tree`` run in
    ``path``'s folder; it must tell ``count`` unknown names."""
    t0 = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestc", "check",
                           path.name], capture_output=True, text=True, cwd=path.parent,
                          env={**ENV, "PYTHONPATH": tree})
    took = time.perf_counter() - t0
    told = done.stderr.count(": error: unknown ")
    if done.returncode != 1 or told != count:
        raise SystemExit(f"gestc check told {told} unknown names of {count} "
                         f"(exit {done.returncode}):\n{done.stderr[-2000:]}")
    return took


def main() -> None:
    trees = [str(ROOT), *sys.argv[1:]]  # this tree, then any other given
    folder = Path(tempfile.mkdtemp())
    files = {}
    for count in COUNTS:
        files[count] = folder / f"unknown{count}.gest"
        files[count].write_text(unknown_calls(count))
    times: dict[tuple[str, int], list[float]] = {}
    for tree in trees:
        checked(files[1], 1, tree)  # warm the caches (bytecode, Lark's grammar)
    for _ in range(RUNS):  # interleaved: a machine busier for a while slows them all
        for count in COUNTS:
            for tree in trees:
                times.setdefault((tree, count), []).append(checked(files[count], count, tree))
    print(f"| source | {' | '.join(f'{c:,} unknown calls' for c in COUNTS)} |")
    print(f"|---|{'---|' * len(COUNTS)}")
    for tree in trees:
        cells = [f"{statistics.median(times[tree, c]):.2f} s" for c in COUNTS]
        print(f"| {tree} | {' | '.join(cells)} |")
    print(f"\nmedians of {RUNS}, interleaved")


if __name__ == "__main__":
    main()
