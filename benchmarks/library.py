"""In-process compile time of the whole gesture library (target < 50 ms).

The parser is built once per process (as in any long-lived use); we time loading every
library file (parsing it and what it imports) and compiling each of its gestures to
streams on its profile (the hand gestures on rhand, the whole-robot ones on inmoov).

    python benchmarks/library.py
"""

from __future__ import annotations

from common import best_and_median, library_gestures

from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.language.library import library_files
from inmoov_dsl.language.load import load
from inmoov_dsl.language.parse import parser


def compile_library(profiles: dict) -> int:
    """Load every library file once (with what it imports) and compile each of its
    gestures on its profile."""
    count = 0
    for path in library_files():
        program = load(str(path))
        for name in program.own:
            compile_program(program, name, profiles[name])
            count += 1
    return count


def main() -> None:
    parser()  # built once per process
    profiles = {name: profile for name, _, profile in library_gestures()}
    count = compile_library(profiles)
    best, median = best_and_median(lambda: compile_library(profiles), 20)
    print(f"library: {count} gestures, compiled in {best * 1000:.1f} ms best, "
          f"{median * 1000:.1f} ms median of 20 (target < 50 ms)")


if __name__ == "__main__":
    main()
