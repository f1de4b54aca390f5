"""A rendered sequence of bench/make_sequences (every suite but the real-camera ones and
`real-photos`): the photo behind, the targets printed under their motion, the distractors and lines,
the lighting, blur and noise, the 1280x720 resampling of the `*-hd` suites, and its truth.json."""

import math
import os
import shutil

import cv2
import numpy as np

from sequence_files import read_grey, write_truth
from sequence_memories import holdout_instances, mpeg7_file
from sequence_motion import CommonMotion, Copy, Mover, affine, place_copies, target_box
from sequence_suites import FAINT_GREY, HD_FROM_640, HD_PAD, HD_SIZE, HEIGHT, PHOTO_DIR, PHOTOS, SEED_INDEX, WIDTH


def background(rng, inverted):
    """A real photo, cropped at random and contrast-reduced to about 100..255; mirrored in grey
    (255 - value) when the print is inverted, so that both polarities have the same contrast."""
    photo = read_grey(os.path.join(PHOTO_DIR, PHOTOS[int(rng.integers(len(PHOTOS)))]))
    h, w = photo.shape
    scale = max(WIDTH / w, HEIGHT / h) * rng.uniform(1.0, 1.5)
    photo = cv2.resize(photo, (max(WIDTH, round(w * scale)), max(HEIGHT, round(h * scale))),
                       interpolation=cv2.INTER_AREA)
    y0 = int(rng.integers(0, photo.shape[0] - HEIGHT + 1))
    x0 = int(rng.integers(0, photo.shape[1] - WIDTH + 1))
    photo = photo[y0:y0 + HEIGHT, x0:x0 + WIDTH].astype(np.float32) / 255.0
    span = rng.uniform(80.0, 130.0)
    low = rng.uniform(100.0, 125.0)
    light = low + photo * span
    return 255.0 - light if inverted else light


def paint(frame, mask, matrix, value):
    alpha = cv2.warpAffine(mask.astype(np.float32) / 255.0, matrix, (WIDTH, HEIGHT),
                           flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
    frame *= 1.0 - alpha
    frame += alpha * value


def random_blob(rng):
    """A distractor that is no MPEG-7 shape: a smooth random star polygon, an ellipse or a cross."""
    size = 256
    mask = np.zeros((size, size), np.uint8)
    kind = int(rng.integers(3))
    c = size // 2
    if kind == 0:
        n = int(rng.integers(5, 13))
        angles = np.sort(rng.uniform(0, 2 * math.pi, n))
        radii = rng.uniform(40, 120, n)
        pts = np.stack([c + radii * np.cos(angles), c + radii * np.sin(angles)], 1)
        cv2.fillPoly(mask, [pts.astype(np.int32)], 255, cv2.LINE_AA)
    elif kind == 1:
        cv2.ellipse(mask, (c, c), (int(rng.integers(50, 120)), int(rng.integers(20, 80))), 0, 0, 360,
                    255, -1, cv2.LINE_AA)
    else:
        w = int(rng.integers(15, 45))
        cv2.rectangle(mask, (c - 110, c - w), (c + 110, c + w), 255, -1)
        cv2.rectangle(mask, (c - w, c - int(rng.integers(40, 110))), (c + w, c + 110), 255, -1)
    return mask


def render_sequence(path, suite, index, spec, memory, classes, mpeg7, frames, seed, key=None, noise_scale=1.0,
                    occluder=None):
    """Sequence `index` of `suite` into `path`. Every generator of the sequence is keyed by (seed, the
    suite's SEED_INDEX; `like`'s for the draws it shares with `like`) and the index; `key` (a list of
    integers) replaces that pair for a construction drawn elsewhere (bench/sampled_benchmark).
    `noise_scale` multiplies the drawn noise sigma (1: as drawn). `occluder` (bench/occluders.py, with
    a generator of its own: the scene's draws stay the same) is drawn in front of the first target in
    every frame, or on its own in a scene with no target; truth.json records it as "occluder"."""
    seed_suite = spec.get("like", suite)
    like_key = [seed, SEED_INDEX[seed_suite]] if key is None else list(key)
    own_key = [seed, SEED_INDEX[suite]] if key is None else list(key)
    rng = np.random.default_rng(like_key + [index])
    labels = sorted(memory)
    inverted = bool(rng.random() < 0.3)

    # What is shown: (label, silhouette file) per target.
    if spec["show"] == "none":
        shown = []
    elif spec["show"] == "two":
        shown = [(label, memory[label]) for label in rng.choice(labels, 2, replace=False)]
    elif spec["show"] == "copies":  # one class per sequence, 4-6 copies of it
        label = labels[int(rng.integers(len(labels)))]
        shown = [(label, memory[label])] * int(rng.integers(spec["copies"][0], spec["copies"][1] + 1))
    else:
        # One fixed order of the memory per suite: a suite covers its classes evenly.
        order = list(np.random.default_rng(like_key[:1] + [7919] + like_key[1:]).permutation(labels))
        label = order[index % len(order)]
        source = memory[label]
        if spec["show"] == "other-instance":
            source = mpeg7_file(label, int(rng.integers(2, 21)))
        elif spec["show"] == "held-out":  # within-class's draw, discarded: the other draws stay its
            rng.integers(2, 21)
            source = mpeg7_file(label, holdout_instances(classes)[0][label])
        shown = [(label, source)]

    # Distractors: MPEG-7 classes not in memory; random blobs when every class is in memory (in
    # `memory-growth`, whose largest memory holds every class).
    in_memory = {label.rsplit("-", 1)[0] if spec["memory"] == "similar3" else label for label in labels}
    if spec.get("memories"):
        in_memory = set(classes)
    others = [c for c in classes if c not in in_memory]
    distractor_masks = []
    for _ in range(int(rng.integers(3, 6))):
        if others:
            cls = others[int(rng.integers(len(others)))]
            distractor_masks.append(read_grey(mpeg7_file(cls, int(rng.integers(1, 21)))))
        else:
            distractor_masks.append(random_blob(rng))

    base = background(rng, inverted)
    ink = (lambda: 255.0 - rng.uniform(15.0, 60.0)) if inverted else (lambda: rng.uniform(15.0, 60.0))

    movers = []
    if spec["show"] == "copies":  # placed apart, then one motion for all
        mask = read_grey(shown[0][1])
        motion = CommonMotion(rng)
        poses = place_copies(rng, mask, len(shown), motion, frames)
        movers = [(label, mask, ink(), Copy(pose, motion)) for (label, _), pose in zip(shown, poses)]
    else:
        for i, (label, source) in enumerate(shown):
            mask = read_grey(source)
            # The squash has a generator of its own: the other draws stay those of `like`.
            squash_rng = np.random.default_rng(own_key + [index, 104729])
            movers.append((label, mask, ink(), Mover(rng, mask.shape[::-1], target_box(rng, len(shown), i),
                                                     spec.get("oblique"), squash_rng)))
    target_centres = [np.array([(m.box[0] + m.box[2]) / 2, (m.box[1] + m.box[3]) / 2]) for *_, m in movers]

    # Static clutter: distractors kept away from the targets' boxes where possible, lines.
    clutter = base.copy()
    distractors = []
    for mask in distractor_masks:
        dh, dw = mask.shape
        for _ in range(100):
            d_scale = rng.uniform(80.0, 170.0) / max(dw, dh)
            centre = np.array([rng.uniform(0, WIDTH), rng.uniform(0, HEIGHT)])
            if all(np.linalg.norm(centre - c) > 190 for c in target_centres):
                break
        matrix = affine(centre, rng.uniform(-math.pi, math.pi), d_scale, math.exp(rng.uniform(-0.2, 0.2)),
                        rng.uniform(-0.3, 0.3), (dw, dh))
        paint(clutter, mask, matrix, ink())
        distractors.append(np.round(matrix, 6).tolist())
    for _ in range(int(rng.integers(3, 7))):
        p0 = (int(rng.integers(0, WIDTH)), int(rng.integers(0, HEIGHT)))
        p1 = (int(rng.integers(0, WIDTH)), int(rng.integers(0, HEIGHT)))
        cv2.line(clutter, p0, p1, float(ink()), int(rng.integers(1, 4)), lineType=cv2.LINE_AA)

    # Lighting gradient (multiplicative ramp in a random direction), blur and noise per frame.
    g_angle = rng.uniform(0, 2 * math.pi)
    g_strength = rng.uniform(0.1, 0.35)
    ys, xs = np.mgrid[0:HEIGHT, 0:WIDTH].astype(np.float32)
    ramp = ((xs - WIDTH / 2) * math.cos(g_angle) + (ys - HEIGHT / 2) * math.sin(g_angle)) / (WIDTH / 2)
    light = 1.0 + g_strength * ramp
    blur = rng.uniform(0.0, 1.2)
    noise = rng.uniform(2.0, 8.0) * noise_scale
    contrast, defocus = spec.get("faint", (1.0, 0.0))
    blur = math.hypot(blur, defocus)  # Gaussians compose: the drawn blur, then the defocus
    hd = spec.get("hd", False)
    if hd:  # the margins: the lit photo (no clutter, no target) mirrored at the left and right edges
        margins = cv2.copyMakeBorder(base * light, 0, 0, HD_PAD, HD_PAD, cv2.BORDER_REFLECT_101)
        hd_from_wide = HD_FROM_640 @ np.array([[1.0, 0.0, -HD_PAD], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])

    if occluder is not None:
        occluder.start(clutter, movers[0][1:] if movers else None, inverted)

    frame_dir = os.path.join(path, "frames")
    if os.path.isdir(frame_dir):
        shutil.rmtree(frame_dir)
    os.makedirs(frame_dir)
    truth_frames = []
    for k in range(frames):
        frame = clutter.copy()
        objects = []
        first_matrix = None
        for label, mask, value, mover in movers:
            matrix = mover.pose(k)
            first_matrix = matrix if first_matrix is None else first_matrix
            paint(frame, mask, matrix, value)
            if hd:
                matrix = to_hd(matrix)
            objects.append({"label": label, "prototype_to_image": np.round(matrix, 6).tolist()})
        if occluder is not None:
            occluder.paint(frame, first_matrix)
        frame *= light
        if contrast != 1.0:
            frame = FAINT_GREY + contrast * (frame - FAINT_GREY)
        if hd:
            wide = margins.copy()
            wide[:, HD_PAD:HD_PAD + WIDTH] = frame
        if blur > 0.3:
            frame = cv2.GaussianBlur(frame, (0, 0), blur)
            if hd:
                wide = cv2.GaussianBlur(wide, (0, 0), blur)
        grain = rng.normal(0.0, noise, frame.shape).astype(np.float32)
        frame += grain
        if hd:  # the same frame, noise included, resampled; the margins' noise mirrored too
            wide += cv2.copyMakeBorder(grain, 0, 0, HD_PAD, HD_PAD, cv2.BORDER_REFLECT_101)
            frame = cv2.warpAffine(wide, hd_from_wide, HD_SIZE, flags=cv2.INTER_LINEAR,
                                   borderMode=cv2.BORDER_REFLECT_101)
        cv2.imwrite(os.path.join(frame_dir, "frame_%04d.png" % k),
                    np.clip(np.rint(frame), 0, 255).astype(np.uint8))
        truth_frames.append({"frame": k, "objects": objects})

    if hd:
        distractors = [np.round(to_hd(np.asarray(d)), 6).tolist() for d in distractors]
    truth = {
        "suite": suite, "sequence": index, "seed": seed, "image_size": list(HD_SIZE) if hd else [WIDTH, HEIGHT],
        "inverted": inverted, "blur_sigma": round(blur, 3), "noise_sigma": round(noise, 3),
        **({"contrast": contrast} if contrast != 1.0 else {}),
        "targets": [{"label": label, "source": os.path.basename(src)} for label, src in shown],
        "prototype_sizes": {label: list(read_grey(src).shape[::-1]) for label, src in shown},
        "distractors": distractors,
        **({"anisotropy": round(movers[0][3].squash[0], 4),
            "squash_axis_deg": round(math.degrees(movers[0][3].squash[1]), 2)} if spec.get("oblique") else {}),
        **({"like": spec["like"], "hd_from_640": HD_FROM_640.tolist()} if hd else {}),
        **({"occluder": occluder.record()} if occluder is not None else {}),
        "convention": "prototype_to_image maps prototype pixel (x, y) to image pixel A @ (x, y, 1); "
                      "integer coordinates are pixel centres (OpenCV)",
        "frames": truth_frames,
    }
    write_truth(path, truth)


def to_hd(matrix):
    """A 2x3 map into the 640x480 frame -> the same into the 1280x720 one (HD_FROM_640 after it)."""
    return HD_FROM_640[:, :2] @ np.asarray(matrix, dtype=np.float64) + np.hstack([np.zeros((2, 2)), HD_FROM_640[:, 2:]])
