"""Waiting on a condition in the Python rostests (imported from the test's own directory)."""
import time

import rospy


def wait_for(condition, timeout, poll=0.02):
    """Polls `condition` every `poll` s on wall time (a rostest's clock may be simulated); False after
    `timeout` s or when ROS shuts down."""
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline or rospy.is_shutdown():
            return False
        time.sleep(poll)
    return True
