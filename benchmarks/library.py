"""In-process compile time of the whole gesture library (target < 50 ms).

The parser is built once per process (as in any long-lived use); we time compiling
every gesture of every library file, parse to streams.

    python benchmarks/library.py
"""

from __future__ import annotations

from common import best_and_median

from inmoov_dsl import load_library, load_profile
from inmoov_dsl.compiler import compile_program, load
from inmoov_dsl.parse import parser


def compile_library(profile) -> int:
    count = 0
    for name, path in load_library().items():
        compile_program(load(str(path)), name, profile)
        count += 1
    return count


def main() -> None:
    profile = load_profile("rhand")
    parser()  # built once per process
    count = compile_library(profile)
    best, median = best_and_median(lambda: compile_library(profile), 20)
    print(f"library: {count} gestures, compiled in {best * 1000:.1f} ms best, "
          f"{median * 1000:.1f} ms median of 20 (target < 50 ms)")


if __name__ == "__main__":
    main()
