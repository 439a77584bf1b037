"""A gesture on the other side of the robot (pure): ``left peace``, ``gestplay peace
--hand left``. A profile's ``[sides]`` pairs each servo of its right side with its
mirror image on the left; playing a gesture on one side moves each servo of the other
side to its partner, with the same value (the boards turn the left side's servos the
other way, so the same value is the mirror image)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import NoReturn

from ..hardware import Profile
from .actions import Action


def onto(profile: Profile, side: str) -> dict[int, int]:
    """Servo index -> its partner's, for the servos of the side opposite ``side``;
    empty when the profile has no ``[sides]``."""
    if not profile.sides:
        return {}
    other = "right" if side == "left" else "left"
    return {profile.index(a): profile.index(b)
            for a, b in zip(profile.sides[other], profile.sides[side], strict=True)}


def moved(actions: Sequence[Action], partner: dict[int, int]
          ) -> tuple[list[Action], list[int]]:
    """``actions`` with each servo replaced by its ``partner`` (when it has one), in
    their branches too, and the servos that a step would then set twice."""
    clashes: list[int] = []

    def move(action: Action) -> Action:
        targets: dict[int, int] = {}
        for i, v in action.targets:
            j = partner.get(i, i)
            if j in targets:
                clashes.append(j)
            targets[j] = v
        branches = tuple(tuple(move(a) for a in branch) for branch in action.branches)
        aims = tuple(_mirrored(aim, partner) for aim in action.aims)
        return replace(action, targets=tuple(targets.items()), branches=branches, aims=aims)

    return [move(a) for a in actions], clashes


def _mirrored(aim, partner: dict[int, int]):
    """A hand's place on the other side (its servos' partners): the mirror image of the
    place (y to -y); the gaze's place as it is, as the head's values are."""
    if not any(i in partner for i in aim.servos):
        return aim
    other = {"right": "left", "left": "right"}.get(aim.what, aim.what)
    x, y, z = aim.xyz
    return replace(aim, what=other, xyz=(x, -y, z),
                   place=aim.place and f"the mirror image of {aim.place}",
                   servos=tuple(partner.get(i, i) for i in aim.servos))


def to_side(steps: list[Action], profile: Profile, side: str, name: str,
            fail: Callable[[str, str], NoReturn]) -> list[Action]:
    """Gesture ``name``'s ``steps`` played on ``side``; ``fail(message, hint)`` where they
    cannot be (a profile without ``[sides]``, a step that would set a servo twice)."""
    partner = onto(profile, side)
    if not partner:
        fail(f"profile '{profile.name}' has no [sides]: it cannot play '{name}' on the "
             f"{side}", "a robot profile pairs its sides in [sides]; a hand alone has its "
             "own profile (--profile lhand)")
    moved_steps, clashes = moved(steps, partner)
    if clashes:
        servo = profile.servos[clashes[0]].name
        fail(f"on the {side}, '{name}' would set '{servo}' twice in one step: it moves "
             f"both sides", f"play '{name}' as it is")
    return moved_steps
