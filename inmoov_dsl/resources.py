"""Where the grammar, the gesture library and the profiles are, installed or not, and
where this user's caches and state may be kept."""

from __future__ import annotations

import os
import stat
from pathlib import Path

_PACKAGE = Path(__file__).resolve().parent


def data_dir(name: str) -> Path:
    """The shipped directory ``name`` (``grammar``, ``gestures``, ``firmware`` or ``ros``).

    A wheel carries them in ``inmoov_dsl/_data``; a source checkout (or an editable
    install) has them at the top of the repository.
    """
    for candidate in (_PACKAGE / "_data" / name, _PACKAGE.parent / name):
        if candidate.is_dir():
            return candidate
    raise FileNotFoundError(f"inmoov-dsl is installed without its {name}/ directory")


def grammar_path() -> Path:
    """The grammar of the gesture language (``gest.lark``)."""
    return data_dir("grammar") / "gest.lark"


def library_dir() -> Path:
    """The shipped gesture library."""
    return data_dir("gestures")


def profiles_dir() -> Path:
    """The shipped robot profiles (``*.toml``)."""
    return library_dir() / "profiles"


CACHE_ENV = "INMOOV_DSL_CACHE"  #: a directory to keep caches in instead of the default


def private_cache_dir() -> Path | None:
    """A directory for this user's caches that no one else can write: ``$INMOOV_DSL_CACHE``,
    or ``inmoov-dsl`` in the user's cache directory (``$XDG_CACHE_HOME`` or ``~/.cache``;
    ``%LOCALAPPDATA%`` on Windows); see ``_private``."""
    return _private(CACHE_ENV, "XDG_CACHE_HOME", ".cache", "")


STATE_ENV = "INMOOV_DSL_STATE"  #: a directory to keep state in instead of the default


def private_state_dir() -> Path | None:
    """A directory for what this user's tools remember between runs (the virtual boards'
    memory), that no one else can write: ``$INMOOV_DSL_STATE``, or ``inmoov-dsl`` in the
    user's state directory (``$XDG_STATE_HOME`` or ``~/.local/state``; ``state`` in
    ``%LOCALAPPDATA%\\inmoov-dsl`` on Windows); see ``_private``."""
    return _private(STATE_ENV, "XDG_STATE_HOME", ".local/state", "state")


def _private(env: str, xdg: str, home: str, windows: str) -> Path | None:
    """``$env``, or ``inmoov-dsl`` in ``$xdg`` or ``~/home`` (``inmoov-dsl/windows`` in
    ``%LOCALAPPDATA%`` on Windows), created with mode 0700. On POSIX it must be a real
    directory (not a symlink), owned by this user, that neither group nor others can
    write; None when it is not (then nothing is kept there)."""
    base = os.environ.get(env)
    if base:
        path = Path(base)
    elif os.name == "nt":
        path = Path(os.environ.get("LOCALAPPDATA") or Path.home() / "AppData" / "Local")
        path = path / "inmoov-dsl" / windows if windows else path / "inmoov-dsl"
    else:
        path = Path(os.environ.get(xdg) or Path.home() / home) / "inmoov-dsl"
    try:
        path.mkdir(mode=0o700, parents=True, exist_ok=True)
        if os.name == "nt":
            return path if path.is_dir() else None
        st = os.lstat(path)
    except (OSError, RuntimeError):  # RuntimeError: no home directory
        return None
    if not stat.S_ISDIR(st.st_mode) or st.st_uid != os.getuid() or st.st_mode & 0o022:
        return None
    return path


def private_file(path: Path) -> bool:
    """May ``path`` (in a private_cache_dir) be trusted: absent, or a regular file of
    this user's that no one else can write?"""
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        return True
    except OSError:
        return False
    if not stat.S_ISREG(st.st_mode):
        return False
    return os.name == "nt" or (st.st_uid == os.getuid() and not st.st_mode & 0o022)


class FolderGiven(ValueError):
    """A folder where a file was to be read (``read_regular``), said as plainly as
    that: ``it is a folder, not a file``."""

    def __init__(self, path: str | os.PathLike):
        super().__init__("it is a folder, not a file")
        self.path = os.fspath(path)


def files_in(folder: str | os.PathLike, suffix: str, most: int = 3) -> list[str]:
    """Up to ``most`` of the files in ``folder`` whose names end in ``suffix``, sorted,
    each as a path through ``folder`` (what to give instead of the folder)."""
    try:
        names = sorted(e.name for e in os.scandir(folder)
                       if e.name.endswith(suffix) and e.is_file())
    except OSError:
        return []
    return [os.path.join(os.fspath(folder), n) for n in names[:most]]


def read_regular(path: str | os.PathLike, limit: int) -> bytes:
    """At most ``limit + 1`` bytes of the regular file ``path`` (one more than the limit
    tells the caller it is too large). A folder is a FolderGiven, anything else that is
    not a file (a FIFO, a device) a ValueError; opening does not wait for a FIFO's
    writer."""
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0)
    try:
        fd = os.open(path, flags)
    except PermissionError:  # Windows opens no folder
        if os.path.isdir(path):
            raise FolderGiven(path) from None
        raise
    if stat.S_ISDIR(os.fstat(fd).st_mode):
        os.close(fd)
        raise FolderGiven(path)
    with open(fd, "rb") as f:
        if not stat.S_ISREG(os.fstat(f.fileno()).st_mode):
            raise ValueError("not a regular file")
        return f.read(limit + 1)
