"""A still photo for the benchmark's real-photo scripts (real_tags.py, real_templates.py): amcr_offline
on the photo repeated for a number of frames, one run per recognizer seed; and the per-frame baselines
of amcr_evaluate on the photo once, as a suite of one sequence of one frame."""
import argparse
import json
import os
import shutil
import subprocess

import cv2
import numpy as np

BASELINES = ("line2d", "sc")  # the per-frame methods of amcr_evaluate these scripts run
SEQUENCE = "photo"             # the suite's one sequence


REPO = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def still_photo_parser(doc, out_name, seeds, config_help="parameter file for amcr_offline (default: its defaults)"):
    """The options every still-photo script takes: --out (default .build/<out_name>), --bin (the
    workspace's binaries), --config, --seeds (default `seeds`) and --frames; the script's docstring
    `doc` as its description and epilog."""
    parser = argparse.ArgumentParser(description=doc.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter, epilog=doc)
    parser.add_argument("--out", default=os.path.join(REPO, ".build", out_name))
    parser.add_argument("--bin", default=os.path.join(REPO, ".build", "ws", "devel", "lib", "amcr"))
    parser.add_argument("--config", default="", help=config_help)
    parser.add_argument("--seeds", default=seeds)
    parser.add_argument("--frames", type=int, default=60)
    return parser


def parse_seeds(text):
    """"1-3" -> [1, 2, 3]; "1,4" -> [1, 4]."""
    if "-" in text:
        first, last = text.split("-")
        return list(range(int(first), int(last) + 1))
    return [int(v) for v in text.split(",")]


def parse_methods(text):
    """"amcr,line2d,sc" -> the list; exits naming a method these scripts do not run."""
    methods = [m for m in text.split(",") if m]
    unknown = [m for m in methods if m != "amcr" and m not in BASELINES]
    if unknown or not methods:
        raise SystemExit("--methods takes amcr and/or %s, got %r" % (", ".join(BASELINES), text))
    return methods


def run_still(binary_dir, prototypes, photo, frames, seed, output, config=""):
    """Runs amcr_offline on `photo` for `frames` frames with recognizer `seed`, the memory read from
    the folder `prototypes`, its JSON lines written to `output`; returns them parsed, one per frame."""
    command = [os.path.join(binary_dir, "amcr_offline"), "--prototypes", prototypes, "--input", photo,
               "--frames", str(frames), "--seed", str(seed), "--output", output]
    if config:
        command += ["--config", config]
    subprocess.run(command, check=True, stderr=subprocess.DEVNULL)
    with open(output) as f:
        return [json.loads(line) for line in f]


def grey_photo(photo):
    """The photo in grey as amcr_offline converts it (OpenCV's BGR to grey)."""
    image = cv2.imread(photo, cv2.IMREAD_UNCHANGED)
    if image is None:
        raise SystemExit("cannot read %s" % photo)
    return image if image.ndim == 2 else cv2.cvtColor(image[:, :, :3], cv2.COLOR_BGR2GRAY)


def write_still_suite(folder, photo, truth):
    """A suite of one sequence of one frame, as amcr_evaluate reads one (bench/evaluate.cpp): the photo
    in grey, and its truth: `truth` is [(label, prototype image size (w, h), template -> photo
    homography)]. The folder is written anew."""
    sequence = os.path.join(folder, SEQUENCE)
    if os.path.isdir(folder):
        shutil.rmtree(folder)
    os.makedirs(os.path.join(sequence, "frames"))
    cv2.imwrite(os.path.join(sequence, "frames", "frame_0000.png"), grey_photo(photo))
    objects = [{"label": label, "homography": np.round(np.asarray(h, float), 9).tolist()} for label, _, h in truth]
    with open(os.path.join(sequence, "truth.json"), "w") as f:
        json.dump({"source": photo, "prototype_sizes": {label: list(size) for label, size, _ in truth},
                   "convention": "homography maps prototype pixel (x, y) to image pixel; integer coordinates are "
                                 "pixel centres (OpenCV)",
                   "frames": [{"frame": 0, "objects": objects}]}, f, indent=1)


def run_baselines(binary_dir, suite, prototypes, methods, target_size, anisotropy, output, extra=()):
    """Runs amcr_evaluate's per-frame `methods` (of BASELINES) on the suite of write_still_suite() with
    the memory `prototypes`, set for targets of `target_size` (min, max: the prototype image's longer
    side at the affine's area scale, px) and `anisotropy` (largest of the affine); results in the folder
    `output`, written anew. Returns {method: (objects, time_ms)}, each object's "homography" the affine
    it reported."""
    if not methods:
        return {}
    if os.path.isdir(output):
        shutil.rmtree(output)  # amcr_evaluate keeps what it finds there
    command = [os.path.join(binary_dir, "amcr_evaluate"), "--suite", suite, "--prototypes", prototypes,
               "--out", output, "--methods", ",".join(methods),
               "--target-size", "%g,%g" % tuple(target_size), "--anisotropy", "%g" % anisotropy] + list(extra)
    subprocess.run(command, check=True)
    results = {}
    for method in methods:
        with open(os.path.join(output, "%s.%s.jsonl" % (SEQUENCE, method))) as f:
            frame = json.loads(f.readline())
        for o in frame["objects"]:
            o["homography"] = np.vstack([np.reshape(o["prototype_to_image"], (2, 3)), [0, 0, 1]]).tolist()
        results[method] = (frame["objects"], frame["time_ms"])
    return results
