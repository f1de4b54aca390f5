#!/usr/bin/python3
"""rostest: config/amcr.yaml is a ROS parameter file (test/ros/rosparam_config.test). The nodelet of the
launch file got it through <rosparam file>; this test starts a second one after `rosparam load` on the
command line, as a user would. Both files are layered (config/large_memory.yaml on top, table_stride 2):
each nodelet must run with exactly those values (dynamic_reconfigure shows the parameters in effect),
and amcr_offline must read the same file through --config.

Private parameters: ~timeout (s, default 30).
"""
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import unittest

import cv2
import numpy as np
import roslib.packages
import rospkg
import rospy
import rostest
import yaml
from dynamic_reconfigure.client import Client

PKG = "amcr"


def layered_values():
    """config/amcr.yaml with config/large_memory.yaml on top, as rosparam loads them."""
    config = os.path.join(rospkg.RosPack().get_path(PKG), "config")
    values = {}
    for name in ("amcr.yaml", "large_memory.yaml"):
        with open(os.path.join(config, name)) as f:
            values.update(yaml.safe_load(f))
    return values, os.path.join(config, "amcr.yaml")


class RosparamConfig(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.timeout = float(rospy.get_param("~timeout", 30.0))
        cls.values, cls.amcr_yaml = layered_values()
        cls.children = []

    @classmethod
    def tearDownClass(cls):
        for child in cls.children:
            child.send_signal(signal.SIGINT)
            try:
                child.wait(timeout=10)
            except subprocess.TimeoutExpired:
                child.kill()

    def check_runs_with_the_files_values(self, node):
        config = Client(node, timeout=self.timeout).get_configuration(timeout=self.timeout)
        self.assertIsNotNone(config, "no configuration from %s" % node)
        compared = 0
        for key, expected in self.values.items():
            if key not in config or isinstance(expected, dict):
                continue
            actual = config[key]
            if isinstance(expected, str):
                self.assertEqual(actual, expected, "%s: %s" % (node, key))
            else:
                self.assertAlmostEqual(float(actual), float(expected), delta=1e-9 * max(1.0, abs(float(expected))),
                                       msg="%s: %s is %s, the files say %s" % (node, key, actual, expected))
            compared += 1
        self.assertGreater(compared, 40, "%s: only %d parameters compared" % (node, compared))
        self.assertEqual(config["table_stride"], 2, "%s: the second file did not take effect" % node)

    def test_launch_file_rosparam(self):
        self.check_runs_with_the_files_values("/amcr")

    def test_command_line_rosparam_load(self):
        config_dir = os.path.dirname(self.amcr_yaml)
        for name in ("amcr.yaml", "large_memory.yaml"):
            subprocess.run(["rosparam", "load", os.path.join(config_dir, name), "/amcr_cli"], check=True,
                           timeout=self.timeout)
        self.assertEqual(rospy.get_param("/amcr_cli/table_stride"), 2)
        child = subprocess.Popen(["rosrun", "nodelet", "nodelet", "standalone", "amcr/RecognizerNodelet",
                                  "__name:=amcr_cli"])
        self.children.append(child)
        self.check_runs_with_the_files_values("/amcr_cli")

    def test_offline_runner_reads_the_same_file(self):
        offline = roslib.packages.find_node(PKG, "amcr_offline")
        self.assertTrue(offline, "amcr_offline not found")
        work = tempfile.mkdtemp(prefix="amcr_rosparam_")
        try:
            prototypes = os.path.join(work, "prototypes")
            os.mkdir(prototypes)
            shape = np.zeros((200, 200), np.uint8)
            cv2.fillPoly(shape, [np.array([(100, 18), (150, 80), (128, 180), (92, 150), (40, 96)], np.int32)], 255)
            cv2.imwrite(os.path.join(prototypes, "kite.png"), shape)
            frame = np.full((240, 320), 190, np.uint8)
            frame[20:220, 60:260] = np.where(shape > 0, 40, 190).astype(np.uint8)
            cv2.imwrite(os.path.join(work, "frame.png"), frame)
            run = subprocess.run([offline[0], "--config", self.amcr_yaml, "--prototypes", prototypes, "--input",
                                  os.path.join(work, "frame.png"), "--frames", "2", "--seed", "1"],
                                 capture_output=True, text=True, timeout=120)
            self.assertEqual(run.returncode, 0, run.stderr)
            self.assertEqual(len(run.stdout.strip().splitlines()), 2, run.stdout)
        finally:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    rospy.init_node("rosparam_config")
    rostest.rosrun(PKG, "rosparam_config", RosparamConfig, sys.argv)
