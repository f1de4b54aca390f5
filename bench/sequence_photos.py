"""The `real-photos` suite: the part cut from a real photograph of several alike flat parts (the
prototype, and every instance of it in the photo with an approximate affine), and a sequence of the
photo under a synthetic camera motion with its truth.json."""

import math
import os
import shutil

import cv2
import numpy as np

from sequence_files import fail, read_grey, write_truth
from sequence_suites import (HALF_TURN_SYMMETRIC, HEIGHT, PART_AREA_TOLERANCE, PART_MARGIN, PART_PHOTOS, PHOTO_DIR,
                             SEED_INDEX, WIDTH)


def dark_parts(grey):
    """The dark components of a photo of dark parts on a light ground: Otsu's threshold on the grey
    photo, 8-connected components of the pixels at or below it that do not touch the photo's border
    and cover at least 0.5% of it. Per component (in order of centroid, top to bottom, then left to
    right): its mask (bool, photo size), area (px), centroid (x, y) and principal axis angle
    (radians, from the second moments)."""
    threshold, _ = cv2.threshold(grey, 0, 255, cv2.THRESH_BINARY | cv2.THRESH_OTSU)
    n, labels, stats, centroids = cv2.connectedComponentsWithStats((grey <= threshold).astype(np.uint8),
                                                                   connectivity=8)
    h, w = grey.shape
    parts = []
    for i in range(1, n):
        x, y, bw, bh, area = stats[i]
        if x == 0 or y == 0 or x + bw == w or y + bh == h or area < 0.005 * grey.size:
            continue
        mask = labels == i
        m = cv2.moments(mask.astype(np.uint8), True)
        angle = 0.5 * math.atan2(2.0 * m["mu11"], m["mu20"] - m["mu02"])
        parts.append({"mask": mask, "area": int(area), "centroid": np.array(centroids[i]), "angle": angle})
    return sorted(parts, key=lambda p: (round(p["centroid"][1] / 20.0), p["centroid"][0]))


def cut_part(photo_file):
    """The `real-photos` prototype and the part's instances in a photo. The prototype is the dark
    component (dark_parts) of the median area (of the areas sorted, the one at index n // 2), cut
    with PART_MARGIN px around it, centred on its centroid, white on black (the MPEG-7 files'
    convention). The instances are the components whose area is within PART_AREA_TOLERANCE of its.
    Each instance gets an approximate prototype->photo affine from the moments: the prototype's
    centroid onto the instance's, rotated by the difference of their principal axes, scaled by the
    square root of their areas' ratio; of the two rotations half a turn apart that the axes leave,
    the one under which the prototype overlaps the instance's mask more (intersection over union).
    Returns (prototype image, photo grey, [(centroid, 2x3 prototype->photo affine), ...])."""
    grey = read_grey(photo_file)
    parts = dark_parts(grey)
    if not parts:
        fail("no dark parts found in %s" % photo_file)
    part = sorted(parts, key=lambda p: p["area"])[len(parts) // 2]
    ys, xs = np.nonzero(part["mask"])
    cx, cy = part["centroid"]
    half_w = math.ceil(max(cx - xs.min(), xs.max() - cx)) + PART_MARGIN
    half_h = math.ceil(max(cy - ys.min(), ys.max() - cy)) + PART_MARGIN
    size = (2 * half_w + 1, 2 * half_h + 1)
    photo_to_proto = np.array([[1.0, 0.0, half_w - cx], [0.0, 1.0, half_h - cy]])
    prototype = cv2.warpAffine(part["mask"].astype(np.uint8) * 255, photo_to_proto, size, flags=cv2.INTER_LINEAR)
    prototype = np.where(prototype > 127, 255, 0).astype(np.uint8)
    instances = []
    for other in parts:
        if abs(other["area"] / part["area"] - 1.0) > PART_AREA_TOLERANCE:
            continue
        scale = math.sqrt(other["area"] / part["area"])
        best = None
        for turn in (0.0, math.pi):
            angle = other["angle"] - part["angle"] + turn
            c, s = math.cos(angle), math.sin(angle)
            linear = scale * np.array([[c, -s], [s, c]])
            matrix = np.hstack([linear, (other["centroid"] - linear @ [half_w, half_h]).reshape(2, 1)])
            seen = cv2.warpAffine(prototype, matrix, grey.shape[::-1], flags=cv2.INTER_LINEAR) > 127
            overlap = np.sum(seen & other["mask"]) / np.sum(seen | other["mask"])
            if best is None or overlap > best[0]:
                best = (overlap, matrix)
        instances.append((other["centroid"], best[1]))
    return prototype, grey, instances


def camera_motion(rng, instances, proto_size, photo_size, frames):
    """`real-photos`: the 2x3 photo->frame map of every frame, a slow synthetic camera motion: the
    parts' centre to the frame's centre at a scale that makes their span 75-85% of the frame, then
    a drift along two sinusoids (15-35 px), a start angle of +-10 degrees turning by 0.05-0.2 degrees
    per frame and a scale changing by 0.1-0.2% per frame (growing or shrinking). Drawn again until
    every instance's prototype box stays 2 px inside the frame in every frame."""
    pw, ph = proto_size
    box = np.array([[0, 0, 1], [pw - 1, 0, 1], [pw - 1, ph - 1, 1], [0, ph - 1, 1]], dtype=np.float64)
    points = np.concatenate([(m @ box.T).T for _, m in instances])
    low, high = points.min(0), points.max(0)
    centre = (low + high) / 2.0
    for _ in range(100):
        base = rng.uniform(0.75, 0.85) * min(WIDTH / (high[0] - low[0]), HEIGHT / (high[1] - low[1]))
        amplitude = rng.uniform(15.0, 35.0, 2)
        period = rng.uniform(100.0, 200.0, 2)
        phase = rng.uniform(0.0, 2.0 * math.pi, 2)
        angle = math.radians(rng.uniform(-10.0, 10.0))
        spin = math.radians(rng.uniform(0.05, 0.2)) * rng.choice([-1.0, 1.0])
        zoom = rng.uniform(0.001, 0.002) * rng.choice([-1.0, 1.0])
        maps = []
        for k in range(frames):
            shift = amplitude * (np.sin(2.0 * math.pi * k / period + phase) - np.sin(phase))
            c, s = math.cos(angle + spin * k), math.sin(angle + spin * k)
            linear = base * math.exp(zoom * k) * np.array([[c, -s], [s, c]])
            target = np.array([(WIDTH - 1) / 2.0, (HEIGHT - 1) / 2.0]) + shift
            maps.append(np.hstack([linear, (target - linear @ centre).reshape(2, 1)]))
        seen = np.concatenate([points @ m[:, :2].T + m[:, 2] for m in maps])
        if seen.min() >= 2 and np.all(seen.max(0) <= [WIDTH - 3, HEIGHT - 3]):
            return maps
    fail("no camera motion keeps the parts in view")


def render_photo(path, suite, index, frames, seed, key=None, noise_scale=1.0):
    """A `real-photos` sequence: the photo of PART_PHOTOS[index % len] under a camera motion of its
    own (camera_motion), bilinear, with noise (sigma 1.5-3); truth: every instance of the part.
    `key` (a list of integers) replaces (seed, SEED_INDEX[suite]) in the sequence's generator for a
    construction drawn elsewhere (bench/sampled_benchmark); `noise_scale` multiplies the drawn noise
    sigma (0: no noise added at all)."""
    rng = np.random.default_rng(([seed, SEED_INDEX[suite]] if key is None else list(key)) + [index])
    name, label = PART_PHOTOS[index % len(PART_PHOTOS)]
    prototype, grey, instances = cut_part(os.path.join(PHOTO_DIR, name))
    maps = camera_motion(rng, instances, prototype.shape[::-1], grey.shape[::-1], frames)
    noise = rng.uniform(1.5, 3.0) * noise_scale
    photo = grey.astype(np.float32)
    # How alike the part is to itself turned by half a turn (about the prototype's centre, its centroid).
    turned = (prototype > 127) & (prototype[::-1, ::-1] > 127)
    half_turn = float(np.sum(turned) / np.sum((prototype > 127) | (prototype[::-1, ::-1] > 127)))
    frame_dir = os.path.join(path, "frames")
    if os.path.isdir(frame_dir):
        shutil.rmtree(frame_dir)
    os.makedirs(frame_dir)
    truth_frames = []
    for k, camera in enumerate(maps):
        frame = cv2.warpAffine(photo, camera, (WIDTH, HEIGHT), flags=cv2.INTER_LINEAR,
                               borderMode=cv2.BORDER_REPLICATE)
        if noise > 0:
            frame += rng.normal(0.0, noise, frame.shape).astype(np.float32)
        cv2.imwrite(os.path.join(frame_dir, "frame_%04d.png" % k), np.clip(np.rint(frame), 0, 255).astype(np.uint8))
        objects = []
        for centroid, matrix in instances:
            to_image = camera[:, :2] @ matrix + np.hstack([np.zeros((2, 2)), camera[:, 2:]])
            objects.append({"label": label, "prototype_to_image": np.round(to_image, 6).tolist(),
                            "center": np.round(camera[:, :2] @ centroid + camera[:, 2], 3).tolist(),
                            "approximate": True})
        truth_frames.append({"frame": k, "objects": objects})
    truth = {
        "suite": suite, "sequence": index, "seed": seed, "image_size": [WIDTH, HEIGHT],
        "source": "opencv-doc %s" % name, "noise_sigma": round(noise, 3), "instances": len(instances),
        "targets": [{"label": label, "source": "cut from %s (bench/make_sequences cut_part)" % name}],
        "prototype_sizes": {label: list(prototype.shape[::-1])},
        "photo_to_image_first": np.round(maps[0], 6).tolist(),
        "approximate": True,
        "half_turn_overlap": round(half_turn, 3), "half_turn_symmetric": half_turn >= HALF_TURN_SYMMETRIC,
        "convention": "prototype_to_image maps prototype pixel (x, y) to image pixel A @ (x, y, 1); integer "
                      "coordinates are pixel centres (OpenCV); it is approximate (from the instance's moments in "
                      "the photo, composed with the exact camera map); center: the instance's centroid",
        "frames": truth_frames,
    }
    write_truth(path, truth)
