"""gestc list: the library's gestures, where each is defined, and the profile it needs."""

from __future__ import annotations

import argparse
import re
import shutil
import sys
import textwrap
from pathlib import Path

from ...errors import GestError
from ...language.library import Entry, comments_above, library_dirs, scan
from ...language.load import load
from ...language.program import Program
from ...profiles.profile import load_profile
from ..common import EXIT_OK, add_lib, report
from .target import PROG


def run(args: argparse.Namespace) -> int:
    """``NAME<TAB>FILE<TAB>PROFILE`` per gesture (a gesture further down the search path
    that one shadows: a note on stderr), or with -l a table."""
    dirs = library_dirs(args.lib)
    library = scan(dirs)
    report(library.warnings(), PROG)
    entries = sorted(library.entries.values(), key=lambda e: e.name)
    needs = profiles_needed(entries, dirs)
    width = max((len(e.name) for e in entries), default=0)
    wrap = shutil.get_terminal_size().columns if sys.stdout.isatty() else None
    for e in entries:
        if args.long:
            shadows = "".join(f"  (shadows {p})" for p in e.shadows)
            line = (f"{e.name:<{width}}  {summary(e) or '-'}  ({e.path.name}:{e.line}, "
                    f"for {needs[e.name]}){shadows}")
            print(textwrap.fill(line, wrap, subsequent_indent=" " * (width + 2),
                                break_long_words=False, break_on_hyphens=False)
                  if wrap else line)
        else:
            print(f"{e.name}\t{e.path}\t{needs[e.name]}")
    if not args.long:  # the columns stay three: what is shadowed is a note of its own
        for e in entries:
            for path in e.shadows:
                print(f"{PROG}: note: '{e.name}' of {e.path} shadows the one in {path}",
                      file=sys.stderr)
    return EXIT_OK


def summary(entry: Entry) -> str:
    """What ``entry`` does: the first sentence of the comment block above it (over as
    many of its lines as it takes, a leading ``name:`` dropped), else its first line."""
    try:
        lines = entry.path.read_text(encoding="utf-8-sig").splitlines()
    except (OSError, UnicodeDecodeError):
        return entry.description
    top = comments_above(lines, entry.line)
    text = " ".join(row.strip().lstrip("#").strip() for row in lines[top - 1:entry.line - 1])
    text = text.removeprefix(f"{entry.name}:").strip()
    end = re.search(r"[.!?](?=\s|$)", text)
    return text[:end.end()] if end else text or entry.description


def profiles_needed(entries: list[Entry], dirs: list[Path]) -> dict[str, str]:
    """Gesture name -> the built-in profile it is for: rhand (the default) if its names
    are all there, else the first profile that has them all; '-' if none has."""
    from ...compiling.resolve import resolver
    from ...profiles.profile import builtin_profiles

    names = ["rhand", *(n for n in builtin_profiles() if n != "rhand")]
    profiles = [load_profile(n) for n in names]
    programs: dict[Path, Program | None] = {}
    needs: dict[str, str] = {}
    for e in entries:
        if e.path not in programs:
            try:
                programs[e.path] = load(str(e.path), search=dirs)
            except GestError:
                programs[e.path] = None
        needs[e.name] = "-"
        for profile in profiles if programs[e.path] is not None else ():
            try:
                resolver(programs[e.path], profile).gesture(e.name)
            except GestError:
                continue
            needs[e.name] = profile.name
            break
    return needs


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestc list``."""
    p = sub.add_parser("list", help="the library's gestures: NAME<TAB>FILE")
    p.add_argument("-l", "--long", action="store_true",
                   help="a table: name, what the gesture does, where it is defined")
    add_lib(p)
    p.set_defaults(func=run)
