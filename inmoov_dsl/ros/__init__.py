"""The hand as a ROS node: ``python -m inmoov_dsl.ros --port PORT`` (docs/ros.md).

``core`` is the node without ROS (ports, the drive loop, requests, joint states),
``trajectory`` turns a joint trajectory into planned steps, and ``ros1`` is the edge
for ROS 1 (rospy): a ROS 2 edge would be one more module beside it. Importing this
package does not import rospy.
"""
