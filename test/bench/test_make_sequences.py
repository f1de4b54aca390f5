#!/usr/bin/python3
"""Tests of bench/make_sequences: the suites of memory size and resolution (the `memory-growth`
memories, nested, each holding every target; `paper-hd`: the `paper` frames and truth, scaled to
1280x720); the suites of several instances in view (`copies`: apart and where the truth says;
`real-photos`: the six parts of pca_test1 where the truth says); the several-instance memories
(`within-class-1330`, `within-class-85`: the held-out instance in no memory, shown, and the
`within-class` frames elsewhere); `real-camera-cube` (its truth.json; a report of the face a quarter
turn round is at the right place); and bench/report.py's instance matching.
Needs the MPEG-7 silhouettes (AMCR_DATA, default ../shared/data from the checkout) and opencv-doc's
photos; skips with a message without them.

  test/bench/test_make_sequences.py [--xml FILE]   (JUnit XML for catkin; about 5 s)
"""
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
# bench/make_sequences's modules, beside it.
import sequence_files  # noqa: E402
import sequence_memories  # noqa: E402
import sequence_photos  # noqa: E402
import sequence_real_camera  # noqa: E402
import sequence_rendering  # noqa: E402
import sequence_suites  # noqa: E402
from sequence_suites import HEIGHT, SEED_INDEX, SUITES, WIDTH  # noqa: E402
# bench/report.py's instance matching and real-camera figures, and the cube's truth.
from report_instances import instance_sequence, instance_summary, match_instances  # noqa: E402
import report_real_camera  # noqa: E402
import real_camera_cube  # noqa: E402  bench/real_camera_cube.py

DATA = os.environ.get("AMCR_DATA", os.path.join(HERE, "..", "..", "..", "shared", "data"))
MPEG7 = os.path.join(DATA, "mpeg7")
HAVE_DATA = os.path.isfile(os.path.join(MPEG7, "apple-1.png")) and os.path.isdir(sequence_suites.PHOTO_DIR)


def render_truth(folder, name, suite, index, spec, memory, classes, frames):
    """Renders sequence `index` of `suite` (seed 1, `frames` frames) into folder/name; returns its truth."""
    path = os.path.join(folder, name)
    os.makedirs(path)
    sequence_rendering.render_sequence(path, suite, index, spec, memory, classes, MPEG7, frames, 1)
    with open(os.path.join(path, "truth.json")) as f:
        return json.load(f)


class SeedIndex(unittest.TestCase):
    def test_earlier_suites_keep_their_seeds(self):
        # The index of a suite enters every draw of its sequences: a new suite must not move one.
        self.assertEqual({s: SEED_INDEX[s] for s in ["clutter-only", "mpeg7-70", "paper", "similar", "two-objects",
                                                         "within-class", "oblique", "real-camera"]},
                         {"clutter-only": 0, "mpeg7-70": 1, "paper": 2, "similar": 3, "two-objects": 4,
                          "within-class": 5, "oblique": 6, "real-camera": 7})
        self.assertEqual([SEED_INDEX[s] for s in ["memory-growth", "paper-hd", "clutter-only-hd", "copies",
                                                      "real-photos"]], [8, 9, 10, 11, 12])
        self.assertEqual([SEED_INDEX[s] for s in ["within-class-1330", "within-class-85"]], [13, 14])
        self.assertEqual(SEED_INDEX["real-camera-cube"], 15)
        self.assertEqual(SEED_INDEX["faint"], 16)
        self.assertEqual(len(set(SEED_INDEX.values())), len(SEED_INDEX))
        self.assertEqual(set(SEED_INDEX), set(SUITES))

    def test_hd_map(self):
        # 640x480 pixel centres: the frame's edges -0.5 and 639.5 / 479.5 land on 159.5, 1119.5 / -0.5, 719.5.
        corners = sequence_suites.HD_FROM_640 @ np.array([[-0.5, 639.5], [-0.5, 479.5], [1.0, 1.0]])
        np.testing.assert_allclose(corners, [[159.5, 1119.5], [-0.5, 719.5]])


@unittest.skipUnless(HAVE_DATA, "no MPEG-7 silhouettes in %s (set AMCR_DATA) or no opencv-doc photos" % MPEG7)
class Suites(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.classes = sequence_memories.mpeg7_classes(MPEG7)

    def test_growth_memories_nested_and_hold_the_targets(self):
        memories = sequence_memories.growth_memories(self.classes)
        self.assertEqual([len(memories[n]) for n in (3, 17, 35, 70)], [3, 17, 35, 70])
        self.assertEqual(memories[17], sorted(sequence_memories.paper_classes(self.classes)))
        for small, large in ((3, 17), (17, 35), (35, 70)):
            self.assertTrue(set(memories[small]) <= set(memories[large]), (small, large))
        self.assertEqual(memories, sequence_memories.growth_memories(self.classes))  # fixed, not drawn anew
        spec = SUITES["memory-growth"]
        targets = sequence_memories.memory_of(spec["memory"], self.classes, MPEG7)
        self.assertEqual(sorted(targets), memories[3])
        with tempfile.TemporaryDirectory() as tmp:
            for index in range(3):
                truth = render_truth(tmp, "seq_%03d" % index, "memory-growth", index, spec, targets, self.classes, 2)
                for frame in truth["frames"]:
                    for o in frame["objects"]:
                        for n in spec["memories"]:
                            self.assertIn(o["label"], memories[n])

    def test_faint_frames_are_the_paper_ones_faint_and_defocused(self):
        memory = sequence_memories.memory_of("paper17", self.classes, MPEG7)
        with tempfile.TemporaryDirectory() as tmp:
            truths, frames = {}, {}
            for suite in ("paper", "faint"):
                truths[suite] = render_truth(tmp, suite, suite, 0, SUITES[suite], memory, self.classes, 3)
                frames[suite] = cv2.imread(os.path.join(tmp, suite, "frames", "frame_0002.png"),
                                           cv2.IMREAD_GRAYSCALE).astype(float)
        sharp, faint = truths["paper"], truths["faint"]
        self.assertEqual(sharp["frames"], faint["frames"])  # the same targets at the same poses
        self.assertEqual(faint["contrast"], 0.25)
        self.assertAlmostEqual(faint["blur_sigma"], np.hypot(sharp["blur_sigma"], 2.0), places=3)
        self.assertEqual(sharp["noise_sigma"], faint["noise_sigma"])
        # A quarter of the grey-level spread (the noise, drawn alike, widens it a little).
        spread = {k: np.percentile(f, 99) - np.percentile(f, 1) for k, f in frames.items()}
        self.assertLess(spread["faint"], 0.35 * spread["paper"])
        self.assertGreater(spread["faint"], 0.15 * spread["paper"])

    def test_hd_frames_and_truth_are_the_640_ones_scaled(self):
        memory = sequence_memories.memory_of("paper17", self.classes, MPEG7)
        with tempfile.TemporaryDirectory() as tmp:
            truths, frames = {}, {}
            for suite in ("paper", "paper-hd"):
                truths[suite] = render_truth(tmp, suite, suite, 0, SUITES[suite], memory, self.classes, 3)
                frames[suite] = cv2.imread(os.path.join(tmp, suite, "frames", "frame_0002.png"), cv2.IMREAD_GRAYSCALE)
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

    def test_copies_apart_and_where_the_truth_says(self):
        spec = SUITES["copies"]
        memory = sequence_memories.memory_of(spec["memory"], self.classes, MPEG7)
        with tempfile.TemporaryDirectory() as tmp:
            for index in range(2):
                path = os.path.join(tmp, "seq_%03d" % index)
                truth = render_truth(tmp, "seq_%03d" % index, "copies", index, spec, memory, self.classes, 12)
                labels = {o["label"] for frame in truth["frames"] for o in frame["objects"]}
                self.assertEqual(len(labels), 1)
                mask = cv2.imread(memory[labels.pop()], cv2.IMREAD_GRAYSCALE)
                for k in (0, 11):
                    objects = truth["frames"][k]["objects"]
                    self.assertTrue(4 <= len(objects) <= 6, len(objects))
                    grey = cv2.imread(os.path.join(path, "frames", "frame_%04d.png" % k), cv2.IMREAD_GRAYSCALE)
                    self.check_copies(grey, mask, [np.asarray(o["prototype_to_image"]) for o in objects],
                                      truth["inverted"])

    def check_copies(self, grey, mask, poses, inverted):
        shapes = [cv2.warpAffine(mask, p, (WIDTH, HEIGHT), flags=cv2.INTER_NEAREST) > 127 for p in poses]
        for i in range(len(shapes)):
            for j in range(i):
                self.assertFalse(np.any(shapes[i] & shapes[j]), "copies %d and %d overlap" % (j, i))
        disc = lambda r: cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
        anywhere = cv2.dilate(np.any(shapes, 0).astype(np.uint8), disc(3)) > 0
        for i, shape in enumerate(shapes):
            # Inside the copy (eroded) against a ring around it that no copy touches: the print's ink
            # against the clutter, darker (lighter when the print is inverted) by 25 grey levels at least.
            inside = cv2.erode(shape.astype(np.uint8), disc(2)) > 0
            ring = (cv2.dilate(shape.astype(np.uint8), disc(9)) > 0) & ~anywhere
            contrast = float(np.median(grey[ring])) - float(np.median(grey[inside]))
            self.assertGreater(-contrast if inverted else contrast, 25.0, "copy %d" % i)


@unittest.skipUnless(HAVE_DATA, "no MPEG-7 silhouettes in %s (set AMCR_DATA) or no opencv-doc photos" % MPEG7)
class HeldOut(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.classes = sequence_memories.mpeg7_classes(MPEG7)
        cls.held, cls.five = sequence_memories.holdout_instances(cls.classes)

    def written(self, kind):
        """The memory `kind` as main writes it: label -> sorted file names of its sub-directory."""
        with tempfile.TemporaryDirectory() as tmp:
            sequence_files.write_memory(tmp, sequence_memories.memory_of(kind, self.classes, MPEG7))
            self.assertEqual([f for f in os.listdir(tmp) if not os.path.isdir(os.path.join(tmp, f))], [])
            return {d: sorted(os.listdir(os.path.join(tmp, d))) for d in os.listdir(tmp)}

    def test_held_out_fixed_one_per_class(self):
        self.assertEqual(sorted(self.held), self.classes)
        self.assertTrue(all(1 <= n <= 20 for n in self.held.values()))
        # Fixed, not drawn anew.
        self.assertEqual((self.held, self.five), sequence_memories.holdout_instances(self.classes))

    def test_memory_1330_holds_19_per_class_none_held_out(self):
        memory = self.written("all70x19")
        self.assertEqual(sorted(memory), self.classes)
        for cls, files in memory.items():
            self.assertEqual(len(files), 19, cls)
            self.assertNotIn(sequence_memories.instance_name(cls, self.held[cls]) + ".png", files)
            self.assertEqual(set(files), {"%s-%d.png" % (cls, n) for n in range(1, 21) if n != self.held[cls]})

    def test_memory_85_holds_5_of_the_paper_classes_none_held_out(self):
        memory = self.written("paper17x5")
        self.assertEqual(sorted(memory), sorted(sequence_memories.paper_classes(self.classes)))
        for cls, files in memory.items():
            self.assertEqual(len(files), 5, cls)
            self.assertNotIn(sequence_memories.instance_name(cls, self.held[cls]) + ".png", files)
            self.assertEqual(files, sorted("%s-%d.png" % (cls, n) for n in self.five[cls]))

    def test_1330_shows_the_held_out_instance_over_the_within_class_frames(self):
        frames, truths = {}, {}
        with tempfile.TemporaryDirectory() as tmp:
            for suite, kind in (("within-class", "all70"), ("within-class-1330", "all70x19")):
                memory = sequence_memories.memory_of(kind, self.classes, MPEG7)
                truths[suite] = render_truth(tmp, suite, suite, 1, SUITES[suite], memory, self.classes, 2)
                frames[suite] = [cv2.imread(os.path.join(tmp, suite, "frames", "frame_%04d.png" % k),
                                            cv2.IMREAD_GRAYSCALE).astype(int) for k in range(2)]
        old, new = truths["within-class"], truths["within-class-1330"]
        label = new["targets"][0]["label"]
        self.assertEqual(label, old["targets"][0]["label"])  # the same class, the class as label
        held_file = sequence_memories.mpeg7_file(label, self.held[label])
        self.assertEqual(new["targets"][0]["source"], os.path.basename(held_file))
        held = cv2.imread(held_file, cv2.IMREAD_GRAYSCALE)
        self.assertEqual(new["prototype_sizes"], {label: list(held.shape[::-1])})
        for key in ("inverted", "blur_sigma", "noise_sigma", "distractors"):
            self.assertEqual(old[key], new[key], key)
        shown = cv2.imread(os.path.join(MPEG7, old["targets"][0]["source"]), cv2.IMREAD_GRAYSCALE)
        disc = lambda r: cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
        for k in range(2):
            [o_old], [o_new] = old["frames"][k]["objects"], new["frames"][k]["objects"]
            self.assertEqual(o_new["label"], label)
            place = lambda mask, o: cv2.warpAffine(mask, np.asarray(o["prototype_to_image"]), (WIDTH, HEIGHT),
                                                   flags=cv2.INTER_NEAREST) > 127
            target_new, target_old = place(held, o_new), place(shown, o_old)
            # Elsewhere than the two targets (and the blur's reach around them), the same pixels.
            near = cv2.dilate((target_new | target_old).astype(np.uint8), disc(7)) > 0
            differ = frames["within-class"][k] != frames["within-class-1330"][k]
            self.assertFalse(np.any(differ & ~near), "frame %d differs away from the targets" % k)
            self.assertTrue(np.any(differ), "frame %d: the same target" % k)
            # The held-out instance is printed where the truth says: its ink against a ring around it.
            grey = frames["within-class-1330"][k]
            inside = cv2.erode(target_new.astype(np.uint8), disc(2)) > 0
            ring = (cv2.dilate(target_new.astype(np.uint8), disc(9)) > 0) & \
                ~(cv2.dilate(target_new.astype(np.uint8), disc(3)) > 0)
            contrast = float(np.median(grey[ring])) - float(np.median(grey[inside]))
            self.assertGreater(-contrast if new["inverted"] else contrast, 25.0, "frame %d" % k)

    def test_85_shows_a_held_out_instance_of_a_paper_class(self):
        spec = SUITES["within-class-85"]
        memory = sequence_memories.memory_of(spec["memory"], self.classes, MPEG7)
        with tempfile.TemporaryDirectory() as tmp:
            truth = render_truth(tmp, "seq_000", "within-class-85", 0, spec, memory, self.classes, 1)
        [target] = truth["targets"]
        self.assertIn(target["label"], memory)
        held_file = sequence_memories.mpeg7_file(target["label"], self.held[target["label"]])
        self.assertEqual(target["source"], os.path.basename(held_file))
        self.assertEqual([o["label"] for o in truth["frames"][0]["objects"]], [target["label"]])


PHOTO = os.path.join(sequence_suites.PHOTO_DIR, sequence_suites.PART_PHOTOS[0][0])


@unittest.skipUnless(os.path.isfile(PHOTO), "no %s: install the Debian package opencv-doc" % PHOTO)
class RealPhotos(unittest.TestCase):
    def test_six_parts_where_the_truth_says(self):
        prototype, photo, instances = sequence_photos.cut_part(PHOTO)
        self.assertEqual(len(instances), 6)
        self.assertEqual(set(np.unique(prototype)), {0, 255})
        self.assertEqual(prototype[0, 0], 0)  # white shape on black, the centroid at the centre
        self.assertEqual(prototype[prototype.shape[0] // 2, prototype.shape[1] // 2], 255)
        with tempfile.TemporaryDirectory() as tmp:
            sequence_photos.render_photo(tmp, "real-photos", 0, 6, 1)
            with open(os.path.join(tmp, "truth.json")) as f:
                truth = json.load(f)
            self.assertTrue(truth["approximate"])
            for k in (0, 5):
                grey = cv2.imread(os.path.join(tmp, "frames", "frame_%04d.png" % k), cv2.IMREAD_GRAYSCALE)
                self.assertEqual(grey.shape, (HEIGHT, WIDTH))
                objects = truth["frames"][k]["objects"]
                self.assertEqual(len(objects), 6)
                threshold, _ = cv2.threshold(grey, 0, 255, cv2.THRESH_BINARY | cv2.THRESH_OTSU)
                centres = np.array([o["center"] for o in objects])
                for o, (x, y) in zip(objects, centres):
                    self.assertTrue(o["approximate"])
                    self.assertLess(grey[int(round(y)), int(round(x))], threshold)  # on a dark part
                    # The approximate affine lays the prototype on the part: mostly dark pixels.
                    shape = cv2.warpAffine(prototype, np.asarray(o["prototype_to_image"]), (WIDTH, HEIGHT),
                                           flags=cv2.INTER_NEAREST) > 127
                    self.assertGreater(np.mean(grey[shape] < threshold), 0.9)
                distances = np.linalg.norm(centres[:, None] - centres[None], axis=2) + 1e9 * np.eye(6)
                self.assertGreater(distances.min(), 30.0)  # six different parts


@unittest.skipUnless(os.path.isdir(os.path.join(real_camera_cube.VISP_DIR, "cube")),
                     "visp-images-data is not installed (apt-get install visp-images-data): no cube")
class RealCameraCube(unittest.TestCase):
    def test_truth_like_real_camera_and_a_turned_report_scores(self):
        with tempfile.TemporaryDirectory() as tmp:
            sequence_real_camera.render_real(tmp, "real-camera-cube", 0, 3, 1)
            with open(os.path.join(tmp, "truth.json")) as f:
                truth = json.load(f)
            self.assertEqual(len(os.listdir(os.path.join(tmp, "frames"))), 3)
        self.assertEqual(truth["targets"][0]["label"], "cube-face")
        self.assertEqual(truth["source"], "visp-images-data cube")
        self.assertEqual(len(truth["symmetries"]), 4)  # the four quarter turns
        self.assertEqual(truth["known_frames"], 3)
        frame = truth["frames"][0]["objects"][0]
        self.assertEqual(len(frame["homography"]), 3)
        # A report of the face turned by a quarter is at the right place: the symmetries count.
        w, h = truth["prototype_sizes"]["cube-face"]
        c = np.array([(w - 1) / 2.0, (h - 1) / 2.0])
        turn = np.array([[0.0, -1.0], [1.0, 0.0]])
        a = np.asarray(frame["prototype_to_image"])
        turned = np.hstack([a[:, :2] @ turn, (a[:, :2] @ (c - turn @ c) + a[:, 2]).reshape(2, 1)])
        rows = {0: {"objects": [{"label": "cube-face", "prototype_to_image": turned.tolist()}], "time_ms": 1.0}}
        m = report_real_camera.real_camera_sequence(truth, rows)
        self.assertEqual(m["right_share"], 1.0)
        self.assertLess(m["corner_error_median"], 1.0)


def copy_at(label, x, y, size=(100, 50)):
    """A truth object or a report: the prototype of `size` with its centre moved to (x, y)."""
    w, h = size
    return {"label": label, "prototype_to_image": [[1.0, 0.0, x - (w - 1) / 2.0], [0.0, 1.0, y - (h - 1) / 2.0]]}


class InstanceMatching(unittest.TestCase):
    sizes = {"cup": (100, 50), "dog": (100, 50)}

    def test_one_of_two_copies_found_is_half(self):
        truth = [copy_at("cup", 100, 100), copy_at("cup", 300, 100)]
        found = match_instances(truth, [copy_at("cup", 305, 104)], self.sizes)
        self.assertEqual(found, [None, 0])
        # The radius: max(10 px, 0.3 x 100 px) = 30 px; 31 px away finds nothing.
        self.assertEqual(match_instances(truth, [copy_at("cup", 331, 100)], self.sizes), [None, None])

    def test_a_wrong_label_does_not_count(self):
        truth = [copy_at("cup", 100, 100), copy_at("cup", 300, 100)]
        self.assertEqual(match_instances(truth, [copy_at("dog", 100, 100)], self.sizes), [None, None])

    def test_one_report_finds_one_instance(self):
        truth = [copy_at("cup", 100, 100), copy_at("cup", 120, 100)]  # both within 30 px of the report
        found = match_instances(truth, [copy_at("cup", 110, 100)], self.sizes)
        self.assertEqual(sorted(found, key=str), [0, None])
        # Two reports: each instance its own, even when the first report is nearer the second instance.
        found = match_instances(truth, [copy_at("cup", 118, 100), copy_at("cup", 135, 100)], self.sizes)
        self.assertEqual(found, [0, 1])

    def test_a_shape_reported_turned_is_at_its_centroid(self):
        # A brick drawn off the middle of its 100x50 image, its centroid at (20, 24.5), in the image at
        # (170.5, 100): reported turned by half a turn about its centroid, the image's middle lands at
        # (141, 100), 59 px from where the truth has it, the centroid in place.
        truth = [copy_at("cup", 200, 100)]
        turned = {"label": "cup", "prototype_to_image": [[-1.0, 0.0, 170.5 + 20], [0.0, -1.0, 100 + 24.5]]}
        self.assertEqual(match_instances(truth, [turned], self.sizes), [None])
        self.assertEqual(match_instances(truth, [turned], self.sizes, {"cup": (20.0, 24.5)}), [0])

    def test_sequence_figures_and_track_ids(self):
        truth = {"frames": [{"frame": k, "objects": [copy_at("cup", 100, 100), copy_at("cup", 300, 100)]}
                            for k in range(4)]}
        both = [copy_at("cup", 100, 100), copy_at("cup", 300, 100)]
        rows = {0: {"objects": both[:1]}, 1: {"objects": both}, 2: {"objects": both}, 3: {"objects": both}}
        s = instance_sequence(truth, rows, self.sizes)
        self.assertEqual(s["shares"], {1: 0.5, 2: 1.0, 3: 1.0, 4: 1.0})
        self.assertEqual(s["at"], 4)  # 60, or the last frame when shorter
        self.assertTrue(s["all_at"] and s["held"])
        m = instance_summary([s])
        self.assertAlmostEqual(m["found_share"], 3.5 / 4)
        self.assertNotIn("tracks_per_instance", m)  # no track ids reported: no fragmentation figure
        tracked = [dict(o, track_id=t, state="confirmed") for o, t in zip(both, (7, 8))]
        rows = {k: {"objects": tracked} for k in range(4)}
        rows[2] = {"objects": [dict(tracked[0], track_id=9), tracked[1]]}  # copy 0 lost and found again
        m = instance_summary([instance_sequence(truth, rows, self.sizes)])
        self.assertAlmostEqual(m["tracks_per_instance"], 1.5)
        self.assertEqual(m["states"], {"confirmed": 1.0})

    def test_held_needs_ninety_percent_after_frame_60(self):
        truth = {"frames": [{"frame": k, "objects": [copy_at("cup", 100, 100)]} for k in range(80)]}
        rows = {k: {"objects": [copy_at("cup", 100, 100)] if k < 60 or k % 5 else []} for k in range(80)}
        s = instance_sequence(truth, rows, self.sizes)  # found at frame 60, in 16 of the 20 after it
        self.assertTrue(s["all_at"])
        self.assertFalse(s["held"])


if __name__ == "__main__":
    from junit_runner import run_module
    sys.exit(run_module(sys.modules[__name__], "test_make_sequences"))
