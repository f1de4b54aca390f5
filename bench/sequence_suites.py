"""The benchmark suites' definitions (bench/make_sequences renders them): the frame size, the photos
behind the targets, per suite its memory, what it shows and how many sequences and frames (full /
--quick), the index of each suite in the seeds, and the constants of the suites that need their own
(the 1280x720 ones, the real-camera ones, `faint`, `copies`, `real-photos`). The module docstring of
bench/make_sequences says what each suite is."""

import numpy as np

WIDTH, HEIGHT = 640, 480
PHOTO_DIR = "/usr/share/doc/opencv-doc/examples/data"
PHOTOS = ["building.jpg", "fruits.jpg", "stuff.jpg", "home.jpg", "leuvenA.jpg", "leuvenB.jpg",
          "baboon.jpg", "board.jpg", "box_in_scene.png", "graf1.png", "graf3.png", "squirrel_cls.jpg",
          "messi5.jpg", "orange.jpg", "apple.jpg", "aero1.jpg", "aero3.jpg", "left01.jpg",
          "right01.jpg", "pic3.png", "blox.jpg", "butterfly.jpg", "ela_original.jpg", "smarties.png",
          "sudoku.png", "starry_night.jpg", "notes.png", "HappyFish.jpg", "rubberwhale1.png"]

# Suites: memory, what is shown, how many sequences and frames (full / quick).
SUITES = {
    "paper": dict(memory="paper17", show="same", sequences=(17, 3), frames=(80, 40)),
    "mpeg7-70": dict(memory="all70", show="same", sequences=(16, 1), frames=(60, 40)),
    "within-class": dict(memory="all70", show="other-instance", sequences=(16, 1), frames=(60, 40)),
    "similar": dict(memory="similar3", show="same", sequences=(9, 2), frames=(100, 40)),
    "clutter-only": dict(memory="paper17", show="none", sequences=(12, 2), frames=(80, 40)),
    "two-objects": dict(memory="paper17", show="two", sequences=(10, 2), frames=(80, 40)),
    # `paper`'s sequences (its seeds) with the target squashed: the suites differ in obliqueness only.
    "oblique": dict(memory="paper17", show="same", sequences=(17, 3), frames=(80, 40), oblique=(1.5, 3.0),
                    like="paper"),
    "real-camera": dict(memory="paper16+mire", show="real", sequences=(1, 1), frames=(501, 40)),
    # A second real sequence: one face of a dotted cube (bench/real_camera_cube.py).
    "real-camera-cube": dict(memory="paper16+cube", show="real", sequences=(1, 1), frames=(80, 40)),
    # One suite, evaluated once per memory (nested 3 < 17 < 35 < 70; the targets in the 3).
    "memory-growth": dict(memory="growth", show="same", sequences=(6, 2), frames=(60, 40),
                          memories=(3, 17, 35, 70)),
    # `paper` and `clutter-only` (their seeds, the same frames) resampled to 1280x720.
    "paper-hd": dict(memory="paper17", show="same", sequences=(17, 3), frames=(80, 40), like="paper", hd=True),
    "clutter-only-hd": dict(memory="paper17", show="none", sequences=(12, 2), frames=(80, 40), like="clutter-only",
                            hd=True),
    # 4-6 copies of one memory shape in view at once, moving together: each is to be reported.
    "copies": dict(memory="paper17", show="copies", sequences=(10, 2), frames=(80, 40), copies=(4, 6)),
    # A real photograph of six alike flat parts under a synthetic camera motion: each is to be reported.
    "real-photos": dict(memory="paper16+cut", show="photo", sequences=(3, 1), frames=(80, 40)),
    # Several instances per class in memory (prototypes/<class>/), the shown one held out of it.
    # `within-class` (its seeds, its draws) with the memory and the shown instance changed only.
    "within-class-1330": dict(memory="all70x19", show="held-out", sequences=(16, 1), frames=(60, 40),
                              like="within-class"),
    "within-class-85": dict(memory="paper17x5", show="held-out", sequences=(17, 1), frames=(60, 40)),
    # `paper` (its seeds) faint and out of focus: a quarter of the contrast about mid-grey, 2 px more blur.
    "faint": dict(memory="paper17", show="same", sequences=(17, 3), frames=(80, 40), like="paper",
                  faint=(0.25, 2.0)),
}
# Index of a suite in the seeds: the first six suites' sorted order, the later ones after them, so
# that adding a suite changes no sequence of the others.
SEED_INDEX = {name: i for i, name in enumerate(
    sorted(["paper", "mpeg7-70", "within-class", "similar", "clutter-only", "two-objects"])
    + ["oblique", "real-camera", "memory-growth", "paper-hd", "clutter-only-hd", "copies", "real-photos",
       "within-class-1330", "within-class-85", "real-camera-cube", "faint"])}
GROWTH_SEED = 14  # the fixed draw of the `memory-growth` memories, not --seed
HOLDOUT_SEED = 17  # the fixed draw of the held-out instances and the 5-instance memory, not --seed
# `paper-hd`, `clutter-only-hd`: the 640x480 frame scaled by HD_SCALE and centred in HD_SIZE.
HD_SIZE, HD_SCALE = (1280, 720), 1.5
HD_PAD = 107  # columns mirrored on each side of the 640x480 frame before resampling (covers 160 / 1.5)
# 640x480 image -> 1280x720 image (pixel centres): x' = 1.5 x + 0.25 + 160, y' = 1.5 y + 0.25.
HD_FROM_640 = np.array([[HD_SCALE, 0.0, (HD_SCALE - 1) / 2 + (HD_SIZE[0] - HD_SCALE * WIDTH) / 2],
                        [0.0, HD_SCALE, (HD_SCALE - 1) / 2 + (HD_SIZE[1] - HD_SCALE * HEIGHT) / 2]])
REAL_SEQUENCES = ["mire-2"]  # visp-images-data sequences of the `real-camera` suite, in order
# The `show="real"` suites: the truth's module (bench/<module>.py), its visp-images-data sequences in
# order, and the target's label (the drawn prototype's file name).
REAL_SUITES = {"real-camera": ("real_camera", REAL_SEQUENCES, "mire"),
               "real-camera-cube": ("real_camera_cube", ["cube"], "cube-face")}
FAINT_GREY = 128.0  # `faint`: the grey level the contrast is reduced about
COPY_GAP = 3  # `copies`: px between two copies at least (in the first frame; the motion keeps it within 6%)
# `real-photos`: opencv-doc photos of several alike flat parts, and the label of the part cut from each.
PART_PHOTOS = [("pca_test1.jpg", "pca-part")]
PART_MARGIN = 8  # px of background around the cut part in its prototype
PART_AREA_TOLERANCE = 0.25  # a component is an instance of the part when its area is within 25% of the part's
HALF_TURN_SYMMETRIC = 0.9  # the part counts as symmetric under a half turn when it overlaps its turned self this much
