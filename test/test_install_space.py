#!/usr/bin/python3
"""The installed package runs: from the install space alone (`catkin_make install`; its
local_setup.bash sourced over the system's ROS, in an environment without the devel space or the
source tree), `roslaunch amcr amcr.launch` starts the nodelet from the installed library, loads
drawn prototypes, answers an image with recognitions (the installed Python messages read them) and
~reset; amcr_offline runs.

scripts/test builds the install space and names it in AMCR_INSTALL_SPACE (and sets
AMCR_REQUIRE_INSTALL=1, so that a missing one fails); run by hand without it, the test skips with a
message.

  test/test_install_space.py [--xml FILE]   (JUnit XML for catkin; about 15 s)
"""
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import unittest

HERE = os.path.dirname(os.path.realpath(__file__))
SOURCE = os.path.dirname(HERE)
INSTALL = os.environ.get("AMCR_INSTALL_SPACE", "")
TIMEOUT = 60.0  # s, for each step

# Runs inside the install space's environment: waits for the label table, publishes a drawn frame
# until recognitions come back, calls ~reset; prints what it saw, one fact per line.
CLIENT = r"""
import sys, time
import numpy as np, cv2, rospy
from sensor_msgs.msg import Image
from std_srvs.srv import Trigger
from amcr.msg import PrototypeTable, Recognitions
rospy.init_node("install_space_client")
table = rospy.wait_for_message("/amcr/prototypes", PrototypeTable, timeout=60)
print("prototypes %d version %d" % (len(table.prototypes), table.version))
got = []
rospy.Subscriber("/amcr/recognitions", Recognitions, got.append)
pub = rospy.Publisher("/cam/image_raw", Image, queue_size=1)
shape = cv2.imread(sys.argv[1], cv2.IMREAD_GRAYSCALE)
frame = np.full((240, 320), 190, np.uint8)
frame[20:220, 60:260][shape > 0] = 40
deadline = time.time() + 60
while not got and time.time() < deadline and not rospy.is_shutdown():
    msg = Image(height=240, width=320, encoding="mono8", step=320, data=frame.tobytes())
    msg.header.stamp = rospy.Time.now()
    msg.header.frame_id = "camera"
    pub.publish(msg)
    time.sleep(0.2)
print("recognitions %s version %d" % (bool(got), got[0].prototype_table_version if got else -1))
answer = rospy.ServiceProxy("/amcr/reset", Trigger)()
print("reset %s" % answer.success)
"""


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class InstallSpace(unittest.TestCase):
    def setUp(self):
        if not INSTALL or not os.path.isfile(os.path.join(INSTALL, "local_setup.bash")):
            if os.environ.get("AMCR_REQUIRE_INSTALL") == "1":
                self.fail("no install space at AMCR_INSTALL_SPACE='%s' (catkin_make install failed?)" % INSTALL)
            self.skipTest("no install space: scripts/test builds one (catkin_make install) and names it in "
                          "AMCR_INSTALL_SPACE")
        self.work = tempfile.mkdtemp(prefix="amcr_install_")
        self.processes = []
        port = free_port()
        # The system's ROS only (the prefixes that are no catkin workspace: a devel or install space
        # holds a .catkin file), then the install space on top of it (local_setup.bash: not the
        # workspaces setup.bash chains as they were at configure time, the devel space among them).
        system = [p for p in os.environ.get("CMAKE_PREFIX_PATH", "/usr").split(":")
                  if p and not os.path.exists(os.path.join(p, ".catkin"))]
        clean = {"PATH": "/usr/bin:/bin", "HOME": self.work, "LANG": "C.UTF-8", "ROS_IP": "127.0.0.1",
                 "ROS_HOME": os.path.join(self.work, "ros"), "ROS_MASTER_URI": "http://127.0.0.1:%d" % port,
                 "CMAKE_PREFIX_PATH": ":".join(system or ["/usr"])}
        dump = subprocess.run(["bash", "-c", 'set +u; source "$0/local_setup.bash" >/dev/null && env -0', INSTALL],
                              env=clean, stdout=subprocess.PIPE, check=True, timeout=TIMEOUT)
        self.env = dict(item.split("=", 1) for item in dump.stdout.decode().split("\0") if "=" in item)
        self.port = port

    def tearDown(self):
        for process in reversed(self.processes):
            if process.poll() is None:
                process.send_signal(signal.SIGINT)
                try:
                    process.wait(timeout=15)
                except subprocess.TimeoutExpired:
                    process.kill()
                    process.wait()
        shutil.rmtree(self.work, ignore_errors=True)

    def run_in_install(self, *command, **kwargs):
        return subprocess.run(list(command), env=self.env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                              universal_newlines=True, timeout=TIMEOUT, **kwargs)

    def start(self, *command):
        log = open(os.path.join(self.work, "%s.log" % os.path.basename(command[0])), "w")
        process = subprocess.Popen(list(command), env=self.env, stdout=log, stderr=subprocess.STDOUT,
                                   start_new_session=True)
        self.processes.append(process)
        return process

    def log(self, name):
        path = os.path.join(self.work, name + ".log")
        return open(path).read()[-3000:] if os.path.exists(path) else ""

    def test_amcr_launch_runs_from_the_install_space(self):
        import cv2
        import numpy as np
        # The environment knows the install space and the system's ROS only.
        for entry in filter(None, self.env.get("ROS_PACKAGE_PATH", "").split(":")):
            self.assertTrue(entry.startswith(INSTALL) or not os.path.realpath(entry).startswith(SOURCE),
                            "ROS_PACKAGE_PATH holds the source tree or the workspace around it: " + entry)
        found = self.run_in_install("rospack", "find", "amcr")
        self.assertEqual(found.stdout.strip(), os.path.join(INSTALL, "share", "amcr"), found.stdout)
        offline = self.run_in_install(os.path.join(INSTALL, "lib", "amcr", "amcr_offline"), "--help")
        self.assertEqual(offline.returncode, 0, offline.stdout)

        prototypes = os.path.join(self.work, "prototypes")
        os.mkdir(prototypes)
        kite = np.zeros((200, 200), np.uint8)
        cv2.fillPoly(kite, [np.array([(100, 18), (150, 80), (128, 180), (92, 150), (40, 96)], np.int32)], 255)
        cv2.imwrite(os.path.join(prototypes, "kite.png"), kite)
        boot = np.zeros((200, 200), np.uint8)
        cv2.fillPoly(boot, [np.array([(40, 20), (95, 20), (95, 120), (170, 130), (175, 178), (35, 178)],
                                     np.int32)], 255)
        cv2.imwrite(os.path.join(prototypes, "boot.png"), boot)

        self.start("roscore", "-p", str(self.port))
        up = False
        deadline = time.monotonic() + TIMEOUT
        while not up and time.monotonic() < deadline:
            up = self.run_in_install("rosparam", "get", "/rosdistro").returncode == 0
            time.sleep(0.2)
        self.assertTrue(up, "roscore did not come up: " + self.log("roscore"))
        launch = self.start("roslaunch", "amcr", "amcr.launch", "prototypes:=" + prototypes, "image:=/cam/image_raw")

        client = self.run_in_install("python3", "-c", CLIENT, os.path.join(prototypes, "kite.png"))
        self.assertIsNone(launch.poll(), "roslaunch ended: " + self.log("roslaunch"))
        self.assertEqual(client.returncode, 0, client.stdout + self.log("roslaunch"))
        lines = client.stdout.splitlines()
        self.assertIn("prototypes 2 version 1", lines, client.stdout)
        self.assertIn("recognitions True version 1", lines, client.stdout)
        self.assertIn("reset True", lines, client.stdout)

        # The nodelet runs the installed library, not the devel space's.
        pids = self.run_in_install("pgrep", "-f", "amcr/RecognizerNodelet").stdout.split()
        self.assertTrue(pids, "no nodelet process")
        maps = "".join(open("/proc/%s/maps" % pid).read() for pid in pids if os.path.exists("/proc/%s/maps" % pid))
        self.assertIn(os.path.join(INSTALL, "lib", "libamcr_nodelet.so"), maps)


if __name__ == "__main__":
    sys.path.insert(0, os.path.join(HERE, "bench"))
    from junit_runner import run_module
    sys.exit(run_module(sys.modules[__name__], "test_install_space"))
