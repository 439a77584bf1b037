"""A ROS 1 client of the hand's node for tests/test_ros.py, run under ROS's Python.

Reads a JSON list of requests on stdin, sends them one after another, and prints one
JSON line for each: the statuses it brought and the joint states after it.

- ``{"gesture": "fist"}``: publish on /inmoov/gesture, wait for "done" or "error: ...".
- ``{"trajectory": [joint names, [[positions, time], ...]]}``: the same on
  /inmoov/trajectory; ``"trace": true`` also gives every joint state until then.
- ``"until": "playing"``: stop waiting at the first status that starts so.
- ``{"joints": true}``: just the next joint states.
- ``{"tf": "frame"}``: wait for a /tf message that carries the frame (read raw: no
  tf2_msgs needed).
- ``{"param": "name"}``: the parameter's first 200 characters.

Every wait is bounded (TIMEOUT); a wait that times out prints {"timeout": what}.
"""

import json
import math
import sys
import threading

import rospy
from sensor_msgs.msg import JointState
from std_msgs.msg import String
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

TIMEOUT = 20.0


class Client:
    """The node's topics, seen from outside."""

    def __init__(self):
        rospy.init_node("test_client", anonymous=True, disable_signals=True)
        self.cond = threading.Condition()
        self.statuses: list[str] = []
        self.states: list[dict] = []
        self.frames: list[bytes] = []
        rospy.Subscriber("/inmoov/status", String, self._keep(self.statuses, "data"))
        rospy.Subscriber("/joint_states", JointState, self._joint_state)
        rospy.Subscriber("/tf", rospy.AnyMsg, self._keep(self.frames, "_buff"))
        self.gesture = rospy.Publisher("/inmoov/gesture", String, queue_size=10)
        self.trajectory = rospy.Publisher("/inmoov/trajectory", JointTrajectory,
                                          queue_size=10)

    def _keep(self, into, field):
        def keep(msg):
            with self.cond:
                into.append(getattr(msg, field))
                self.cond.notify_all()
        return keep

    def _joint_state(self, msg):
        with self.cond:
            self.states.append(dict(zip(msg.name, msg.position, strict=True)))
            self.cond.notify_all()

    def wait(self, test, what):
        """Wait for ``test()``; False (and a line saying what) if it does not come."""
        with self.cond:
            if self.cond.wait_for(test, TIMEOUT):
                return True
        print(json.dumps({"timeout": what}), flush=True)
        return False

    def ready(self):
        """The node is up (its latched status came) and hears our publishers."""
        return self.wait(lambda: self.statuses and self.states, "the node's status") and \
            self.wait(lambda: self.gesture.get_num_connections() > 0 and
                      self.trajectory.get_num_connections() > 0, "the node subscribing")

    def request(self, req):
        """Send one request; its statuses and the joint states after it."""
        if "param" in req:
            return {"param": str(rospy.get_param(req["param"], ""))[:200]}
        if "tf" in req:
            name = req["tf"].encode()
            return {"tf": self.wait(lambda: any(name in f for f in self.frames), "tf")}
        first, states = len(self.statuses), len(self.states)
        if "gesture" in req:
            self.gesture.publish(String(req["gesture"]))
        elif "trajectory" in req:
            self.trajectory.publish(trajectory(*req["trajectory"]))
        ends = (req["until"],) if "until" in req else ("done", "error")
        if "joints" not in req and not self.wait(
                lambda: any(s.startswith(ends) for s in self.statuses[first:]), ends):
            return None
        after = len(self.states)
        if not self.wait(lambda: len(self.states) > after, "joint states"):
            return None
        out = {"status": self.statuses[first:], "joints": self.states[-1]}
        if req.get("trace"):
            out["trace"] = self.states[states:]
        return out


def trajectory(names, points):
    """A JointTrajectory message."""
    msg = JointTrajectory(joint_names=names)
    for positions, t in points:
        secs = math.floor(t)
        msg.points.append(JointTrajectoryPoint(
            positions=positions, time_from_start=rospy.Duration(secs, int((t - secs) * 1e9))))
    return msg


def main():
    requests = json.load(sys.stdin)
    client = Client()
    if client.ready():
        for req in requests:
            out = client.request(req)
            if out is None:
                break
            print(json.dumps(out), flush=True)
    rospy.signal_shutdown("done")


if __name__ == "__main__":
    main()
