#!/usr/bin/python3
"""A grey template cut from frame 0 of a real camera sequence, found in the sequence, with memories of
1, 2, 17 and 70 prototypes: found-by-frame over recognizer seeds, and the recall funnel's stages.

The sequence is visp-images-data's `cube` (80 frames, 384 x 288, bench/real_camera_cube.py). The
template is the bounding box of the cube's front face in frame 0, cut from the frame's own pixels as a
user cuts one (71 x 68 px; CUT below). The truth is real_camera_cube's (the face's ring of dots, then
its edges), expressed in the cut's pixels. The other prototypes are MPEG-7 silhouettes: for a memory
of 2 the apple, of 17 number 1 of the `paper` memory's classes, of 70 number 1 of every class, beyond
that the next instances of every class in turn (300: numbers 1-5 of the 70 classes but one).

Per memory size, every recognizer seed runs `amcr_evaluate --methods amcr` on the same suite; a seed
finds the face at the first frame whose report is at the right place (the funnel's `reported`: every
corner within 10% of the face's diagonal, under any of its quarter turns). The table gives the share of
seeds that found it within the first 10, 30 and 80 frames, and per funnel stage the share of known frames that reached
it (bench/recall_funnel.h). <out>/found.json keeps, per memory size, each seed's first right report
(null: never), which bench/found_by_frame.py draws as found-by-frame curves.

    bench/real_camera_cut.py --out .build/real-camera-cut [--memories 1,2,17,70,300] [--seeds 1-8]
                             [--config config/amcr.yaml] [--bin .build/ws/devel/lib/amcr]
"""
import argparse
import concurrent.futures
import json
import os
import shutil
import subprocess

import cv2
import numpy as np

import real_camera_cube
from sequence_memories import mpeg7_classes, mpeg7_file, paper_classes
from sequence_real_camera import real_truth, render_real

REPO = os.path.dirname(os.path.dirname(os.path.realpath(__file__)))
CUT = (182, 76, 253, 144)  # x0, y0, x1, y1 (exclusive) in frame 0: the face's bounding box
STAGES = ["on_object", "proposed", "alive", "cluster", "verified", "passed", "reported"]
CHECK_FRAMES = (10, 30, 80)


def seed_list(text):
    seeds = []
    for part in text.split(","):
        first, _, last = part.partition("-")
        seeds.extend(range(int(first), int(last or first) + 1))
    return seeds


def others(size, mpeg7):
    """The MPEG-7 files beside the face in a memory of `size` prototypes."""
    classes = mpeg7_classes(mpeg7)
    if size == 1:
        return []
    if size == 2:
        return [mpeg7_file("apple", 1)]
    if size <= 18:
        return [mpeg7_file(c, 1) for c in paper_classes(classes)[:size - 1]]
    # Beyond the 70 classes, the next instances of each class in turn (labels apple-1, apple-2, ...).
    files = [mpeg7_file(c, n) for n in range(1, 21) for c in classes]
    return files[:size - 1]


def write_suite(folder, size, mpeg7):
    """prototypes/ (the cut and the others) and seq_000/ (frames, truth in the cut's pixels)."""
    if os.path.exists(os.path.join(folder, "seq_000", "truth.json")):
        return
    files = real_camera_cube.sequence_files()
    first = cv2.imread(files[0], cv2.IMREAD_GRAYSCALE)
    found = real_camera_cube.track([first])[0]
    if "unknown" in found:
        raise SystemExit("real_camera_cut: the face is not found in frame 0 (%s)" % found["unknown"])
    x0, y0, x1, y1 = CUT
    to_cut = np.array([[1, 0, -x0], [0, 1, -y0], [0, 0, 1.0]])
    square = to_cut @ np.asarray(found["homography"]) @ real_camera_cube.square_to_prototype()
    square /= square[2, 2]
    _, label = real_truth("real-camera-cube")
    protos = os.path.join(folder, "prototypes")
    os.makedirs(protos, exist_ok=True)
    cv2.imwrite(os.path.join(protos, label + ".png"), first[y0:y1, x0:x1])
    for f in others(size, mpeg7):
        shutil.copy(f, protos)
    seq = os.path.join(folder, "seq_000")
    os.makedirs(seq, exist_ok=True)
    render_real(seq, "real-camera-cube", 0, len(files), 1, drawn={
        "shape": (x1 - x0, y1 - y0), "square_to_prototype": square.tolist(),
        "source": "cut from frame 0 (bench/real_camera_cut.py)"})


def run(binary, suite, out, seed, config):
    if not os.path.exists(os.path.join(out, "seq_000.amcr.funnel.jsonl")):
        subprocess.run([binary, "--suite", suite, "--out", out, "--methods", "amcr", "--seed", str(seed),
                        "--config", config], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    first, reached, known = None, [0] * len(STAGES), 0
    with open(os.path.join(out, "seq_000.amcr.funnel.jsonl")) as f:
        for line in f:
            row = json.loads(line)
            for o in row.get("objects", []):
                known += 1
                for k, s in enumerate(o["stages"]):
                    reached[k] += s
                if o["stages"][-1] and first is None:
                    first = row["frame"]
    return first, reached, known


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=os.path.join(REPO, ".build", "real-camera-cut"))
    parser.add_argument("--memories", default="1,2,17,70")
    parser.add_argument("--seeds", default="1-8")
    parser.add_argument("--config", default=os.path.join(REPO, "config", "amcr.yaml"))
    parser.add_argument("--bin", default=os.path.join(REPO, ".build", "ws", "devel", "lib", "amcr"))
    parser.add_argument("--data", default=os.path.join(os.path.dirname(REPO), "shared", "data"))
    parser.add_argument("--jobs", type=int, default=2)
    args = parser.parse_args()
    if not os.path.isdir(real_camera_cube.VISP_DIR):
        raise SystemExit("real_camera_cut: %s is missing (Debian's visp-images-data)" % real_camera_cube.VISP_DIR)
    binary = os.path.join(args.bin, "amcr_evaluate")
    seeds = seed_list(args.seeds)
    print("| memory | found by frame %s | stages reached (share of known frames: %s) |" % (
        " / ".join(str(k) for k in CHECK_FRAMES), ", ".join(STAGES)))
    print("|---|---|---|")
    record = {"config": args.config, "seeds": seeds, "frames": 80, "first_report": {}}
    for size in [int(s) for s in args.memories.split(",")]:
        suite = os.path.join(args.out, "memory-%d" % size)
        write_suite(suite, size, os.path.join(args.data, "mpeg7"))
        with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
            results = list(pool.map(lambda s: run(binary, suite, os.path.join(suite, "seed-%d" % s), s,
                                                  args.config), seeds))
        found = ["%d/%d" % (sum(r[0] is not None and r[0] < k for r in results), len(seeds)) for k in CHECK_FRAMES]
        known = sum(r[2] for r in results)
        stages = ", ".join("%.0f%%" % (100.0 * sum(r[1][k] for r in results) / max(1, known))
                           for k in range(len(STAGES)))
        print("| %d | %s | %s |" % (size, " / ".join(found), stages), flush=True)
        record["first_report"][str(size)] = [r[0] for r in results]
    with open(os.path.join(args.out, "found.json"), "w") as f:
        json.dump(record, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
