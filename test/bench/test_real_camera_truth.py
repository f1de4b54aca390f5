#!/usr/bin/python3
"""Tests of the real-camera suite's truth (bench/real_camera.py): on a target drawn in code under a
known homography, and on visp-images-data's mire-2 (skipped with a message when it is absent).

  test/bench/test_real_camera_truth.py [--xml FILE]   (JUnit XML for catkin; about 5 s)
"""
import os
import sys
import unittest

import cv2
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "..", "bench"))
import real_camera as rc  # noqa: E402


def printed_view(h_proto, size=(384, 288), background=170, module=rc, ink_grey=25.0, blur=0.0, seed=3):
    """A target drawn like `module`'s prototype (mire: a black rectangle with a white disc and dots;
    real_camera_cube: a black face with white dots) on a light box, under h_proto: the shape in
    `ink_grey`, its holes white; a camera's blur of `blur` px, noise of 2 grey levels."""
    proto = module.draw_prototype().astype(np.float32) / 255.0  # 1 = the black print
    ink = cv2.warpPerspective(proto, h_proto, size, flags=cv2.INTER_LINEAR)
    inside = cv2.warpPerspective(np.ones_like(proto), h_proto, size, flags=cv2.INTER_NEAREST)
    w, h = module.prototype_shape()
    m = module.PROTOTYPE_MARGIN
    holes = np.zeros_like(proto)
    holes[m:h - m, m:w - m] = 1.0 - proto[m:h - m, m:w - m]
    white = cv2.warpPerspective(holes, h_proto, size, flags=cv2.INTER_LINEAR)
    grey = np.full(size[::-1], float(background), np.float32)
    grey = grey * (1 - ink) + ink_grey * ink
    grey = grey * (1 - white * inside) + 235.0 * white * inside
    if blur > 0:
        grey = cv2.GaussianBlur(grey, (0, 0), blur)
    return np.clip(grey + np.random.default_rng(seed).normal(0, 2, grey.shape), 0, 255).astype(np.uint8)


def check_known_frames(test, known, white, black):
    """On each (grey, truth) of `known`: the prototype points `white` map onto white and `black`
    onto black; the labelling does not turn (corner 0 stays near where it was)."""
    previous = None
    for grey, t in known:
        for x, y in rc.apply(t["homography"], white):
            test.assertGreater(grey[int(round(y)), int(round(x))], 150)
        for x, y in rc.apply(t["homography"], black):
            test.assertLess(grey[int(round(y)), int(round(x))], 90)
        c = t["corners"]
        if previous is not None:
            test.assertLess(np.linalg.norm(c[0] - previous[0]), 0.2 * np.linalg.norm(c[2] - c[0]))
        previous = c


class DrawnTarget(unittest.TestCase):
    def test_corners_of_a_known_homography(self):
        corners = rc.prototype_corners()
        for image_corners in ([[80, 60], [300, 75], [290, 230], [95, 215]],      # mild perspective
                              [[60, 120], [250, 40], [330, 150], [140, 250]],    # rotated, oblique
                              [[120, 90], [260, 100], [240, 190], [130, 170]]):  # small, squashed
            h = cv2.getPerspectiveTransform(np.float32(corners), np.float32(image_corners))
            found, reason = rc.detect(printed_view(h))
            self.assertIsNotNone(found, reason)
            # Half a turn is the target's symmetry: compare with the nearer labelling.
            error = min(np.max(np.linalg.norm(np.roll(found, -s, 0) - image_corners, axis=1)) for s in (0, 2))
            self.assertLess(error, 1.0, "corners %s, expected %s" % (found.round(2).tolist(), image_corners))

    def test_no_target_no_truth(self):
        grey = np.full((288, 384), 170, np.uint8)
        cv2.circle(grey, (190, 140), 40, 240, -1)
        found, _ = rc.detect(grey)
        self.assertIsNone(found)

    def test_prototype_is_white_shape_on_black(self):
        p = rc.draw_prototype()
        self.assertEqual(p.shape[::-1], rc.prototype_shape())
        self.assertEqual(p[0, 0], 0)
        w, h = rc.prototype_shape()
        self.assertEqual(p[h // 2, w // 2], 0)    # the disc: a hole
        self.assertEqual(p[h // 2, 12], 255)      # the rectangle


@unittest.skipUnless(os.path.isdir(os.path.join(rc.VISP_DIR, "mire-2")),
                     "visp-images-data is not installed (apt-get install visp-images-data): no mire-2")
class Mire2(unittest.TestCase):
    def test_truth_on_real_frames(self):
        files = rc.sequence_files("mire-2")[100:140]
        greys = [cv2.imread(f, cv2.IMREAD_GRAYSCALE) for f in files]
        truth = rc.track(greys)
        known = [(g, t) for g, t in zip(greys, truth) if "homography" in t]
        self.assertGreaterEqual(len(known), 0.6 * len(files))
        # The disc's and the dots' centres map onto white, the rectangle's inside onto black.
        check_known_frames(self, known, rc.apply(rc.square_to_prototype(), rc.MIRE["dots"] + [rc.MIRE["disc_center"]]),
                           rc.apply(rc.square_to_prototype(), [[0.5, 0.08], [0.08, 0.5]]))


if __name__ == "__main__":
    from junit_runner import run_module
    sys.exit(run_module(sys.modules[__name__], "test_real_camera_truth"))
