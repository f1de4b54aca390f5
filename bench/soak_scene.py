"""The input of the soak test (bench/soak_driver): a prototype folder, a folder that must be refused,
and a loop of frames in which a known shape moves over a real photo.

Everything comes from Debian's opencv-doc (as scripts/make_demo_sequence): the silhouettes of
shape_sample/ and a photo of examples/data/. The frames are rendered once, before the stream starts,
so that publishing them costs only the copy into the message.
"""

import math
import os
import shutil

import cv2
import numpy as np

SHAPES = "/usr/share/doc/opencv-doc/examples/shape/data/shape_sample"
PHOTOS = "/usr/share/doc/opencv-doc/examples/data"
PHOTO = "building.jpg"
# The memory: label -> silhouette in SHAPES (the three of scripts/make_demo_sequence).
PROTOTYPES = {"bat": "3.png", "bird": "5.png", "car": "7.png"}
# Static distractors of other classes (never a twin of a prototype).
DISTRACTORS = ["1.png", "11.png", "16.png"]
# Longer side of the target in the frames, px: the size at which the demo's 640x480 scenes are
# recognized (the same scene scaled up to 1280x720 was not, when the filter still worked on the
# whole frame rather than on the input reduced to working_resolution).
TARGET_SIZE = 200.0
# Path speed of the target, px per frame, and the amplitude of its turning, rad.
SPEED = 4.0
TURN = 0.6


def read_grey(path):
    image = cv2.imread(path, cv2.IMREAD_GRAYSCALE)
    if image is None:
        raise RuntimeError("cannot read %s (is the Debian package opencv-doc installed?)" % path)
    return image


def write_prototypes(folder):
    """Copies the three silhouettes into `folder` as <label>.png; returns the labels."""
    os.makedirs(folder, exist_ok=True)
    for label, name in PROTOTYPES.items():
        shutil.copyfile(os.path.join(SHAPES, name), os.path.join(folder, label + ".png"))
    return sorted(PROTOTYPES)


LARGE_MEMORY = 70  # prototypes of the folder a reload of a larger memory loads


def random_silhouette(rng, size=200):
    """A white polygon on black, its corners at random radii and even angles: a shape unlike the
    prototypes, for filling a larger memory."""
    corners = int(rng.integers(5, 12))
    angles = np.sort(rng.uniform(0.0, 2.0 * math.pi, corners))
    radii = rng.uniform(0.35, 0.9, corners) * size * 0.45
    points = np.stack([size / 2 + radii * np.cos(angles), size / 2 + radii * np.sin(angles)], axis=1)
    image = np.zeros((size, size), np.uint8)
    cv2.fillPoly(image, [np.round(points).astype(np.int32)], 255)
    return image


def write_large_folder(folder, seed=1):
    """The three silhouettes and drawn ones, LARGE_MEMORY in all: the memory of the reload that
    builds as long as a first start of a mid-sized memory does."""
    write_prototypes(folder)
    rng = np.random.default_rng(seed)
    for i in range(LARGE_MEMORY - len(PROTOTYPES)):
        cv2.imwrite(os.path.join(folder, "drawn-%02d.png" % i), random_silhouette(rng))
    return LARGE_MEMORY


def write_unusable_folder(folder):
    """A folder that ~load_prototypes must refuse: a truncated PNG and a text file, no usable image."""
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(SHAPES, PROTOTYPES["bat"]), "rb") as f:
        head = f.read(40)
    with open(os.path.join(folder, "truncated.png"), "wb") as f:
        f.write(head)
    with open(os.path.join(folder, "notes.txt"), "w") as f:
        f.write("not an image\n")


def affine(center, angle, scale, proto_size):
    """2x3 prototype->image map: the prototype's centre goes to `center`, turned and scaled."""
    pw, ph = proto_size
    c, s = math.cos(angle) * scale, math.sin(angle) * scale
    linear = np.array([[c, -s], [s, c]])
    offset = np.asarray(center, dtype=np.float64) - linear @ np.array([(pw - 1) / 2.0, (ph - 1) / 2.0])
    return np.hstack([linear, offset.reshape(2, 1)])


def paint(frame, mask, matrix, darkness):
    """Prints the silhouette `mask` (white on black) dark into the float image `frame`."""
    height, width = frame.shape
    alpha = cv2.warpAffine(mask.astype(np.float32) / 255.0, matrix, (width, height), flags=cv2.INTER_LINEAR)
    frame *= 1.0 - alpha
    frame += alpha * darkness


def background(width, height):
    """The photo, grey, covering width x height, contrast reduced to about 115..215 (clutter)."""
    photo = read_grey(os.path.join(PHOTOS, PHOTO))
    h, w = photo.shape
    scale = max(width / w, height / h)
    photo = cv2.resize(photo, (max(width, round(w * scale)), max(height, round(h * scale))),
                       interpolation=cv2.INTER_AREA if scale < 1.0 else cv2.INTER_LINEAR)
    y0, x0 = (photo.shape[0] - height) // 2, (photo.shape[1] - width) // 2
    return 115.0 + photo[y0:y0 + height, x0:x0 + width].astype(np.float32) * (100.0 / 255.0)


def clutter(width, height, rng):
    """The static part: photo, three distractor silhouettes left and right of the target's path, lines."""
    image = background(width, height)
    places = [(0.14, 0.3), (0.86, 0.7), (0.85, 0.22)]
    for name, (fx, fy) in zip(DISTRACTORS, places):
        mask = read_grey(os.path.join(SHAPES, name))
        scale = rng.uniform(120.0, 170.0) / max(mask.shape)
        matrix = affine((fx * width, fy * height), rng.uniform(-math.pi, math.pi), scale, mask.shape[::-1])
        paint(image, mask, matrix, rng.uniform(25.0, 60.0))
    for _ in range(4):
        p0 = (int(rng.integers(0, width)), int(rng.integers(0, height)))
        p1 = (int(rng.integers(0, width)), int(rng.integers(0, height)))
        cv2.line(image, p0, p1, float(rng.uniform(30.0, 90.0)), int(rng.integers(1, 4)), lineType=cv2.LINE_AA)
    return image


def render_loop(width, height, count, target, seed=1):
    """`count` mono8 frames (numpy uint8, height x width) of one closed loop: the target goes round a
    circle about the image centre at SPEED px per frame, turning back and forth by TURN rad, so that
    the last frame leads into the first. Returns (frames, per-frame 2x3 prototype->image affines)."""
    rng = np.random.default_rng(seed)
    static = clutter(width, height, rng)
    mask = read_grey(os.path.join(SHAPES, PROTOTYPES[target]))
    scale = TARGET_SIZE / max(mask.shape)
    radius = min(SPEED * count / (2.0 * math.pi), 0.25 * min(width, height))
    darkness = 35.0
    frames, poses = [], []
    for k in range(count):
        phase = 2.0 * math.pi * k / count
        center = (0.5 * width + radius * math.cos(phase), 0.5 * height + radius * math.sin(phase))
        matrix = affine(center, 0.3 + TURN * math.sin(phase), scale, mask.shape[::-1])
        frame = static.copy()
        paint(frame, mask, matrix, darkness)
        frame += rng.normal(0.0, 4.0, frame.shape).astype(np.float32)
        frames.append(np.clip(np.rint(frame), 0, 255).astype(np.uint8))
        poses.append(matrix)
    return frames, poses
