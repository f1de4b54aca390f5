#!/usr/bin/python3
"""rostest: RViz with config/amcr.rviz, run for real in a virtual display beside the recognizer on the
demo sequence (test/ros/rviz_screenshot.test). From screenshots of the display it checks that RViz
draws what the recognizer publishes: the overlay image in its Image panel, and each object's outline
marker in the 3D view in its track's colour (there before, not there before the first report).

The demo sequence is rendered here (scripts/make_demo_sequence, from opencv-doc's files) and
published frame after frame as /camera/image_raw (frame_id "camera", the fixed frame of amcr.rviz)
with its camera_info;
the memory is loaded through ~load_prototypes. Xvfb provides the display (software OpenGL). The last
screenshot is written to ~screenshot (default: $ROS_HOME/amcr_rviz.png), the README's RViz picture.

Private parameters: ~frames (of the sequence, default 40), ~timeout (s, default 60), ~screenshot.
Skips with a message when rviz, Xvfb or xwd is not installed (Debian: rviz xvfb x11-apps; scripts/test
installs them).
"""
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import time
import unittest

import cv2
import numpy as np
import rosgraph
import rospkg
import rospy
import rostest
from cv_bridge import CvBridge
from drawn_camera import camera_info
from ros_waiting import wait_for
from sensor_msgs.msg import CameraInfo, Image
from visualization_msgs.msg import MarkerArray

from amcr.msg import Recognitions
from amcr.srv import LoadPrototypes

PKG = "amcr"
SCREEN = (1280, 800)
COLOUR_TOLERANCE = 40        # grey levels per channel: a marker line's shading and antialiasing
MIN_MARKER_PIXELS = 30       # of the track's colour in the 3D view once an outline is drawn
MIN_OVERLAY_MATCH = 0.8      # normalised correlation of the overlay image with its panel


def read_xwd(data):
    """An XWD screenshot (xwd -root of a 24-bit TrueColor display, 24 or 32 bits per pixel) as BGR."""
    header = np.frombuffer(data[:100], ">u4")
    header_size, version, depth = int(header[0]), int(header[1]), int(header[3])
    width, height, byte_order, bits_per_pixel = int(header[4]), int(header[5]), int(header[7]), int(header[11])
    bytes_per_line, ncolors = int(header[12]), int(header[19])
    if version != 7 or depth != 24 or bits_per_pixel not in (24, 32):
        raise ValueError("xwd: version %d, depth %d, %d bits per pixel: not a 24-bit TrueColor dump"
                         % (version, depth, bits_per_pixel))
    start = header_size + 12 * ncolors
    rows = np.frombuffer(data[start:start + height * bytes_per_line], np.uint8).reshape(height, bytes_per_line)
    channels = bits_per_pixel // 8
    pixels = rows[:, :channels * width].reshape(height, width, channels)
    # LSBFirst (0): B, G, R (, X) in memory; MSBFirst: (X,) R, G, B.
    return pixels[:, :, :3].copy() if byte_order == 0 else pixels[:, :, ::-1][:, :, :3].copy()


def best_match(screen, image):
    """The best normalised correlation of `image` (grey) anywhere in `screen` (BGR), over the scales an
    RViz panel may show it at: every 0.02 from 0.15 to 1, then every 0.002 around the best (at a
    panel's size a scale 0.01 off already loses much of the correlation)."""
    grey = cv2.cvtColor(screen, cv2.COLOR_BGR2GRAY)

    def at(scale):
        w, h = int(round(image.shape[1] * scale)), int(round(image.shape[0] * scale))
        if w < 40 or h < 30 or w > grey.shape[1] or h > grey.shape[0]:
            return -1.0
        small = cv2.resize(image, (w, h), interpolation=cv2.INTER_LINEAR)
        return float(cv2.matchTemplate(grey, small, cv2.TM_CCOEFF_NORMED).max())

    coarse = max(np.arange(0.15, 1.0001, 0.02), key=at)
    return max(at(scale) for scale in np.arange(coarse - 0.02, coarse + 0.0201, 0.002))


def colour_pixels(screen, rgb):
    """Pixels within COLOUR_TOLERANCE of `rgb` (0-1 floats, as a marker's colour)."""
    bgr = np.array([rgb[2], rgb[1], rgb[0]]) * 255.0
    return int(np.all(np.abs(screen.astype(float) - bgr) <= COLOUR_TOLERANCE, axis=2).sum())


class RvizScreenshot(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.frames = int(rospy.get_param("~frames", 40))
        cls.timeout = float(rospy.get_param("~timeout", 60.0))
        cls.screenshot = rospy.get_param("~screenshot", os.path.join(
            os.environ.get("ROS_HOME", os.path.expanduser("~/.ros")), "amcr_rviz.png"))
        cls.missing = [tool for tool in ("rviz", "Xvfb", "xwd") if not shutil.which(tool)]
        cls.dir = tempfile.mkdtemp(prefix="amcr_rviz_")
        cls.processes = []
        cls.lock = threading.Lock()
        cls.overlay = None
        cls.outline_colours = []
        cls.recognitions = 0
        cls.bridge = CvBridge()
        cls.image_pub = rospy.Publisher("/camera/image_raw", Image, queue_size=5)
        cls.info_pub = rospy.Publisher("/camera/camera_info", CameraInfo, queue_size=1, latch=True)
        rospy.Subscriber("/amcr/overlay", Image, cls.on_overlay, queue_size=2)
        rospy.Subscriber("/amcr/markers", MarkerArray, cls.on_markers, queue_size=10)
        rospy.Subscriber("/amcr/recognitions", Recognitions, cls.on_recognitions, queue_size=10)

    @classmethod
    def tearDownClass(cls):
        for process in reversed(cls.processes):
            process.terminate()
            try:
                process.wait(10)
            except subprocess.TimeoutExpired:
                process.kill()
        shutil.rmtree(cls.dir, ignore_errors=True)

    @classmethod
    def on_overlay(cls, msg):
        with cls.lock:
            cls.overlay = cls.bridge.imgmsg_to_cv2(msg, "mono8")

    @classmethod
    def on_markers(cls, msg):
        with cls.lock:
            cls.outline_colours = [(m.color.r, m.color.g, m.color.b) for m in msg.markers if m.ns == "outline"
                                   and m.action == m.ADD]

    @classmethod
    def on_recognitions(cls, msg):
        with cls.lock:
            cls.recognitions += 1 if msg.objects else 0

    def start_display(self):
        """Xvfb on a free display number; returns the DISPLAY value."""
        read, write = os.pipe()
        xvfb = subprocess.Popen(["Xvfb", "-displayfd", str(write), "-screen", "0", "%dx%dx24" % SCREEN,
                                 "-nolisten", "tcp"], pass_fds=(write,), stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL)
        os.close(write)
        self.processes.append(xvfb)
        with os.fdopen(read) as f:
            number = f.readline().strip()
        self.assertTrue(number.isdigit(), "Xvfb gave no display number")
        return ":" + number

    def grab(self, display):
        data = subprocess.run(["xwd", "-root", "-silent", "-display", display], check=True,
                              stdout=subprocess.PIPE, timeout=30).stdout
        return read_xwd(data)

    def test_overlay_and_markers_are_drawn(self):
        if self.missing:
            self.skipTest("not installed: %s (Debian: apt-get install rviz xvfb x11-apps)" % ", ".join(self.missing))
        package = rospkg.RosPack().get_path(PKG)
        sequence = os.path.join(self.dir, "sequence")
        subprocess.run(["/usr/bin/python3", os.path.join(package, "scripts", "make_demo_sequence"), "--out", sequence,
                        "--frames", str(self.frames), "--seed", "1"], check=True, stdout=subprocess.DEVNULL)
        rospy.wait_for_service("/amcr/load_prototypes", self.timeout)
        answer = rospy.ServiceProxy("/amcr/load_prototypes", LoadPrototypes)(os.path.join(sequence, "prototypes"))
        self.assertTrue(answer.success, answer.message)

        display = self.start_display()
        env = dict(os.environ, DISPLAY=display, LIBGL_ALWAYS_SOFTWARE="1")
        self.processes.append(subprocess.Popen(["rviz", "-d", os.path.join(package, "config", "amcr.rviz")], env=env,
                                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        # RViz is up once its Image display subscribes to the overlay (amcr.rviz names amcr/overlay).
        master = rosgraph.Master(rospy.get_name())

        def rviz_subscribed():
            subscribers = dict(master.getSystemState()[1]).get("/amcr/overlay", [])
            return any(node.startswith("/rviz") for node in subscribers)

        self.assertTrue(wait_for(rviz_subscribed, self.timeout, poll=0.5),
                        "RViz did not subscribe to /amcr/overlay within %.0f s" % self.timeout)
        time.sleep(3.0)  # its first frames drawn
        before = self.grab(display)

        self.assertTrue(wait_for(lambda: self.image_pub.get_num_connections() > 0, self.timeout),
                        "nobody subscribes to /camera/image_raw")
        # camera_info and metres_per_pixel (rviz_screenshot.test) give the objects their poses: markers.
        self.assertTrue(wait_for(lambda: self.info_pub.get_num_connections() > 0, self.timeout),
                        "nobody subscribes to /camera/camera_info")
        self.info_pub.publish(camera_info("camera"))
        frames = sorted(os.listdir(os.path.join(sequence, "frames")))
        stamp = rospy.Time(100.0)
        sent = 0
        deadline = time.monotonic() + self.timeout
        # Publish the sequence (again from its start when it ends) until objects are reported and
        # marked, and two seconds more.
        settled_at = None
        while time.monotonic() < deadline and not rospy.is_shutdown():
            image = cv2.imread(os.path.join(sequence, "frames", frames[sent % len(frames)]), cv2.IMREAD_GRAYSCALE)
            stamp += rospy.Duration(0.1)
            msg = self.bridge.cv2_to_imgmsg(image, "mono8")
            msg.header.stamp, msg.header.frame_id = stamp, "camera"
            self.image_pub.publish(msg)
            sent += 1
            time.sleep(0.1)
            with self.lock:
                ready = self.recognitions >= 5 and self.outline_colours and self.overlay is not None
            if ready and settled_at is None:
                settled_at = time.monotonic()
            if settled_at is not None and time.monotonic() - settled_at > 2.0:
                break
        with self.lock:
            self.assertIsNotNone(settled_at, "no object was reported and marked in %d frames (%d recognitions with "
                                 "objects, %d outline markers, overlay %s)" % (sent, self.recognitions,
                                 len(self.outline_colours), "received" if self.overlay is not None else "none"))
        # No more frames: RViz keeps showing the last overlay and markers, which the test has too.
        time.sleep(3.0)
        after = self.grab(display)
        with self.lock:
            overlay, colours = self.overlay.copy(), list(self.outline_colours)
        os.makedirs(os.path.dirname(os.path.abspath(self.screenshot)), exist_ok=True)
        cv2.imwrite(self.screenshot, after)

        match = best_match(after, overlay)
        self.assertGreaterEqual(match, MIN_OVERLAY_MATCH,
                                "the overlay image is not in RViz's Image panel (best correlation %.2f; %s)"
                                % (match, self.screenshot))
        drawn = max(colour_pixels(after, c) for c in colours)
        before_drawn = max(colour_pixels(before, c) for c in colours)
        self.assertGreaterEqual(drawn, MIN_MARKER_PIXELS,
                                "no outline marker in its track's colour in RViz (%d px; %s)" % (drawn, self.screenshot))
        self.assertLess(before_drawn, MIN_MARKER_PIXELS // 3,
                        "the track's colour was there before any report (%d px)" % before_drawn)


if __name__ == "__main__":
    rospy.init_node("rviz_screenshot", anonymous=True)
    rostest.rosrun(PKG, "rviz_screenshot", RvizScreenshot, sys.argv)
