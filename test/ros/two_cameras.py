#!/usr/bin/python3
"""rostest: two recognizers from launch/amcr.launch side by side, one per camera (test/ros/two_cameras.test:
/left through the launch file's ns argument, /right through <group ns>). Each camera shows another
drawn shape; each recognizer must report its own camera's shape with a pose and a tf frame under its
own prefix, read camera_info from its image's sibling topic, and publish nothing outside its namespace.

Inputs are drawn here: two asymmetric polygons (prototypes and scenes), grey background, noise.
Private parameters: ~max_frames (default 100), ~timeout (s, default 20).
"""
import os
import shutil
import sys
import tempfile
import threading
import unittest

import cv2
import numpy as np
import rosgraph
import rospy
import rostest
import tf2_ros
from drawn_camera import camera_info
from ros_waiting import wait_for
from sensor_msgs.msg import CameraInfo, Image

from amcr.msg import Recognitions
from amcr.srv import LoadPrototypes

PKG = "amcr"
SIZE = 200  # prototype image side, px
METRES_PER_PIXEL = 0.001  # as two_cameras.test gives it
# Asymmetric outlines in prototype px: no mirror or rotational symmetry.
SHAPES = {
    "kite": [(100, 18), (150, 80), (128, 180), (92, 150), (40, 96), (70, 60)],
    "boot": [(40, 20), (95, 20), (95, 120), (170, 130), (175, 178), (35, 178), (55, 100)],
    "wedge": [(20, 160), (180, 40), (170, 170), (110, 140)],
}
CAMERAS = {"left": "kite", "right": "boot"}
# Topics every node may publish besides its own namespace.
SHARED_TOPICS = {"/tf", "/tf_static", "/rosout", "/diagnostics"}


def prototype(name):
    image = np.zeros((SIZE, SIZE), np.uint8)
    cv2.fillPoly(image, [np.array(SHAPES[name], np.int32)], 255, cv2.LINE_AA)
    return image


def scene(name, angle, centre, seed):
    """640 x 480 mono8: the shape dark on a light gradient, rotated by `angle` rad about its centre."""
    rng = np.random.default_rng(seed)
    x = np.linspace(0.0, 1.0, 640, dtype=np.float32)
    image = np.tile(175.0 + 40.0 * x, (480, 1))
    c, s = np.cos(angle), np.sin(angle)
    points = [((px - 100) * c - (py - 100) * s + centre[0], (px - 100) * s + (py - 100) * c + centre[1])
              for px, py in SHAPES[name]]
    mask = np.zeros((480, 640), np.uint8)
    cv2.fillPoly(mask, [np.round(np.array(points) * 16).astype(np.int32)], 255, cv2.LINE_AA, shift=4)
    image = image * (1.0 - mask / 255.0) + 35.0 * (mask / 255.0)
    image += rng.normal(0.0, 5.0, image.shape)
    return np.clip(image, 0, 255).astype(np.uint8)


def image_msg(array, stamp, frame_id):
    msg = Image()
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    msg.height, msg.width = array.shape
    msg.encoding = "mono8"
    msg.step = msg.width
    msg.data = array.tobytes()
    return msg


class TwoCameras(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.max_frames = int(rospy.get_param("~max_frames", 100))
        cls.timeout = float(rospy.get_param("~timeout", 20.0))
        cls.dir = tempfile.mkdtemp(prefix="amcr_two_cameras_")
        for name in SHAPES:
            cv2.imwrite(os.path.join(cls.dir, name + ".png"), prototype(name))
        cls.lock = threading.Lock()
        cls.received = {ns: {} for ns in CAMERAS}
        cls.image_pubs, cls.info_pubs = {}, {}
        for ns in CAMERAS:
            cls.image_pubs[ns] = rospy.Publisher("/%s/camera/image_raw" % ns, Image, queue_size=10)
            cls.info_pubs[ns] = rospy.Publisher("/%s/camera/camera_info" % ns, CameraInfo, queue_size=1, latch=True)
            rospy.Subscriber("/%s/amcr/recognitions" % ns, Recognitions, cls.on_recognitions, callback_args=ns,
                             queue_size=100)
        cls.tf_buffer = tf2_ros.Buffer()
        cls.tf_listener = tf2_ros.TransformListener(cls.tf_buffer)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    @classmethod
    def on_recognitions(cls, msg, ns):
        with cls.lock:
            cls.received[ns][msg.header.stamp] = msg

    def test_each_camera_its_own_recognizer(self):
        for ns in CAMERAS:
            service = "/%s/amcr/load_prototypes" % ns
            rospy.wait_for_service(service, self.timeout)
            answer = rospy.ServiceProxy(service, LoadPrototypes)(self.dir)
            self.assertTrue(answer.success, answer.message)
            self.assertTrue(wait_for(lambda: self.image_pubs[ns].get_num_connections() > 0, self.timeout),
                            "nobody subscribes to /%s/camera/image_raw" % ns)
            # camera_info is the image's sibling: the recognizer subscribes to it unasked.
            self.assertTrue(wait_for(lambda: self.info_pubs[ns].get_num_connections() > 0, self.timeout),
                            "nobody subscribes to /%s/camera/camera_info" % ns)
            self.info_pubs[ns].publish(camera_info(ns + "_camera"))

        found = {}
        stamp = rospy.Time(100.0)
        for k in range(self.max_frames):
            stamp += rospy.Duration(0.1)
            for ns, shape in CAMERAS.items():
                angle = 0.3 if ns == "left" else -0.5
                self.image_pubs[ns].publish(image_msg(scene(shape, angle, (320, 240), 1000 * len(ns) + k), stamp,
                                                      ns + "_camera"))
            for ns in CAMERAS:
                self.assertTrue(wait_for(lambda: stamp in self.received[ns], self.timeout),
                                "no recognitions from /%s/amcr for frame %d" % (ns, k))
            with self.lock:
                for ns, shape in CAMERAS.items():
                    msg = self.received[ns][stamp]
                    self.assertEqual(msg.header.frame_id, ns + "_camera")
                    for o in msg.objects:
                        # Each recognizer sees its own camera only: the other camera's shape never shows.
                        self.assertNotEqual(o.label, CAMERAS["right" if ns == "left" else "left"],
                                            "/%s/amcr reports the other camera's shape" % ns)
                    if ns not in found and msg.objects and msg.objects[0].label == shape and msg.objects[0].pose_valid:
                        found[ns] = msg
            if len(found) == len(CAMERAS):
                break
        self.assertEqual(sorted(found), sorted(CAMERAS), "recognized with a pose within %d frames: %s"
                         % (self.max_frames, sorted(found)))

        # Frames under each recognizer's own prefix (the default: <ns>/<name>/), children of its camera.
        for ns, msg in found.items():
            obj = msg.objects[0]
            child = "%s/amcr/%s_%d" % (ns, obj.label, obj.track_id)
            try:
                t = self.tf_buffer.lookup_transform(ns + "_camera", child, msg.header.stamp,
                                                    rospy.Duration(self.timeout))
            except tf2_ros.TransformException as e:
                self.fail("no tf frame %s: %s" % (child, e))
            # The shape's centre at the image centre, the plane parallel to the image: x, y about 0.
            self.assertAlmostEqual(t.transform.translation.z, obj.pose.position.z, delta=1e-6)
            self.assertGreater(t.transform.translation.z, 0.0)

        # No topic or service of one recognizer outside its namespace.
        publishers, subscribers, services = rosgraph.Master("/two_cameras").getSystemState()
        for ns in CAMERAS:
            node = "/%s/amcr" % ns
            for topic, nodes in publishers:
                if node in nodes:
                    self.assertTrue(topic.startswith("/%s/" % ns) or topic in SHARED_TOPICS,
                                    "%s publishes %s" % (node, topic))
            for topic, nodes in subscribers:
                if node in nodes and topic not in SHARED_TOPICS:
                    self.assertTrue(topic.startswith("/%s/" % ns), "%s subscribes to %s" % (node, topic))
            for service, nodes in services:
                if node in nodes:
                    self.assertTrue(service.startswith(node + "/"), "%s offers %s" % (node, service))
            mine = [topic for topic, nodes in subscribers if node in nodes]
            self.assertIn("/%s/camera/camera_info" % ns, mine)
            self.assertIn("/%s/camera/image_raw" % ns, mine)


if __name__ == "__main__":
    rospy.init_node("two_cameras")
    rostest.rosrun(PKG, "two_cameras", TwoCameras, sys.argv)
