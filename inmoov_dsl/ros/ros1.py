"""The node's ROS 1 edge (rospy): topics in and out of the core (core.py).

- ``joint_states`` (sensor_msgs/JointState): the joints' positions, ``--rate`` times a
  second, for robot_state_publisher and rviz.
- ``inmoov/gesture`` (std_msgs/String): a gesture's name, or a line as the repl takes.
- ``inmoov/trajectory`` (trajectory_msgs/JointTrajectory): planned through the limits.
- ``inmoov/status`` (std_msgs/String, latched): "ready: ...", "playing NAME", "done",
  "warning: ...", "error: ..."; errors and warnings are logged too.

Names are relative: in the root namespace they are /joint_states, /inmoov/gesture...
The node handles SIGINT and SIGTERM itself (``disable_signals``), so that the hand
gets its CANCEL before the node leaves, as gestplay's does.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol

import rospy
from sensor_msgs.msg import JointState
from std_msgs.msg import String
from trajectory_msgs.msg import JointTrajectory

from ..errors import Diagnostic, GestError


class Node(Protocol):
    """What the graph asks of the node (``core.Node``)."""

    def joint_names(self) -> list[str]:
        """The joints it publishes, in order."""

    def joint_positions(self) -> list[float]:
        """Their positions now (rad)."""

    def gesture(self, text: str) -> None:
        """Play a gesture (a name or steps)."""

    def trajectory(self, joints: list[str],
                   points: Sequence[tuple[Sequence[float], float]]) -> None:
        """Play a joint trajectory: (positions, time from start) per point."""

    def close(self) -> None:
        """Stop: CANCEL to the boards."""

NAME = "inmoov_hand"  #: the node's name, unless roslaunch gives it another (__name:=)
LOG = {"error": rospy.logerr, "warning": rospy.logwarn, "info": rospy.loginfo}


def argv(args: list[str]) -> list[str]:
    """The command line without ROS's ``name:=value`` arguments (roslaunch adds some)."""
    return rospy.myargv(args)


class Ros1:
    """The node in a ROS 1 graph."""

    def __init__(self, rate: float):
        self.rate = rate
        self.status: rospy.Publisher | None = None
        self.timer: rospy.Timer | None = None

    def check(self) -> None:
        """A GestError if no master answers (roslaunch starts one; else roscore)."""
        import rosgraph  # rospy's own dependency: imported after rospy, which says more

        if not rosgraph.is_master_online():
            raise GestError(Diagnostic(
                "error", f"no ROS master at {rosgraph.get_master_uri()}",
                hint="start roscore (roslaunch starts one), or set ROS_MASTER_URI"))

    def start(self, node: Node) -> None:
        """Join the graph: the node's topics, and its joint states at the rate."""
        rospy.init_node(NAME, disable_signals=True)
        self.status = rospy.Publisher("inmoov/status", String, queue_size=20, latch=True)
        states = rospy.Publisher("joint_states", JointState, queue_size=10)
        joints = node.joint_names()

        def publish(_event: object) -> None:
            msg = JointState(name=joints, position=node.joint_positions())
            msg.header.stamp = rospy.Time.now()
            states.publish(msg)

        def planned(msg: JointTrajectory) -> None:
            node.trajectory(list(msg.joint_names),
                            [(p.positions, p.time_from_start.to_sec()) for p in msg.points])

        rospy.Subscriber("inmoov/gesture", String, lambda msg: node.gesture(msg.data),
                         queue_size=10)
        rospy.Subscriber("inmoov/trajectory", JointTrajectory, planned, queue_size=10)
        self.timer = rospy.Timer(rospy.Duration(1 / self.rate), publish)
        rospy.on_shutdown(node.close)

    def say(self, kind: str, text: str) -> None:
        """Log ``text`` and publish it on inmoov/status."""
        LOG[kind](text)
        if self.status is not None:
            self.status.publish(String(text))

    def stop(self) -> None:
        """Stop publishing and leave the graph."""
        if self.timer is not None:
            self.timer.shutdown()
        if not rospy.is_shutdown():
            rospy.signal_shutdown("the node stops")
