"""The URDF model of a profile's robot (pure): ``gestc urdf --profile NAME``.

The body is urdf_parts' InMoov. A profile's model is the part of it that holds the
profile's joints (a hand alone from its forearm, or the whole robot from its hips);
each servo turns its ``joint`` (profile table), with the limits of its range as
joints.py converts them. Joints of the body that no servo turns are fixed at their
rest pose, and a finger's phalanges follow its joint. Each part's shape is both its
look (``visual``) and its ``collision`` geometry, so any URDF tool checks the model
collide.py checks.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from collections.abc import Iterable

from ..errors import Diagnostic, GestError, did_you_mean
from ..hardware import Profile, Servo
from . import joints
from . import urdf_parts as parts
from .urdf_parts import Part, Shape

EFFORT = 1.0  #: N m: about what an MG996R-class servo gives (the model has no dynamics)


def body(profile: Profile) -> list[Part]:
    """The parts of the InMoov that hold the profile's joints, root first."""
    travel = {s.joint: math.degrees(joints.position(s, s.hi) - joints.position(s, s.lo))
              for s in profile.servos}
    everything = parts.robot(travel)
    carried = {p.joint: p for p in everything}
    for servo in profile.servos:
        if servo.joint not in carried:
            raise GestError(_unknown(profile, servo, [p.joint for p in everything
                                                      if p.axis and not p.mimic]))
    root = _root(everything, [carried[s.joint].parent for s in profile.servos])
    if root.endswith("_forearm"):
        return [parts.standalone(root.removesuffix("_forearm")), *_below(everything, root)]
    return [Part("", "", root, None), *_below(everything, root)]


def _unknown(profile: Profile, servo: Servo, names: list[str]) -> Diagnostic:
    pos, line = servo.joint_at or (None, None)
    return Diagnostic("error", f"servo '{servo.name}' turns joint '{servo.joint}', which "
                      f"the InMoov model does not have",
                      pos, did_you_mean(servo.joint, names) or
                      f"set joint = \"...\" in its [servo.{servo.name}] table, one of: "
                      + ", ".join(names), line)


def _root(everything: list[Part], links: list[str]) -> str:
    """The deepest link above (or at) every one of ``links``."""
    up = {p.link: p.parent for p in everything}

    def chain(link: str) -> list[str]:
        out = [link]
        while link in up:
            link = up[link]
            out.append(link)
        return out[::-1]

    chains = [chain(link) for link in links]
    common = [names[0] for names in zip(*chains, strict=False) if len(set(names)) == 1]
    return common[-1]


def _below(everything: list[Part], root: str) -> list[Part]:
    """The parts under link ``root``, each after its parent."""
    found, links = [], {root}
    for part in everything:  # urdf_parts lists every part after its parent
        if part.parent in links:
            found.append(part)
            links.add(part.link)
    return found


def model(profile: Profile) -> str:
    """The URDF (XML text) of the profile's robot."""
    servos = joints.servo_of(profile)
    robot = ET.Element("robot", name=profile.name)
    for name, rgba in parts.COLOURS.items():
        ET.SubElement(ET.SubElement(robot, "material", name=name), "color",
                      rgba=_text(rgba))
    for part in body(profile):
        _link(robot, part)
        if part.joint:
            _joint(robot, part, servos)
    ET.indent(robot)
    comment = (f"<!-- {profile.name}: made by gestc urdf from the profile "
               f"{profile.path or profile.name}; see docs/simulation.md -->\n")
    return '<?xml version="1.0"?>\n' + comment + ET.tostring(robot, encoding="unicode") + "\n"


def _link(robot: ET.Element, part: Part) -> None:
    link = ET.SubElement(robot, "link", name=part.link)
    if part.shape is None:
        return
    visual = _shape(link, "visual", part.shape)
    ET.SubElement(visual, "material", name=part.shape.colour)
    _shape(link, "collision", part.shape)  # the same shape: what collide.py checks


def _shape(link: ET.Element, kind: str, shape: Shape) -> ET.Element:
    """A ``visual`` or ``collision`` element of ``link``: the shape, where it is."""
    element = ET.SubElement(link, kind)
    ET.SubElement(element, "origin", xyz=_text(shape.xyz), rpy="0 0 0")
    geometry = ET.SubElement(element, "geometry")
    if shape.kind == "box":
        ET.SubElement(geometry, "box", size=_text(shape.size))
    elif shape.kind == "cylinder":
        ET.SubElement(geometry, "cylinder", radius=_text(shape.size[:1]),
                      length=_text(shape.size[1:]))
    else:
        ET.SubElement(geometry, "sphere", radius=_text(shape.size))
    return element


def _joint(robot: ET.Element, part: Part, servos: dict[str, Servo]) -> None:
    """The joint that carries ``part``: a servo's (revolute, its limits), one that
    follows a servo's (mimic), or fixed."""
    master = part.mimic[0] if part.mimic else part.joint
    servo = servos.get(master) if part.axis else None
    joint = ET.SubElement(robot, "joint", name=part.joint,
                          type="fixed" if servo is None else "revolute")
    ET.SubElement(joint, "parent", link=part.parent)
    ET.SubElement(joint, "child", link=part.link)
    ET.SubElement(joint, "origin", xyz=_text(part.xyz), rpy=_text(part.rpy))
    if servo is None or part.axis is None:
        return
    ET.SubElement(joint, "axis", xyz=_text(part.axis))
    k = part.mimic[1] if part.mimic else 1.0
    low, high = sorted(x * k for x in joints.limits(servo))
    speed = servo.max_velocity * joints.scale(servo) * abs(k)
    ET.SubElement(joint, "limit", lower=_text([low]), upper=_text([high]),
                  effort=_text([EFFORT]), velocity=_text([speed]))
    if part.mimic:
        ET.SubElement(joint, "mimic", joint=master, multiplier=_text([k]), offset="0")


def _text(numbers: Iterable[float]) -> str:
    """Numbers as URDF writes them: space-separated, to 1e-6, no -0."""
    return " ".join(repr(round(x, 6) + 0.0) for x in numbers)
