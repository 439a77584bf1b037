"""Bad input: seeded mutants of the library's .gest files, of the built-in profiles and of
compiled gestures (tests/mutate.py), each run as ``gestc check``, ``load_profile`` and
the player would, within a time bound; then how ``gestc check`` scales with the number
of gestures in one file, up to a 10 MB file.

Target: no exception but GestError (each at ``file:line:col``), no input over the bound,
``check`` linear in the file, a 10 MB file checked in under a minute or refused at once.

    python benchmarks/fuzz.py [--seed 1] [--count 20000] [--limit 5] [--kinds gest toml gestc]
    python benchmarks/fuzz.py --count 0        # the scaling only

One process at a time: the mutants run in this one, each ``gestc check`` of the
scaling in a child of its own (for its peak memory).
"""

from __future__ import annotations

import argparse
import collections
import random
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from common import ROOT

sys.path.insert(0, str(ROOT / "tests"))

from mutate import KINDS, attempt, mutate, seeds  # noqa: E402

SIZES = (1_000, 8_000, 20_000, 200_000)  #: one-line gestures per file


def fuzz(kind: str, count: int, seed: int, limit: float, pool) -> None:
    statuses: collections.Counter = collections.Counter()
    slowest = (0.0, "")
    examples: dict[str, str] = {}
    t0 = time.perf_counter()
    for n in range(count):
        rng = random.Random(f"{seed}:{kind}:{n}")
        source = rng.choice(pool)
        data = mutate(source.data, rng, kind)
        outcome = attempt(source, data, limit)
        statuses[outcome.status] += 1
        if outcome.seconds > slowest[0]:
            slowest = (outcome.seconds, f"mutant {n} of {Path(source.name).name}, "
                       f"{len(data):,} bytes, {outcome.status}"
                       + (f": {outcome.detail[:80]}" if outcome.detail else ""))
        if outcome.status not in ("accepted", "refused"):
            examples.setdefault(outcome.status, f"mutant {n} of {source.name}: "
                                f"{outcome.detail[:200]}")
    total = time.perf_counter() - t0
    bad = statuses["uncaught"] + statuses["bad-error"]
    print(f"| {kind} | {count:,} | {statuses['accepted']:,} | {statuses['refused']:,} | "
          f"{bad:,} | {statuses['hang']:,} | {slowest[0] * 1000:,.0f} ms ({slowest[1]}) | "
          f"{total:,.0f} s |", flush=True)
    for status, example in examples.items():
        print(f"|   {status}: {example} |", flush=True)


# the peak of this process's own memory: VmHWM (Linux), which starts again at exec;
# ru_maxrss would count the parent's size at the fork
CHILD = """
import re, resource, sys, time
from inmoov_dsl.cli import gestc
t0 = time.perf_counter()
code = gestc.main(["check", sys.argv[1]])
seconds = time.perf_counter() - t0
try:
    with open("/proc/self/status") as f:
        peak = int(re.search(r"VmHWM:\\s*(\\d+)", f.read())[1])
except OSError:
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
print(seconds, peak, code, file=sys.stderr)
"""


def one_line_gestures(count: int) -> str:
    """``count`` gestures of 51 bytes each: 200,000 make a 10 MB file."""
    return "".join(f"g{i:06d}: index {i % 181:3d}, middle {7 * i % 181:3d}, ring 90 over "
                   f"0.5s\n" for i in range(count))


def check(path: Path) -> tuple[float, float, int, str]:
    """(seconds in gestc check, peak RSS in MB, exit status, first message) of a child
    process checking ``path``."""
    done = subprocess.run([sys.executable, "-c", CHILD, str(path)], capture_output=True,
                          text=True, timeout=900, cwd=ROOT)
    *messages, last = done.stderr.strip().splitlines()
    seconds, rss, code = last.split()
    first = next((m for m in messages if ": error: " in m), "")
    return float(seconds), int(rss) / 1024, int(code), first


def scaling() -> None:
    print("| file | size | gestc check | per gesture | peak memory | result |")
    print("|---|---:|---:|---:|---:|---|")
    with tempfile.TemporaryDirectory() as tmp:
        files = [(f"{n:,} one-line gestures", n, one_line_gestures(n)) for n in SIZES]
        files.append(("one line of 1.7 MB", 1, "g: " + "index 9, " * 190_000 + "index 9\n"))
        for label, n, text in files:
            path = Path(tmp) / "big.gest"
            path.write_text(text, encoding="utf-8")
            seconds, rss, code, first = check(path)
            result = "ok" if code == 0 else f"refused: {first.split(': error: ')[-1][:70]}"
            per = f"{seconds / n * 1000:.2f} ms" if code == 0 else "-"
            print(f"| {label} | {len(text.encode()) / 1e6:,.2f} MB | {seconds:,.2f} s | "
                  f"{per} | {rss:,.0f} MB | {result} |", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--count", type=int, default=20_000, help="mutants per kind")
    ap.add_argument("--limit", type=float, default=5.0, help="seconds an input may take")
    ap.add_argument("--kinds", nargs="+", choices=KINDS, default=list(KINDS))
    ap.add_argument("--no-scaling", action="store_true")
    args = ap.parse_args()
    if args.count:
        pools = seeds()
        print(f"seed {args.seed}, {args.count:,} mutants per kind, {args.limit:g} s per input")
        print()
        print("| kind | mutants | accepted | refused (GestError) | uncaught or misplaced | "
              "over the bound | slowest | total |")
        print("|---|---:|---:|---:|---:|---:|---|---:|")
        for kind in args.kinds:
            fuzz(kind, args.count, args.seed, args.limit, pools[kind])
        print()
    if not args.no_scaling:
        scaling()


if __name__ == "__main__":
    main()
