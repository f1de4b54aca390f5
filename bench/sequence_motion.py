"""Where the targets of the rendered suites are and how they move: the prototype->image affine of a
pose, a target's own smooth motion (Mover) inside its box, and the copies of `copies`, placed apart
in the first frame and moved together (CommonMotion)."""

import math

import cv2
import numpy as np

from sequence_suites import COPY_GAP, HEIGHT, WIDTH


def affine(center, angle, scale, aspect, shear, proto_size, squash=None):
    """2x3 prototype->image map: prototype centre -> `center`; shear, anisotropic scale, rotation;
    then, when `squash` = (anisotropy, axis angle), an oblique view: a squash by sqrt(anisotropy)
    along the image axis at `axis` and a stretch by it across (area kept)."""
    pw, ph = proto_size
    c, s = math.cos(angle), math.sin(angle)
    linear = np.array([[c, -s], [s, c]]) @ np.diag([scale * aspect, scale / aspect]) \
        @ np.array([[1.0, shear], [0.0, 1.0]])
    if squash is not None:
        k, axis = math.sqrt(squash[0]), squash[1]
        r = np.array([[math.cos(axis), -math.sin(axis)], [math.sin(axis), math.cos(axis)]])
        linear = r @ np.diag([1.0 / k, k]) @ r.T @ linear
    proto_center = np.array([(pw - 1) / 2.0, (ph - 1) / 2.0])
    offset = np.asarray(center, dtype=np.float64) - linear @ proto_center
    return np.hstack([linear, offset.reshape(2, 1)])


class Mover:
    """A target's smooth motion: drift with a gently curving heading, reflected inside `box`;
    steady spin; scale, aspect and shear breathing slowly around their random start values."""

    def __init__(self, rng, size, box, oblique=None, squash_rng=None):
        pw, ph = size
        self.size = size
        self.box = box  # (x0, y0, x1, y1) the centre stays in
        longer = rng.uniform(120.0, 240.0)
        self.scale = longer / max(pw, ph)
        self.aspect = math.exp(rng.uniform(-0.2, 0.2))  # anisotropic scale up to about 1.5:1
        self.shear = rng.uniform(-0.3, 0.3)
        self.angle = rng.uniform(-math.pi, math.pi)  # any rotation
        self.spin = math.radians(rng.uniform(0.3, 1.5)) * rng.choice([-1.0, 1.0])
        self.heading = rng.uniform(0.0, 2.0 * math.pi)
        self.speed = rng.uniform(0.5, 2.5)
        self.phase = rng.uniform(0.0, 2.0 * math.pi)
        x0, y0, x1, y1 = box
        self.position = np.array([rng.uniform(x0, x1), rng.uniform(y0, y1)])
        self.squash = None
        if oblique is not None:
            self.squash = (squash_rng.uniform(*oblique), squash_rng.uniform(0.0, math.pi))
            self.aspect, self.shear = 1.0, 0.0  # the obliqueness is all in the squash

    def pose(self, k):
        direction = self.heading + 0.6 * math.sin(2.0 * math.pi * k / 90.0 + self.phase)
        step = self.speed * np.array([math.cos(direction), math.sin(direction)])
        x0, y0, x1, y1 = self.box
        nxt = self.position + step
        if not x0 <= nxt[0] <= x1:
            self.heading = math.pi - self.heading
            step[0] = -step[0]
        if not y0 <= nxt[1] <= y1:
            self.heading = -self.heading
            step[1] = -step[1]
        if k > 0:
            self.position = self.position + step
        breathe = math.sin(2.0 * math.pi * k / 120.0 + self.phase)
        if self.squash is not None:
            return affine(self.position, self.angle + self.spin * k, self.scale * (1 + 0.08 * breathe),
                          1.0, 0.0, self.size, self.squash)
        return affine(self.position, self.angle + self.spin * k, self.scale * (1 + 0.08 * breathe),
                      self.aspect, self.shear + 0.05 * breathe, self.size)


def target_box(rng, count, index):
    """Where a target's centre may move: the middle of the frame, or its half for two targets."""
    if count == 1:
        return (WIDTH * 0.3, HEIGHT * 0.35, WIDTH * 0.7, HEIGHT * 0.65)
    half = WIDTH / 2
    return (index * half + half * 0.35, HEIGHT * 0.35, index * half + half * 0.65, HEIGHT * 0.65)


class CommonMotion:
    """`copies`: the motion every copy shares (a tray of prints moved under the camera; the clutter
    stays): a drift of up to 20 px along two slow sinusoids, a steady spin of 0.05-0.15 degrees per
    frame and a scale breathing by up to 5%, about the frame's centre."""

    def __init__(self, rng):
        self.amplitude = rng.uniform(8.0, 20.0, 2)
        self.period = rng.uniform(90.0, 160.0, 2)
        self.phase = rng.uniform(0.0, 2.0 * math.pi, 2)
        self.spin = math.radians(rng.uniform(0.05, 0.15)) * rng.choice([-1.0, 1.0])
        self.breathe = rng.uniform(0.02, 0.05)

    def matrix(self, k):
        """3x3 map of frame 0's image onto frame k's."""
        shift = self.amplitude * (np.sin(2.0 * math.pi * k / self.period + self.phase) - np.sin(self.phase))
        scale = 1.0 + self.breathe * math.sin(2.0 * math.pi * k / 120.0)
        c, s = math.cos(self.spin * k), math.sin(self.spin * k)
        centre = np.array([(WIDTH - 1) / 2.0, (HEIGHT - 1) / 2.0])
        linear = scale * np.array([[c, -s], [s, c]])
        return np.vstack([np.hstack([linear, (centre + shift - linear @ centre).reshape(2, 1)]), [0.0, 0.0, 1.0]])


class Copy:
    """One copy of `copies`: its own pose in frame 0 (`placed`), then the common motion."""

    def __init__(self, placed, motion):
        self.placed = np.vstack([placed, [0.0, 0.0, 1.0]])
        self.motion = motion
        centre = placed[:, 2]  # only for keeping the distractors away; any point near the copy does
        self.box = (centre[0], centre[1], centre[0], centre[1])

    def pose(self, k):
        return (self.motion.matrix(k) @ self.placed)[:2]


def place_copies(rng, mask, count, motion, frames):
    """2x3 poses of `count` copies of `mask` in frame 0: any rotation, the longer side 90-150 px,
    aspect and shear as the distractors'; drawn again until the copy stays inside the frame (2 px
    margin) in every frame under `motion` and keeps COPY_GAP px from the copies placed before (a few
    may nearly touch). A copy that finds no place in 300 draws is tried smaller (x 0.9)."""
    ph, pw = mask.shape
    box = np.array([[0, 0, 1], [pw - 1, 0, 1], [pw - 1, ph - 1, 1], [0, ph - 1, 1]], dtype=np.float64)
    motions = [motion.matrix(k) for k in range(frames)]
    taken = np.zeros((HEIGHT, WIDTH), np.uint8)
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * COPY_GAP + 1, 2 * COPY_GAP + 1))
    poses = []
    shrink = 1.0
    while len(poses) < count:
        for _ in range(300):
            matrix = affine((rng.uniform(0, WIDTH), rng.uniform(0, HEIGHT)), rng.uniform(-math.pi, math.pi),
                            shrink * rng.uniform(90.0, 150.0) / max(pw, ph), math.exp(rng.uniform(-0.2, 0.2)),
                            rng.uniform(-0.3, 0.3), (pw, ph))
            corners = np.concatenate([(m @ np.vstack([matrix, [0, 0, 1]]) @ box.T)[:2].T for m in motions])
            if corners.min() < 2 or np.any(corners.max(0) > [WIDTH - 3, HEIGHT - 3]):
                continue
            shape = cv2.warpAffine(mask, matrix, (WIDTH, HEIGHT), flags=cv2.INTER_LINEAR) > 0
            if np.any(shape & (cv2.dilate(taken, kernel) > 0)):
                continue
            taken[shape] = 1
            poses.append(matrix)
            break
        else:
            shrink *= 0.9
    return poses
