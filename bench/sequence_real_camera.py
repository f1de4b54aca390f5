"""The real-camera suites (`real-camera`, `real-camera-cube`): visp-images-data's frames as PNG, and
the truth that the suite's own module (bench/real_camera.py, bench/real_camera_cube.py) finds in
them."""

import importlib
import os
import shutil

import cv2
import numpy as np

from printed_target import best_affine, unit_square_corners
from sequence_files import read_grey, write_truth
from sequence_suites import REAL_SUITES


def real_truth(suite):
    """The truth's module of a `show="real"` suite (bench/real_camera.py or real_camera_cube.py,
    beside this script) and the target's label."""
    module, _, label = REAL_SUITES[suite]
    return importlib.import_module(module), label


def tracked(module, files):
    """module.track of the frames in `files` (kept for this process: a sampled run renders the same
    frames once per draw)."""
    cache_key = (module.__name__, tuple(files))
    if cache_key not in TRACKED:
        TRACKED[cache_key] = module.track([read_grey(f) for f in files])
    return TRACKED[cache_key]


TRACKED = {}


def render_real(path, suite, index, frames, seed, like=None, drawn=None):
    """A `real-camera` or `real-camera-cube` sequence: the visp-images-data frames as PNG and the
    truth of the suite's module (REAL_SUITES). A sampled construction (bench/sampled_benchmark)
    names its real suite in `like` and may give `drawn`, a prototype drawn otherwise than from the
    measured geometry: {"shape": (width, height), "square_to_prototype": 3x3 map of its target's unit
    square to its pixels, "source": text}. The truth stays that of the measured target (found with
    the measured geometry); it is expressed in the drawn prototype's pixels by mapping the drawn
    target's square onto the measured one's (homography composed with that map; its best affine)."""
    module, label = real_truth(like or suite)
    name = REAL_SUITES[like or suite][1][index]
    files = module.sequence_files(name)[:frames]
    greys = [read_grey(f) for f in files]
    found_frames = tracked(module, files)
    if drawn is not None:
        square = np.asarray(drawn["square_to_prototype"], dtype=np.float64)
        measured_from_drawn = module.square_to_prototype() @ np.linalg.inv(square)
        found_frames = [drawn_truth(found, measured_from_drawn, square) for found in found_frames]
    frame_dir = os.path.join(path, "frames")
    if os.path.isdir(frame_dir):
        shutil.rmtree(frame_dir)
    os.makedirs(frame_dir)
    truth_frames = []
    for k, (grey, found) in enumerate(zip(greys, found_frames)):
        cv2.imwrite(os.path.join(frame_dir, "frame_%04d.png" % k), grey)
        if "unknown" in found:
            truth_frames.append({"frame": k, "unknown": True, "reason": found["unknown"],
                                 "objects": [{"label": label}]})
        else:
            truth_frames.append({"frame": k, "objects": [{
                "label": label, "prototype_to_image": np.round(found["affine"], 6).tolist(),
                "homography": np.round(found["homography"], 9).tolist()}]})
    height, width = greys[0].shape
    truth = {
        "suite": suite, "sequence": index, "seed": seed, "source": "visp-images-data %s" % name,
        "image_size": [width, height],
        "targets": [{"label": label, "source": "drawn (bench/%s.py)" % module.__name__ if drawn is None
                     else drawn["source"]}],
        "prototype_sizes": {label: list(module.prototype_shape() if drawn is None else drawn["shape"])},
        "score_points": np.round(module.prototype_corners() if drawn is None
                                 else unit_square_corners(np.asarray(drawn["square_to_prototype"])), 3).tolist(),
        "symmetries": module.SYMMETRIES,
        "known_frames": sum("unknown" not in f for f in truth_frames),
        "convention": "homography and prototype_to_image map prototype pixel (x, y) to image pixel; integer "
                      "coordinates are pixel centres (OpenCV); prototype_to_image is the least-squares affine "
                      "of the homography over a 5x5 grid of the target",
        "frames": truth_frames,
    }
    write_truth(path, truth)


def drawn_truth(found, measured_from_drawn, square):
    """A frame's truth (module.track) re-expressed for a drawn prototype: the homography composed with
    the map of the drawn prototype's pixels onto the measured one's, and its best affine."""
    if "unknown" in found:
        return found
    h = found["homography"] @ measured_from_drawn
    h = h / h[2, 2]
    return dict(found, homography=h, affine=best_affine(h, square))
