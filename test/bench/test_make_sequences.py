#!/usr/bin/python3
"""Tests of the issue-14 suites of bench/make_sequences: the `memory-growth` memories (nested, each
holding every target) and the 1280x720 suites (`paper-hd`: the `paper` frames and truth, scaled).
Needs the MPEG-7 silhouettes (AMCR_DATA, default ../shared/data from the checkout) and opencv-doc's
photos; skips with a message without them.

  test/bench/test_make_sequences.py [--xml FILE]   (JUnit XML for catkin; about 5 s)
"""
import importlib.machinery
import importlib.util
import json
import os
import sys
import tempfile
import unittest

import cv2
import numpy as np

HERE = os.path.dirname(os.path.realpath(__file__))
sys.path.insert(0, HERE)

_loader = importlib.machinery.SourceFileLoader("make_sequences", os.path.join(HERE, "..", "..", "bench", "make_sequences"))
_spec = importlib.util.spec_from_loader("make_sequences", _loader)
ms = importlib.util.module_from_spec(_spec)
_loader.exec_module(ms)

DATA = os.environ.get("AMCR_DATA", os.path.join(HERE, "..", "..", "..", "shared", "data"))
MPEG7 = os.path.join(DATA, "mpeg7")
HAVE_DATA = os.path.isfile(os.path.join(MPEG7, "apple-1.png")) and os.path.isdir(ms.PHOTO_DIR)


class SeedIndex(unittest.TestCase):
    def test_earlier_suites_keep_their_seeds(self):
        # The index of a suite enters every draw of its sequences: a new suite must not move one.
        self.assertEqual({s: ms.SEED_INDEX[s] for s in ["clutter-only", "mpeg7-70", "paper", "similar", "two-objects",
                                                         "within-class", "oblique", "real-camera"]},
                         {"clutter-only": 0, "mpeg7-70": 1, "paper": 2, "similar": 3, "two-objects": 4,
                          "within-class": 5, "oblique": 6, "real-camera": 7})
        self.assertEqual(len(set(ms.SEED_INDEX.values())), len(ms.SEED_INDEX))
        self.assertEqual(set(ms.SEED_INDEX), set(ms.SUITES))

    def test_hd_map(self):
        # 640x480 pixel centres: the frame's edges -0.5 and 639.5 / 479.5 land on 159.5, 1119.5 / -0.5, 719.5.
        corners = ms.HD_FROM_640 @ np.array([[-0.5, 639.5], [-0.5, 479.5], [1.0, 1.0]])
        np.testing.assert_allclose(corners, [[159.5, 1119.5], [-0.5, 719.5]])


@unittest.skipUnless(HAVE_DATA, "no MPEG-7 silhouettes in %s (set AMCR_DATA) or no opencv-doc photos" % MPEG7)
class Suites(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.classes = ms.mpeg7_classes(MPEG7)

    def test_growth_memories_nested_and_hold_the_targets(self):
        memories = ms.growth_memories(self.classes)
        self.assertEqual([len(memories[n]) for n in (3, 17, 35, 70)], [3, 17, 35, 70])
        self.assertEqual(memories[17], sorted(ms.paper_classes(self.classes)))
        for small, large in ((3, 17), (17, 35), (35, 70)):
            self.assertTrue(set(memories[small]) <= set(memories[large]), (small, large))
        self.assertEqual(memories, ms.growth_memories(self.classes))  # fixed, not drawn anew
        spec = ms.SUITES["memory-growth"]
        targets = ms.memory_of(spec["memory"], self.classes, MPEG7)
        self.assertEqual(sorted(targets), memories[3])
        with tempfile.TemporaryDirectory() as tmp:
            for index in range(3):
                path = os.path.join(tmp, "seq_%03d" % index)
                os.makedirs(path)
                ms.render_sequence(path, "memory-growth", index, spec, targets, self.classes, MPEG7, 2, 1)
                with open(os.path.join(path, "truth.json")) as f:
                    truth = json.load(f)
                for frame in truth["frames"]:
                    for o in frame["objects"]:
                        for n in spec["memories"]:
                            self.assertIn(o["label"], memories[n])

    def test_hd_frames_and_truth_are_the_640_ones_scaled(self):
        memory = ms.memory_of("paper17", self.classes, MPEG7)
        with tempfile.TemporaryDirectory() as tmp:
            truths, frames = {}, {}
            for suite in ("paper", "paper-hd"):
                path = os.path.join(tmp, suite)
                os.makedirs(path)
                ms.render_sequence(path, suite, 0, ms.SUITES[suite], memory, self.classes, MPEG7, 3, 1)
                with open(os.path.join(path, "truth.json")) as f:
                    truths[suite] = json.load(f)
                frames[suite] = cv2.imread(os.path.join(path, "frames", "frame_0002.png"), cv2.IMREAD_GRAYSCALE)
        low, high = truths["paper"], truths["paper-hd"]
        self.assertEqual(high["image_size"], [1280, 720])
        self.assertEqual(frames["paper-hd"].shape, (720, 1280))
        h = np.vstack([np.asarray(high["hd_from_640"]), [0, 0, 1]])
        for a, b in zip(low["frames"], high["frames"]):
            self.assertEqual([o["label"] for o in a["objects"]], [o["label"] for o in b["objects"]])
            for oa, ob in zip(a["objects"], b["objects"]):
                expected = (h @ np.vstack([oa["prototype_to_image"], [0, 0, 1]]))[:2]
                np.testing.assert_allclose(ob["prototype_to_image"], expected, atol=2e-6)
        for key in ("inverted", "blur_sigma", "noise_sigma", "targets"):
            self.assertEqual(low[key], high[key])
        # The pixels: the 1280x720 frame sampled back at the 640x480 pixel centres is that frame
        # (up to the two bilinear steps and rounding).
        ys, xs = np.mgrid[0:480, 0:640].astype(np.float32)
        back = cv2.remap(frames["paper-hd"], xs * 1.5 + 160.25, ys * 1.5 + 0.25, cv2.INTER_LINEAR)
        self.assertLess(np.mean(np.abs(back.astype(float) - frames["paper"])), 5.0)


if __name__ == "__main__":
    from junit_runner import run_module
    sys.exit(run_module(sys.modules[__name__], "test_make_sequences"))
