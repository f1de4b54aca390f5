"""The real-camera suites (`real-camera`, `real-camera-cube`): visp-images-data's frames as PNG, and
the truth that the suite's own module (bench/real_camera.py, bench/real_camera_cube.py) finds in
them."""

import importlib
import os
import shutil

import cv2
import numpy as np

from sequence_files import read_grey, write_truth
from sequence_suites import REAL_SUITES


def real_truth(suite):
    """The truth's module of a `show="real"` suite (bench/real_camera.py or real_camera_cube.py,
    beside this script) and the target's label."""
    module, _, label = REAL_SUITES[suite]
    return importlib.import_module(module), label


def render_real(path, suite, index, frames, seed):
    """A `real-camera` or `real-camera-cube` sequence: the visp-images-data frames as PNG and the
    truth of the suite's module (REAL_SUITES)."""
    module, label = real_truth(suite)
    name = REAL_SUITES[suite][1][index]
    files = module.sequence_files(name)[:frames]
    greys = [read_grey(f) for f in files]
    frame_dir = os.path.join(path, "frames")
    if os.path.isdir(frame_dir):
        shutil.rmtree(frame_dir)
    os.makedirs(frame_dir)
    truth_frames = []
    for k, (grey, found) in enumerate(zip(greys, module.track(greys))):
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
        "targets": [{"label": label, "source": "drawn (bench/%s.py)" % module.__name__}],
        "prototype_sizes": {label: list(module.prototype_shape())},
        "score_points": np.round(module.prototype_corners(), 3).tolist(),
        "symmetries": module.SYMMETRIES,
        "known_frames": sum("unknown" not in f for f in truth_frames),
        "convention": "homography and prototype_to_image map prototype pixel (x, y) to image pixel; integer "
                      "coordinates are pixel centres (OpenCV); prototype_to_image is the least-squares affine "
                      "of the homography over a 5x5 grid of the target",
        "frames": truth_frames,
    }
    write_truth(path, truth)
