"""Nothing from outside runs code: the parser's cache is never read from a place others
can write (Lark unpickles it)."""

from __future__ import annotations

import os
import pickle
import subprocess
import sys
from pathlib import Path

import pytest

POSIX = pytest.mark.skipif(os.name != "posix", reason="file modes and owners are POSIX")
ROOT = Path(__file__).resolve().parent.parent


class Planted:
    """A pickle that, when loaded, creates the file ``marker``."""

    def __init__(self, marker: Path):
        self.marker = marker

    def __reduce__(self):
        return (Path.touch, (self.marker,))


def plant(path: Path, marker: Path) -> None:
    """Overwrite Lark's cache file ``path`` so that reading it runs code."""
    first = path.read_bytes().split(b"\n", 1)[0] if path.exists() else b"0"
    path.write_bytes(first + b"\n" + pickle.dumps(Planted(marker)))


def gestc_check(env: dict[str, str]) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "inmoov_dsl.cli.gestc", "check",
                           str(ROOT / "gestures" / "count.gest")],
                          capture_output=True, text=True, timeout=120,
                          env={**os.environ, **env})


@POSIX
def test_a_pickle_planted_where_lark_kept_its_cache_is_not_read(tmp_path):
    shared = tmp_path / "tmp"
    shared.mkdir()
    # the file Lark's own cache=True would use in this temp dir: made by Lark itself
    make_old_cache = (
        "from inmoov_dsl.language import parse\n"
        "parse.Lark(parse.grammar_path().read_text(encoding='utf-8'), parser='lalr', "
        "lexer='contextual', postlex=parse.GestIndenter(), maybe_placeholders=False, "
        "transformer=parse.TO_AST, cache=True)\n")
    subprocess.run([sys.executable, "-c", make_old_cache], check=True, timeout=120,
                   env={**os.environ, "TMPDIR": str(shared)})
    (old,) = shared.glob(".lark_cache_*")
    marker = tmp_path / "ran"
    plant(old, marker)
    done = gestc_check({"TMPDIR": str(shared), "INMOOV_DSL_CACHE": str(tmp_path / "mine")})
    assert done.returncode == 0, done.stderr
    assert not marker.exists()
    assert list(shared.glob(".lark_cache_*")) == [old]  # nothing new in the shared place


@POSIX
def test_the_private_cache_is_used_only_when_no_one_else_can_write_it(tmp_path):
    mine = tmp_path / "mine"
    env = {"INMOOV_DSL_CACHE": str(mine)}
    assert gestc_check(env).returncode == 0
    (cache,) = mine.glob("gest-grammar-*.lark")
    assert (mine.stat().st_mode & 0o777) == 0o700
    marker = tmp_path / "ran"
    plant(cache, marker)
    mine.chmod(0o777)  # others could have put it there: not read
    assert gestc_check(env).returncode == 0 and not marker.exists()
    mine.chmod(0o700)
    cache.chmod(0o666)  # a file others can write: not read
    assert gestc_check(env).returncode == 0 and not marker.exists()
    cache.unlink()
    os.symlink(tmp_path / "elsewhere", cache)  # a link: not followed
    assert gestc_check(env).returncode == 0 and not marker.exists()
    assert not (tmp_path / "elsewhere").exists()


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="FIFOs are POSIX")
def test_a_fifo_given_as_a_compiled_file_is_refused_without_waiting(tmp_path, capsys):
    from inmoov_dsl.cli import gestplay

    fifo = tmp_path / "x.gestc"
    os.mkfifo(fifo)  # opened for reading, it would wait for a writer forever
    assert gestplay.main([str(fifo), "--dry-run"]) == 1
    assert capsys.readouterr().err == f"gestplay: error: cannot read '{fifo}': not a " \
                                      "regular file\n"
