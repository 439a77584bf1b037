"""The pairs never checked of a user's own profile (model/allowed.py): made once, then
kept in the user's private cache by the model's digest, so the next command reuses
them (seconds saved on every gestc check); a changed model makes them again, and a
corrupt or foreign file in the cache is made again, never a traceback."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from inmoov_dsl.cli import gestc
from inmoov_dsl.model import allowed, collide
from inmoov_dsl.profiles.profile import load_profile

pytest.importorskip("fcl", reason="the [collide] extra brings python-fcl")

INMOOV = Path(load_profile("inmoov").path).read_text(encoding="utf-8")


@pytest.fixture
def builds(monkeypatch, tmp_path) -> list[str]:
    """The names of the profiles whose pairs were made, in a private cache of the test's
    own (the builder samples 200 poses, not 10,000: the same work, quicker)."""
    monkeypatch.setenv("INMOOV_DSL_CACHE", str(tmp_path / "cache"))
    made: list[str] = []
    real = allowed.allowed_pairs

    def counted(profile, samples=allowed.SAMPLES, seed=allowed.SEED, clearance_mm=None):
        made.append(profile.name)
        return real(profile, 200, seed, clearance_mm)
    monkeypatch.setattr(allowed, "allowed_pairs", counted)
    return made


def mine(tmp_path, wrist: str = "125, 160") -> Path:
    """A copy of the inmoov profile saved elsewhere, the right wrist's calibration
    ``wrist`` (the inmoov's: 125, 160)."""
    path = tmp_path / "mine.toml"
    path.write_text(INMOOV.replace('name = "inmoov"', 'name = "mine"', 1)
                    .replace("calibration = [125, 160]", f"calibration = [{wrist}]", 1))
    return path


def check(monkeypatch, tmp_path, profile: Path | str, capsys) -> None:
    """``gestc check`` of a gesture that lifts the right arm, as a new process runs it
    (no checker kept from a command before), and it says the file is fine."""
    monkeypatch.setattr(collide, "_CHECKERS", {})
    gesture = tmp_path / "lift.gest"
    gesture.write_text("lift: r_shoulder 90 over 1s\n")
    assert gestc.main(["check", "--profile", str(profile), str(gesture)]) == 0
    assert capsys.readouterr().out.startswith(f"{gesture}: ok")


def kept(tmp_path) -> list[Path]:
    """The files of the cache's pairs."""
    return sorted((tmp_path / "cache" / allowed.CACHE).glob("*" + allowed.SUFFIX))


def test_a_second_check_reuses_the_pairs_the_first_made(builds, monkeypatch, tmp_path,
                                                        capsys):
    profile = mine(tmp_path, "120, 160")
    check(monkeypatch, tmp_path, profile, capsys)
    assert builds == ["mine"]
    (file,) = kept(tmp_path)
    assert file.name.startswith(allowed.digest(load_profile(str(profile))))
    check(monkeypatch, tmp_path, profile, capsys)
    assert builds == ["mine"]  # not made again


def test_a_changed_model_makes_them_again_and_each_is_kept(builds, monkeypatch, tmp_path,
                                                           capsys):
    profile = mine(tmp_path, "120, 160")
    check(monkeypatch, tmp_path, profile, capsys)
    mine(tmp_path, "110, 160")  # the wrist turns further: another model
    check(monkeypatch, tmp_path, profile, capsys)
    assert builds == ["mine", "mine"] and len(kept(tmp_path)) == 2
    mine(tmp_path, "120, 160")  # back: its pairs are still kept
    check(monkeypatch, tmp_path, profile, capsys)
    assert builds == ["mine", "mine"]


def test_a_profile_with_its_pairs_beside_it_makes_none(builds, monkeypatch, tmp_path,
                                                        capsys):
    check(monkeypatch, tmp_path, "inmoov", capsys)  # the shipped inmoov.collisions.json
    profile = mine(tmp_path)  # the inmoov's model: the same pairs, kept beside it
    allowed.save(allowed.load(allowed.path_for(load_profile("inmoov"))),
                 allowed.path_for(load_profile(str(profile))))
    check(monkeypatch, tmp_path, profile, capsys)
    assert builds == [] and kept(tmp_path) == []


def foreign(file: Path) -> None:
    """Another model's pairs (the shipped inmoov's) where this model's were kept."""
    file.write_text(allowed.path_for(load_profile("inmoov")).read_text(encoding="utf-8"))


def writable(file: Path) -> None:
    """The right pairs, in a file anyone may write."""
    file.chmod(0o666)


def pairs_of_nothing(file: Path) -> None:
    """This model's file, its pairs not pairs."""
    data = json.loads(file.read_text(encoding="utf-8"))
    file.write_text(json.dumps({**data, "allowed": ["abc", 3]}))


def a_folder(file: Path) -> None:
    """A folder where the file was."""
    file.unlink()
    file.mkdir()


SPOILED = {"not JSON": lambda file: file.write_bytes(b"\x00garbage{"),
           "not its keys": lambda file: file.write_text("[1, 2]"),
           "pairs of nothing": pairs_of_nothing, "another model's": foreign,
           "anyone may write it": writable, "a folder": a_folder}


@pytest.mark.parametrize("spoil", SPOILED.values(), ids=SPOILED)
def test_a_corrupt_or_foreign_cache_file_is_made_again(builds, monkeypatch, tmp_path, capsys,
                                                       spoil):
    profile = mine(tmp_path, "120, 160")
    check(monkeypatch, tmp_path, profile, capsys)
    (file,) = kept(tmp_path)
    spoil(file)
    check(monkeypatch, tmp_path, profile, capsys)  # no traceback: made again
    assert builds == ["mine", "mine"]
    if file.is_file():  # and kept again, for the next command
        check(monkeypatch, tmp_path, profile, capsys)
        assert builds == ["mine", "mine"]


def test_the_cache_keeps_the_models_used_last(builds, monkeypatch, tmp_path, capsys):
    """A profile edited again and again does not fill the disk: the cache keeps the
    pairs of the KEPT models used last, the one used again among them."""
    monkeypatch.setattr(allowed, "KEPT", 2)
    profile = tmp_path / "mine.toml"
    for wrist in ("120, 160", "110, 160", "120, 160", "100, 160"):
        mine(tmp_path, wrist)
        check(monkeypatch, tmp_path, profile, capsys)
    assert len(builds) == 3 and len(kept(tmp_path)) == 2
    mine(tmp_path, "120, 160")  # used third: kept
    check(monkeypatch, tmp_path, profile, capsys)
    assert len(builds) == 3
