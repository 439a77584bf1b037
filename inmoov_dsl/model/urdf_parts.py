"""The InMoov's body as simple shapes (pure data): every link of the model and the joint
that carries it, sized like the printed parts. InMoov's own meshes are under a licence
we cannot ship, so each part is a box, a cylinder or a sphere.

Frames: the robot stands at ``base_link`` with x forward, y to its left and z up. A hand
is built in its own frame, its forearm's: fingers along +z from the wrist, the palm
facing -y, the right hand's thumb on the +x side; the left hand is its mirror image.
Joints turning the way a person would call positive: a finger curls, an arm rises.
Joint names are the original model's for the hands (``right_palm_to_index``); the rest
are the servos' names of the ``inmoov`` profile. A finger's phalanges follow its first
joint (``mimic``), as the tendon curls the whole finger.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

Vec = tuple[float, float, float]

IVORY = "ivory"  #: printed parts
GREY = "grey"  #: the forearm and the body's frame
DARK = "dark"  #: eyes and joints' housings
COLOURS = {IVORY: (0.93, 0.9, 0.8, 1.0), GREY: (0.55, 0.58, 0.62, 1.0),
           DARK: (0.15, 0.15, 0.17, 1.0)}


@dataclass(frozen=True)
class Shape:
    """A link's look: ``box`` (size x y z), ``cylinder`` (radius, length along z) or
    ``sphere`` (radius), centred at ``xyz`` in the link's frame."""

    kind: str
    size: tuple[float, ...]
    xyz: Vec = (0.0, 0.0, 0.0)
    colour: str = IVORY


@dataclass(frozen=True)
class Part:
    """A link and the joint from ``parent`` that carries it. ``axis`` None: the joint is
    fixed. ``mimic``: (joint, multiplier) that this joint follows."""

    joint: str
    parent: str
    link: str
    shape: Shape | None
    xyz: Vec = (0.0, 0.0, 0.0)
    rpy: Vec = (0.0, 0.0, 0.0)
    axis: Vec | None = None
    mimic: tuple[str, float] | None = None


#: finger: (x of its base on the palm, phalanx lengths, radius); the second and third
#: phalanx of a finger turn 90 and 60 degrees at full curl, the thumb's THUMB_CURL
FINGERS = {
    "index": (0.028, (0.045, 0.028, 0.024), 0.0085),
    "medius": (0.009, (0.050, 0.031, 0.025), 0.009),
    "ring": (-0.010, (0.046, 0.029, 0.024), 0.0085),
    "pinky": (-0.028, (0.036, 0.022, 0.020), 0.0075),
}
THUMB = ((0.045, 0.033, 0.027), 0.0095)
THUMB_CURL = (45.0, 35.0)
PALM = (0.084, 0.032, 0.095)  #: width (x), thickness (y), length (z)
FOREARM = (0.035, 0.25)  #: radius, length
WRIST_GAP = 0.01


def finger(side: str, name: str, base: Vec, rpy: Vec, lengths: tuple[float, ...],
           radius: float, axis: Vec, travel: float, curl: tuple[float, float] = (90, 60),
           bend: Vec = (1, 0, 0)) -> list[Part]:
    """A finger's three phalanges from the palm: the first turns about ``axis``, the
    others bend about ``bend``; ``travel``: the first joint's full travel in degrees,
    which the other two follow to their own full ``curl``."""
    parts = []
    parent, joint = f"{side}_palm", f"{side}_palm_to_{name}"
    for k, length in enumerate(lengths, start=1):
        link = f"{side}_{name}_{k}"
        follow = {2: curl[0], 3: curl[1]}.get(k)
        mimic = (f"{side}_palm_to_{name}", follow / travel) if follow and travel else None
        shape = Shape("cylinder", (radius, length), (0, 0, length / 2))
        xyz = base if k == 1 else (0.0, 0.0, lengths[k - 2])
        parts.append(Part(joint, parent, link, shape, xyz, rpy if k == 1 else (0, 0, 0),
                          axis if k == 1 else bend, mimic))
        parent, joint = link, f"{side}_{name}_{k}_to_{k + 1}"
    return parts


def hand(travel: dict[str, float]) -> list[Part]:
    """The right hand from its forearm: the wrist turns the palm about the forearm, each
    finger curls towards the palm. ``travel``: each finger joint's full travel, degrees
    (from the profile's calibration: the curl of the phalanges follows it)."""
    radius, length = FOREARM
    palm_z = length + WRIST_GAP
    parts = [Part("right_arm_to_wrist", "right_forearm", "right_palm",
                  Shape("box", PALM, (0, 0, PALM[2] / 2)), (0, 0, palm_z), axis=(0, 0, 1))]
    for name, (x, lengths, r) in FINGERS.items():
        parts += finger("right", name, (x, 0.0, PALM[2]), (0, 0, 0), lengths, r, (1, 0, 0),
                        travel.get(f"right_palm_to_{name}", 90.0))
    lengths, r = THUMB
    # the thumb swings across the front of the palm (about the palm's length), its
    # phalanges curling over the fingers
    tilt = 0.45
    parts += finger("right", "thumb", (PALM[0] / 2 - 0.004, -0.01, 0.025), (0, tilt, 0),
                    lengths, r, (math.sin(tilt), 0, -math.cos(tilt)),
                    travel.get("right_palm_to_thumb", 90.0), THUMB_CURL)
    # the hand's point, where a target puts the hand: the middle of the palm's inner face
    parts.append(Part("right_palm_to_point", "right_palm", "right_hand_point", None,
                      (0.0, -PALM[1] / 2, PALM[2] / 2)))
    return parts


def forearm(side: str) -> Shape:
    """The forearm's look, in its frame: from the elbow (0) to the wrist (+z)."""
    radius, length = FOREARM
    return Shape("cylinder", (radius, length), (0, 0, length / 2), GREY)


def mirror(parts: list[Part], axis: int, rename: dict[str, str]) -> list[Part]:
    """The mirror image of ``parts`` through the plane normal to ``axis`` (0: x, 1: y):
    places flip, turning axes and angles change as a mirror changes a rotation; names
    change by the prefixes in ``rename``."""
    def flip(v: Vec) -> Vec:
        return tuple(-c if i == axis else c for i, c in enumerate(v))

    def turn(v: Vec) -> Vec:  # an axial vector: the mirror image of a rotation's axis
        return tuple(c if i == axis else -c for i, c in enumerate(v))

    def name(text: str) -> str:
        for old, new in rename.items():
            if text.startswith(old):
                return new + text[len(old):]
        return text

    out = []
    for p in parts:
        shape = p.shape and replace(p.shape, xyz=flip(p.shape.xyz))
        mimic = p.mimic and (name(p.mimic[0]), p.mimic[1])
        out.append(Part(name(p.joint), name(p.parent), name(p.link), shape, flip(p.xyz),
                        turn(p.rpy), p.axis and turn(p.axis), mimic))
    return out


def hands(travel: dict[str, float]) -> list[Part]:
    """Both hands, each from its forearm (``right_forearm``, ``left_forearm``)."""
    right = hand(travel)
    left = mirror(hand({k.replace("left_", "right_"): v for k, v in travel.items()
                        if k.startswith("left_")}), 0, {"right_": "left_"})
    return right + left


def torso_and_head() -> list[Part]:
    """From the hips up: bend, turn and lean (the stomach's three servos), the neck's
    nod and turn, the jaw and both eyes (the left eye follows the right one)."""
    z, y = (0.0, 0.0, 1.0), (0.0, 1.0, 0.0)
    return [
        Part("low_stom", "base_link", "abdomen", Shape("cylinder", (0.09, 0.15), (0, 0, 0.075),
                                                       GREY), (0, 0, 0.05), axis=y),
        Part("mid_stom", "abdomen", "waist", Shape("cylinder", (0.11, 0.03), (0, 0, 0.015),
                                                   DARK), (0, 0, 0.15), axis=z),
        Part("top_stom", "waist", "chest", Shape("box", (0.2, 0.34, 0.36), (0, 0, 0.2)),
             (0, 0, 0.03), axis=(1, 0, 0)),
        Part("neck", "chest", "neck_link", Shape("cylinder", (0.035, 0.08), (0, 0, 0.04), GREY),
             (0, 0, 0.38), axis=y),
        Part("rothead", "neck_link", "head", Shape("box", (0.2, 0.17, 0.2), (0, 0, 0.1)),
             (0, 0, 0.08), axis=z),
        Part("jaw", "head", "jaw_link", Shape("box", (0.1, 0.12, 0.03), (0.05, 0, -0.015)),
             (0.03, 0, 0.0), axis=y),
        Part("eye_x", "head", "right_eye_socket", None, (0.1, -0.035, 0.12), axis=z),
        Part("eye_y", "right_eye_socket", "right_eye", Shape("sphere", (0.017,), colour=DARK),
             axis=y),
        Part("left_eye_x", "head", "left_eye_socket", None, (0.1, 0.035, 0.12), axis=z,
             mimic=("eye_x", 1.0)),
        Part("left_eye_y", "left_eye_socket", "left_eye", Shape("sphere", (0.017,),
                                                                colour=DARK),
             axis=y, mimic=("eye_y", 1.0)),
        # the gaze, between the eyes, its +x the way they look: it turns as they do
        Part("gaze_x", "head", "gaze_socket", None, (0.1, 0.0, 0.12), axis=z,
             mimic=("eye_x", 1.0)),
        Part("gaze_y", "gaze_socket", "gaze", None, axis=y, mimic=("eye_y", 1.0)),
    ]


def arm() -> list[Part]:
    """The right arm, from the chest to the forearm: raise sideways (omoplate) and
    forward (shoulder), turn the upper arm, bend the elbow (bicep). Its forearm points
    down, the palm of its hand towards the body, the thumb forward."""
    return [
        Part("r_omoplate", "chest", "r_shoulder_link", Shape("sphere", (0.05,), colour=GREY),
             (0, -0.22, 0.32), axis=(-1, 0, 0)),
        Part("r_shoulder", "r_shoulder_link", "r_upper_arm",
             Shape("cylinder", (0.04, 0.26), (0, 0, -0.13)), axis=(0, -1, 0)),
        Part("r_rotate", "r_upper_arm", "r_elbow", Shape("sphere", (0.04,), colour=GREY),
             (0, 0, -0.27), axis=(0, 0, 1)),
        Part("r_bicep", "r_elbow", "right_forearm", forearm("right"), rpy=(math.pi, 0, 0),
             axis=(0, 1, 0)),
    ]


def robot(travel: dict[str, float]) -> list[Part]:
    """The whole InMoov: torso, head, both arms and both hands."""
    right = arm()
    left = mirror(right[:-1], 1, {"r_": "l_"})
    # the left hand is built mirrored in its own frame: its forearm turns the other way
    left.append(Part("l_bicep", "l_elbow", "left_forearm", forearm("left"),
                     rpy=(0, math.pi, 0), axis=(0, -1, 0)))
    return torso_and_head() + right + left + hands(travel)


def standalone(side: str) -> Part:
    """A hand's forearm as the root of a model of the hand alone (upright, palm -y)."""
    return Part("", "", f"{side}_forearm", forearm(side))
