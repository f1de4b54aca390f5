#!/usr/bin/python3
"""rostest: a bag written by this test, played with `rosbag play --clock`, gives the same
recognitions on /amcr/recognitions as amcr_offline on the same frames with the same seed.

The recognizer runs from launch/bag.launch (use_sim_time, no player: this test plays the bag once it
is written). Frames: the demo sequence (scripts/make_demo_sequence, from opencv-doc's files).
Private parameters: ~frames (default 20), ~seed (the recognizer's ~seed, default 3),
~timeout (s, default 60).
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import unittest

import cv2
import rosbag
import roslib.packages
import rospy
import rostest
from cv_bridge import CvBridge
from ros_waiting import wait_for

from amcr.msg import Recognitions
from amcr.srv import LoadPrototypes

PKG = "amcr"
IMAGE_TOPIC = "/camera/image_raw"
SCORE_TOL = 1e-4      # amcr_offline writes 4 decimals
AFFINE_TOL = 1e-5     # 6 decimals
PIXEL_TOL = 0.01      # 2 decimals


class BagVsOffline(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.frames = int(rospy.get_param("~frames", 20))
        cls.seed = int(rospy.get_param("~seed", 3))
        cls.timeout = float(rospy.get_param("~timeout", 60.0))
        cls.dir = tempfile.mkdtemp(prefix="amcr_bag_test_")
        cls.received = {}
        cls.lock = threading.Lock()
        rospy.Subscriber("/amcr/recognitions", Recognitions, cls.on_recognitions, queue_size=1000)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    @classmethod
    def on_recognitions(cls, msg):
        with cls.lock:
            cls.received[msg.header.seq] = msg

    def test_bag_gives_the_offline_recognitions(self):
        package = roslib.packages.get_pkg_dir(PKG)
        sequence = os.path.join(self.dir, "sequence")
        subprocess.run(["/usr/bin/python3", os.path.join(package, "scripts", "make_demo_sequence"), "--out", sequence,
                        "--frames", str(self.frames), "--seed", "1"], check=True, stdin=subprocess.DEVNULL,
                       stdout=subprocess.DEVNULL)
        frame_dir = os.path.join(sequence, "frames")
        prototypes = os.path.join(sequence, "prototypes")
        names = sorted(os.listdir(frame_dir))
        self.assertEqual(len(names), self.frames)

        # The bag: the frames as amcr_offline reads them (IMREAD_UNCHANGED), 10 Hz, seq = frame index.
        bag_path = os.path.join(self.dir, "frames.bag")
        bridge = CvBridge()
        with rosbag.Bag(bag_path, "w") as bag:
            for index, name in enumerate(names):
                image = cv2.imread(os.path.join(frame_dir, name), cv2.IMREAD_UNCHANGED)
                self.assertIsNotNone(image, name)
                msg = bridge.cv2_to_imgmsg(image, "mono8" if image.ndim == 2 else "bgr8")
                msg.header.seq = index
                msg.header.stamp = rospy.Time(100.0 + 0.1 * index)
                msg.header.frame_id = "camera"
                bag.write(IMAGE_TOPIC, msg, msg.header.stamp)

        # The reference: amcr_offline on the same frames, same config and seed.
        offline = roslib.packages.find_node(PKG, "amcr_offline")
        self.assertTrue(offline, "amcr_offline is not built")
        jsonl = os.path.join(self.dir, "offline.jsonl")
        subprocess.run([offline[0], "--prototypes", prototypes, "--input", frame_dir, "--config",
                        os.path.join(package, "config", "amcr.yaml"), "--seed", str(self.seed), "--output", jsonl],
                       check=True, stdin=subprocess.DEVNULL)
        reference = [json.loads(line) for line in open(jsonl) if line.strip()]
        self.assertEqual(len(reference), self.frames)
        self.assertTrue(any(r["objects"] for r in reference), "the offline runner recognized nothing")

        # The recognizer loads the same prototypes (it started without: none exist before this test).
        rospy.wait_for_service("/amcr/load_prototypes", timeout=self.timeout)
        answer = rospy.ServiceProxy("/amcr/load_prototypes", LoadPrototypes)(prototypes)
        self.assertTrue(answer.success, answer.message)

        player = subprocess.run(["rosbag", "play", "--clock", "--wait-for-subscribers", "-q", bag_path],
                                stdin=subprocess.DEVNULL, timeout=self.timeout)
        self.assertEqual(player.returncode, 0)
        self.assertTrue(wait_for(lambda: len(self.received) >= self.frames, self.timeout),
                        "%d of %d frames recognized" % (len(self.received), self.frames))

        for index, ref in enumerate(reference):
            msg = self.received[index]
            where = "frame %d" % index
            self.assertEqual(msg.iteration, ref["iteration"], where)
            self.assertEqual(msg.header.stamp, rospy.Time(100.0 + 0.1 * index), where)
            ref_objects = ref["objects"]  # both keep the core's order: best score first
            self.assertEqual([o.label for o in msg.objects], [o["label"] for o in ref_objects], where)
            for got, want in zip(msg.objects, ref_objects):
                self.assertEqual(got.track_id, want["track_id"], where)
                self.assertEqual(got.support, want["support"], where)
                self.assertAlmostEqual(got.score, want["score"], delta=SCORE_TOL, msg=where)
                self.assertAlmostEqual(got.visible_share, want["visible_share"], delta=SCORE_TOL, msg=where)
                for name in ("image_to_prototype", "prototype_to_image"):
                    flat = [v for row in want[name] for v in row]
                    for a, b in zip(getattr(got, name), flat):
                        self.assertAlmostEqual(a, b, delta=AFFINE_TOL, msg="%s %s" % (where, name))
                # The perspective fit and the view (anisotropy, viewing angle).
                self.assertEqual(got.homography_valid, want["homography_valid"], where)
                flat = [v for row in want["homography"] for v in row]
                self.assertEqual(len(got.homography), len(flat), where)
                for a, b in zip(got.homography, flat):
                    self.assertAlmostEqual(a, b, delta=AFFINE_TOL, msg="%s homography" % where)
                self.assertAlmostEqual(got.anisotropy, want["anisotropy"], delta=1e-4, msg=where)
                self.assertAlmostEqual(got.viewing_angle_deg, want["viewing_angle_deg"], delta=0.01, msg=where)
                self.assertEqual(len(got.correspondences), len(want["correspondences"]), where)
                for c, w in zip(got.correspondences, want["correspondences"]):
                    for a, b in zip((c.image_x, c.image_y, c.prototype_x, c.prototype_y), w):
                        self.assertAlmostEqual(a, b, delta=PIXEL_TOL, msg=where)


if __name__ == "__main__":
    rospy.init_node("bag_vs_offline")
    rostest.rosrun(PKG, "bag_vs_offline", BagVsOffline, sys.argv)
