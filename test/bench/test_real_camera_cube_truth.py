#!/usr/bin/python3
"""Tests of the real-camera-cube suite's truth (bench/real_camera_cube.py): on a face drawn in code
under a known homography, and on visp-images-data's cube (skipped with a message when it is absent).

  test/bench/test_real_camera_cube_truth.py [--xml FILE]   (JUnit XML for catkin; about 6 s)
"""
import os
import sys
import unittest

import cv2
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "..", "bench"))
import real_camera_cube as rcc  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
import test_real_camera_truth as mire_test  # noqa: E402  (its drawn view of a printed target)


def printed_view(h_proto, size=(384, 288), background=170, seed=3):
    """The face as on the cube (black square, white dots) on a light ground, under h_proto, with a
    camera's blur (the dots are only 6-10 px across)."""
    return mire_test.printed_view(h_proto, size, background, module=rcc, ink_grey=30.0, blur=0.6, seed=seed)


class DrawnFace(unittest.TestCase):
    # Faces of the sizes the sequence shows (64-80 px) and larger, turned every way: the labelling
    # comes from the face's own margins, so the corners must come back in the drawn order.
    VIEWS = ([[150, 90], [225, 95], [222, 168], [147, 162]],    # upright, about 75 px, mild perspective
             [[200, 60], [270, 130], [200, 200], [130, 130]],   # turned by 45 degrees, 99 px
             [[240, 200], [160, 205], [155, 125], [235, 118]],  # upside down (a half turn), 80 px
             [[100, 200], [95, 110], [185, 100], [195, 190]],   # a quarter turn, 90 px
             [[120, 80], [230, 95], [220, 170], [125, 160]])    # squashed to 1.4:1, oblique

    def test_corners_of_a_known_homography(self):
        corners = rcc.prototype_corners()
        for image_corners in self.VIEWS:
            h = cv2.getPerspectiveTransform(np.float32(corners), np.float32(image_corners))
            found, reason = rcc.detect(printed_view(h))
            self.assertIsNotNone(found, "%s: %s" % (image_corners, reason))
            error = np.max(np.linalg.norm(found - image_corners, axis=1))
            self.assertLess(error, 0.5, "corners %s, expected %s" % (found.round(2).tolist(), image_corners))

    def test_track_gives_the_homography(self):
        corners = rcc.prototype_corners()
        h = cv2.getPerspectiveTransform(np.float32(corners), np.float32(self.VIEWS[0]))
        truth = rcc.track([printed_view(h, seed=s) for s in range(3)])
        for t in truth:
            self.assertIn("homography", t, t.get("unknown"))
            # Every point of the face, not only its corners: the homography itself is recovered.
            grid = np.array([[x, y] for x in np.linspace(8, 248, 5) for y in np.linspace(8, 248, 5)])
            self.assertLess(np.max(np.linalg.norm(rcc.apply(t["homography"], grid) - rcc.apply(h, grid), axis=1)),
                            0.5)
            # The affine is the homography's best approximation over the face: within a pixel here.
            a = t["affine"]
            self.assertLess(np.max(np.linalg.norm(grid @ a[:, :2].T + a[:, 2] - rcc.apply(h, grid), axis=1)), 1.0)

    def test_no_face_no_truth(self):
        grey = np.full((288, 384), 170, np.uint8)
        cv2.rectangle(grey, (120, 80), (200, 160), 30, -1)  # a black square without dots
        cv2.circle(grey, (280, 150), 30, 240, -1)
        found, reason = rcc.detect(grey)
        self.assertIsNone(found)
        self.assertEqual(reason, "no ring of 12 dots")
        self.assertEqual(rcc.track([grey]), [{"unknown": "no ring of 12 dots"}])  # left unscored, with why

    def test_dots_without_the_face_no_truth(self):
        # The ring of 12 dots on a light ground, no black square around it: no edges, no truth.
        corners = rcc.prototype_corners()
        h = cv2.getPerspectiveTransform(np.float32(corners), np.float32(self.VIEWS[0]))
        grey = np.full((288, 384), 90, np.uint8)
        for x, y in rcc.apply(h, rcc.apply(rcc.square_to_prototype(), rcc.face_dots())):
            cv2.circle(grey, (int(round(x)), int(round(y))), 4, 235, -1)
        found, reason = rcc.detect(grey)
        self.assertIsNone(found)
        self.assertNotEqual(reason, "no ring of 12 dots")

    def test_prototype_is_white_shape_on_black(self):
        p = rcc.draw_prototype()
        self.assertEqual(p.shape[::-1], rcc.prototype_shape())
        self.assertEqual(p[0, 0], 0)
        w, h = rcc.prototype_shape()
        self.assertEqual(p[h // 2, w // 2], 255)  # the face's middle: no dot there
        for x, y in rcc.apply(rcc.square_to_prototype(), rcc.face_dots()):
            self.assertEqual(p[int(round(y)), int(round(x))], 0)  # the dots: holes
        self.assertEqual(len(rcc.SYMMETRIES), 4)


@unittest.skipUnless(os.path.isdir(os.path.join(rcc.VISP_DIR, "cube")),
                     "visp-images-data is not installed (apt-get install visp-images-data): no cube")
class Cube(unittest.TestCase):
    def test_truth_on_real_frames(self):
        files = rcc.sequence_files("cube")[30:60]
        greys = [cv2.imread(f, cv2.IMREAD_GRAYSCALE) for f in files]
        truth = rcc.track(greys)
        known = [(g, t) for g, t in zip(greys, truth) if "homography" in t]
        self.assertGreaterEqual(len(known), 0.8 * len(files))
        # The dots' centres map onto white, the face's inside (middle and between the dots and the
        # edges) onto black.
        dots = rcc.apply(rcc.square_to_prototype(), rcc.face_dots())
        inside = rcc.apply(rcc.square_to_prototype(), [[0.5, 0.5], [0.06, 0.5], [0.5, 0.06], [0.94, 0.5], [0.5, 0.94]])
        mire_test.check_known_frames(self, known, dots, inside)


if __name__ == "__main__":
    from junit_runner import run_module
    sys.exit(run_module(sys.modules[__name__], "test_real_camera_cube_truth"))
