#!/usr/bin/python3
"""Tests of bench/sampled_benchmark's draws (bench/sampling.py): a draw is the same files for the same
seed and another memory for another draw index; a drawn real-camera target stays within +-5% of the
measured geometry (a nearly square one is sometimes a plain square), and the measured geometry drawn
unperturbed is the real suites' own prototype; the truth of a drawn real-camera target maps the drawn
prototype's corners onto the real target's corners in the image; `real-photos-clean` adds no noise.
Needs the MPEG-7 silhouettes (AMCR_DATA, default ../shared/data from the checkout) and opencv-doc's
photos, and for the real cameras visp-images-data; skips with a message without them.

  test/bench/test_sampled_benchmark.py [--xml FILE]   (JUnit XML for catkin; about 10 s)
"""
import filecmp
import json
import os
import sys
import tempfile
import unittest

import cv2
import numpy as np

HERE = os.path.dirname(os.path.realpath(__file__))
sys.path.insert(0, HERE)

sys.path.insert(0, os.path.join(HERE, "..", "..", "bench"))
# bench/sampled_benchmark's draws and the modules of bench/make_sequences they use.
import printed_target  # noqa: E402
import sampling  # noqa: E402
import sequence_memories  # noqa: E402
import sequence_real_camera  # noqa: E402
import sequence_suites  # noqa: E402

DATA = os.environ.get("AMCR_DATA", os.path.join(HERE, "..", "..", "..", "shared", "data"))
MPEG7 = os.path.join(DATA, "mpeg7")
HAVE_DATA = os.path.isfile(os.path.join(MPEG7, "apple-1.png")) and os.path.isdir(sequence_suites.PHOTO_DIR)
HAVE_VISP = os.path.isdir(printed_target.VISP_DIR)
REAL = ["real-camera-sampled", "real-camera-cube-sampled"]


def same_tree(a, b):
    """Whether two folders hold the same files, byte for byte."""
    cmp = filecmp.dircmp(a, b)
    if cmp.left_only or cmp.right_only or cmp.funny_files:
        return False
    _, mismatch, errors = filecmp.cmpfiles(a, b, cmp.common_files, shallow=False)
    return not mismatch and not errors and all(same_tree(os.path.join(a, d), os.path.join(b, d))
                                               for d in cmp.common_dirs)


@unittest.skipUnless(HAVE_DATA, "no MPEG-7 silhouettes in %s (set AMCR_DATA) or no opencv-doc photos" % MPEG7)
class Draws(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.classes = sequence_memories.mpeg7_classes(MPEG7)

    def render(self, folder, suite, k, counts=(2, 3)):
        return sampling.render_draw(folder, suite, k, 1, MPEG7, self.classes, 1, counts)

    def test_a_draw_is_the_same_files_for_the_same_seed(self):
        with tempfile.TemporaryDirectory() as tmp:
            for suite in ("paper-sampled", "real-photos-sampled"):
                first, second = os.path.join(tmp, suite, "a"), os.path.join(tmp, suite, "b")
                self.render(first, suite, 1)
                self.render(second, suite, 1)
                self.assertTrue(os.path.exists(os.path.join(first, "draw.json")))
                self.assertTrue(same_tree(first, second), suite)

    def test_draw_indices_draw_other_memories(self):
        for suite in ("paper-sampled", "clutter-only-sampled", "real-photos-sampled", "real-camera-sampled"):
            memories = [sampling.plan_draw(suite, k, 1, self.classes, 2)["memory"] for k in range(4)]
            size = sampling.SAMPLED_SUITES[suite]["memory"]
            for memory in memories:
                self.assertEqual(len(memory), size)
                self.assertTrue(set(memory) <= set(self.classes))
            self.assertEqual(len({tuple(m) for m in memories}), 4, suite)
            self.assertEqual(memories[0], sampling.plan_draw(suite, 0, 1, self.classes, 2)["memory"])
            self.assertNotEqual(memories[0], sampling.plan_draw(suite, 0, 2, self.classes, 2)["memory"])
        # The targets shown are in the memory, 17 prototypes in all.
        with tempfile.TemporaryDirectory() as tmp:
            record = self.render(tmp, "paper-sampled", 0)
            self.assertEqual(len(record["memory"]), 17)
            for sequence in record["sequences_rendered"]:
                self.assertTrue(set(sequence["targets"]) <= set(record["memory"]))
                self.assertGreaterEqual(sequence["noise_scale"], 0.0)
                self.assertLessEqual(sequence["noise_scale"], 1.0)

    def test_clean_photos_have_no_added_noise(self):
        with tempfile.TemporaryDirectory() as tmp:
            clean = self.render(os.path.join(tmp, "clean"), "real-photos-clean", 0, (1, 2))
            noisy = self.render(os.path.join(tmp, "noisy"), "real-photos-sampled", 0, (1, 2))
            self.assertEqual(clean["memory"], noisy["memory"])  # the same draw, the noise aside
            truths, frames = {}, {}
            for name in ("clean", "noisy"):
                with open(os.path.join(tmp, name, "seq_000", "truth.json")) as f:
                    truths[name] = json.load(f)
                frames[name] = cv2.imread(os.path.join(tmp, name, "seq_000", "frames", "frame_0000.png"),
                                          cv2.IMREAD_GRAYSCALE)
        self.assertEqual(truths["clean"]["noise_sigma"], 0.0)
        self.assertGreater(truths["noisy"]["noise_sigma"], 0.0)
        self.assertEqual(truths["clean"]["photo_to_image_first"], truths["noisy"]["photo_to_image_first"])
        # The clean frame is the photo under the camera map, rounded: nothing added.
        name = sequence_suites.PART_PHOTOS[0][0]
        photo = cv2.imread(os.path.join(sequence_suites.PHOTO_DIR, name), cv2.IMREAD_GRAYSCALE).astype(np.float32)
        camera = np.asarray(truths["clean"]["photo_to_image_first"], dtype=np.float64)
        expected = cv2.warpAffine(photo, camera, (sequence_suites.WIDTH, sequence_suites.HEIGHT),
                                  flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
        expected = np.clip(np.rint(expected), 0, 255).astype(np.uint8)
        # photo_to_image_first is rounded to 6 decimals in truth.json, and the warp samples at 1/32 px:
        # a few pixels on edges may differ; noise would change most of them.
        self.assertLess(np.mean(expected != frames["clean"]), 0.005)
        self.assertGreater(np.mean(expected != frames["noisy"]), 0.3)


@unittest.skipUnless(HAVE_DATA and HAVE_VISP, "no MPEG-7 silhouettes in %s (set AMCR_DATA), no opencv-doc photos "
                     "or no %s (Debian's visp-images-data)" % (MPEG7, printed_target.VISP_DIR))
class RealTargets(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.classes = sequence_memories.mpeg7_classes(MPEG7)

    def test_measured_target_draws_the_suites_own_prototype(self):
        for suite in REAL:
            module, _ = sequence_real_camera.real_truth(sampling.SAMPLED_SUITES[suite]["like"])
            target = sampling.measured_target(sampling.SAMPLED_SUITES[suite]["like"])
            self.assertEqual(tuple(target["shape"]), tuple(module.prototype_shape()))
            np.testing.assert_array_equal(sampling.draw_target(target), module.draw_prototype())
            np.testing.assert_allclose(target["square_to_prototype"], module.square_to_prototype())

    def test_drawn_target_within_five_percent_of_the_measured(self):
        for suite in REAL:
            measured = sampling.measured_target(sampling.SAMPLED_SUITES[suite]["like"])
            squares = 0
            for k in range(200):
                drawn, factors = sampling.perturb_target(np.random.default_rng([9, k]), measured)
                squares += factors["square"]
                if factors["square"]:
                    self.assertEqual(drawn["aspect"], 1.0)
                self.assertLessEqual(abs(drawn["aspect"] / measured["aspect"] - 1), 0.05 + 1e-12)
                for ((x, y), r), ((mx, my), mr) in zip(drawn["holes"], measured["holes"]):
                    for value, reference in ((x, mx), (y, my), (r, mr)):
                        self.assertLessEqual(abs(value / reference - 1), 0.05 + 1e-12)
                # The drawn image: its target's aspect within 5% too (up to a pixel of rounding).
                w, h = (v - 2 * printed_target.PROTOTYPE_MARGIN for v in drawn["shape"])
                self.assertLessEqual(abs((w / h) / measured["aspect"] - 1), 0.05 + 1.0 / h)
            if abs(measured["aspect"] - 1) <= 0.05:  # the cube's face: a plain square about 1 time in 4
                self.assertTrue(20 < squares < 80, squares)
            else:
                self.assertEqual(squares, 0)
        plan = sampling.plan_draw("real-camera-cube-sampled", 0, 1, self.classes, 1)
        self.assertNotEqual(plan["target"]["drawn"]["holes"], plan["target"]["measured"]["holes"])

    def test_drawn_truth_maps_the_drawn_corners_onto_the_real_ones(self):
        for suite, frames in (("real-camera-cube-sampled", 3), ("real-camera-sampled", 12)):
            like = sampling.SAMPLED_SUITES[suite]["like"]
            module, label = sequence_real_camera.real_truth(like)
            with tempfile.TemporaryDirectory() as tmp:
                record = sampling.render_draw(tmp, suite, 0, 1, MPEG7, self.classes, 1, (1, frames))
                with open(os.path.join(tmp, "seq_000", "truth.json")) as f:
                    truth = json.load(f)
                drawn = cv2.imread(os.path.join(tmp, "prototypes", label + ".png"), cv2.IMREAD_GRAYSCALE)
            self.assertEqual(truth["prototype_sizes"][label], [drawn.shape[1], drawn.shape[0]])
            self.assertEqual(record["target"]["drawn"]["shape"], [drawn.shape[1], drawn.shape[0]])
            files = module.sequence_files(sequence_suites.REAL_SUITES[like][1][0])[:frames]
            found = module.track([cv2.imread(f, cv2.IMREAD_GRAYSCALE) for f in files])
            known = [k for k, t in enumerate(found) if "corners" in t]
            self.assertTrue(known, suite)
            for k in known:
                h = np.asarray(truth["frames"][k]["objects"][0]["homography"])
                corners = printed_target.apply(h, np.asarray(truth["score_points"]))
                self.assertLess(np.max(np.linalg.norm(corners - found[k]["corners"], axis=1)), 0.5, (suite, k))
                # The drawn prototype's corners are its own, not the measured one's.
                np.testing.assert_allclose(truth["score_points"], printed_target.unit_square_corners(
                    np.asarray(record["target"]["drawn"]["square_to_prototype"])), atol=1e-3)
                # The best affine: the measured target's, composed with the map of the drawn
                # prototype's pixels onto the measured one's.
                measured_from_drawn = module.square_to_prototype() @ np.linalg.inv(
                    np.asarray(record["target"]["drawn"]["square_to_prototype"]))
                affine = np.asarray(truth["frames"][k]["objects"][0]["prototype_to_image"])
                points = np.hstack([np.asarray(truth["score_points"]), np.ones((4, 1))])
                np.testing.assert_allclose(points @ affine.T, points @ (found[k]["affine"] @ measured_from_drawn).T,
                                           atol=2e-3)


if __name__ == "__main__":
    from junit_runner import run_module
    sys.exit(run_module(sys.modules[__name__], "test_sampled_benchmark"))
