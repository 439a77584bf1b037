"""The library kept between lookups: read once per process, and again only when one of
its files changes (told by ``os.stat``, not by parsing); ``Catalog``, what a program's
hints ask of it (``Program.in_library``)."""

from __future__ import annotations

import os
import threading
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType

from ..errors import GestError
from . import library
from .library import Entry, Library

KEPT = 8  #: search paths kept at once (an editor's settings may name a few)

Stamp = tuple[tuple[object, ...], ...]
_kept: dict[tuple[str, ...], tuple[Stamp, Library | GestError]] = {}
_lock = threading.Lock()


def scanned(dirs: Sequence[str | os.PathLike] | None = None) -> Library:
    """The library along ``dirs`` (the search path when None) as ``library.scan`` reads
    it, read again only when one of its .gest files is added, removed or changed: its
    size, its times or its inode (a change within the file system's clock tick that
    keeps the size is not seen). A library that is an error (a name defined twice in
    one directory) is that error each time it is asked."""
    paths = [Path(d) for d in (library.library_dirs() if dirs is None else dirs)]
    key = tuple(map(str, paths))
    stamp = _stamp(paths)  # before reading: a change while it reads is read next time
    with _lock:
        kept = _kept.get(key)
    if kept is None or kept[0] != stamp:
        try:
            found: Library | GestError = library.scan(paths)
        except GestError as exc:
            found = exc
        kept = (stamp, found)
        with _lock:
            _kept.pop(key, None)
            while len(_kept) >= KEPT:
                del _kept[next(iter(_kept))]
            _kept[key] = kept
    if isinstance(kept[1], GestError):
        raise GestError(kept[1].diagnostics)
    return kept[1]


def _stamp(dirs: Sequence[Path]) -> Stamp:
    """What a change to the library changes: each directory's .gest files (any case,
    hidden ones too: more than ``library_files`` reads is only read again more often),
    each one's size, times and inode (a link's target's)."""
    out: list[tuple[object, ...]] = []
    for d in dirs:
        try:
            with os.scandir(d) as found:
                names = sorted(e.name for e in found if e.name.lower().endswith(".gest"))
        except OSError:
            out.append((str(d),))
            continue
        for name in names:
            try:
                st = os.stat(os.path.join(d, name))
            except OSError:
                out.append((str(d), name))
                continue
            out.append((str(d), name, st.st_size, st.st_mtime_ns, st.st_ctime_ns,
                        st.st_ino))
    return tuple(out)


@dataclass(frozen=True)
class Catalog:
    """The library along one search path, as a compile's hints ask it
    (``names.NameTable.hint``): the file that defines a gesture, every gesture's name."""

    dirs: tuple[str, ...]

    def __call__(self, name: str) -> str | None:
        """The file that defines gesture ``name`` (its file name, as a ``use`` line
        gives it), or None."""
        entry = self.entries().get(name)
        return entry.path.name if entry is not None else None

    def entries(self) -> Mapping[str, Entry]:
        """Every gesture of the library -> its Entry (none when the path is empty)."""
        if not self.dirs:
            return MappingProxyType({})
        return MappingProxyType(scanned(self.dirs).entries)
