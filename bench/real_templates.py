#!/usr/bin/python3
"""Grey templates cut from real photos, found in other real photos of the same planar object.

Two pairs that Debian's opencv-doc ships (/usr/share/doc/opencv-doc/examples/data), each with its
truth from an independent method:
  box    the whole of `box.png` (a printed box, 324 x 223 px) in `box_in_scene.png` (turned, smaller,
         partly hidden, among other boxes); truth: SIFT matches and a RANSAC homography (OpenCV).
  graf   a 300 x 300 px cut of `graf1.png` (a graffiti wall) in `graf3.png` (the wall seen about 40
         degrees off); truth: the homography the data set gives (`H1to3p.xml`).
Each template is the only prototype (read as a grey template: it is no silhouette). amcr_offline
runs the still target photo for --frames frames per recognizer seed; the report gives per pair
and seed the first frame with a report, and at the last frame the template's corners' error
(mean and largest over the 4 corners) against the truth.

    bench/real_templates.py --out .build/real-templates [--seeds 1-3] [--frames 60]
"""
import argparse
import json
import os
import sys

import cv2
import numpy as np

from still_photo import parse_seeds, run_still

DATA = "/usr/share/doc/opencv-doc/examples/data"
HERE = os.path.dirname(os.path.abspath(__file__))
GRAF_CUT = (250, 150, 300, 300)  # x, y, width, height in graf1.png


def sift_homography(template, scene):
    """The template -> scene homography from SIFT matches (ratio test 0.75, RANSAC 3 px)."""
    sift = cv2.SIFT_create()
    kt, dt = sift.detectAndCompute(template, None)
    ks, ds = sift.detectAndCompute(scene, None)
    matches = [m for m, n in cv2.BFMatcher().knnMatch(dt, ds, k=2) if m.distance < 0.75 * n.distance]
    h, inliers = cv2.findHomography(np.float32([kt[m.queryIdx].pt for m in matches]),
                                    np.float32([ks[m.trainIdx].pt for m in matches]), cv2.RANSAC, 3.0)
    if h is None or inliers.sum() < 30:
        sys.exit("real_templates: the SIFT truth of box_in_scene.png has too few inliers")
    return h


def pairs():
    """(name, template image, scene path, template -> scene homography)."""
    box = cv2.imread(os.path.join(DATA, "box.png"), cv2.IMREAD_GRAYSCALE)
    scene = os.path.join(DATA, "box_in_scene.png")
    yield "box", box, scene, sift_homography(box, cv2.imread(scene, cv2.IMREAD_GRAYSCALE))
    graf = cv2.imread(os.path.join(DATA, "graf1.png"), cv2.IMREAD_GRAYSCALE)
    x, y, w, h = GRAF_CUT
    storage = cv2.FileStorage(os.path.join(DATA, "H1to3p.xml"), cv2.FILE_STORAGE_READ)
    h13 = storage.getFirstTopLevelNode().mat()
    cut_to_graf1 = np.array([[1.0, 0, x], [0, 1.0, y], [0, 0, 1.0]])
    yield "graf", graf[y:y + h, x:x + w], os.path.join(DATA, "graf3.png"), h13 @ cut_to_graf1


def corners(image):
    h, w = image.shape[:2]
    return np.float32([[0, 0], [w - 1, 0], [w - 1, h - 1], [0, h - 1]]).reshape(-1, 1, 2)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    parser.add_argument("--out", default=os.path.join(HERE, "..", ".build", "real-templates"))
    parser.add_argument("--bin", default=os.path.join(HERE, "..", ".build", "ws", "devel", "lib", "amcr"))
    parser.add_argument("--config", default="")
    parser.add_argument("--seeds", default="1-3")
    parser.add_argument("--frames", type=int, default=60)
    args = parser.parse_args()
    if not os.path.isdir(DATA):
        print("real_templates: %s is missing: apt-get install opencv-doc" % DATA, file=sys.stderr)
        return 2

    summary = []
    for name, template, scene, truth in pairs():
        folder = os.path.join(args.out, name)
        prototypes = os.path.join(folder, "prototypes")
        os.makedirs(prototypes, exist_ok=True)
        cv2.imwrite(os.path.join(prototypes, name + ".png"), template)
        truth_corners = cv2.perspectiveTransform(corners(template), truth).reshape(-1, 2)
        for seed in parse_seeds(args.seeds):
            output = os.path.join(folder, "seed-%d.jsonl" % seed)
            frames = run_still(args.bin, prototypes, scene, args.frames, seed, output, args.config)
            first = next((k for k, f in enumerate(frames) if f["objects"]), None)
            row = {"pair": name, "seed": seed, "first_report": first, "reported_at_end": False}
            if frames[-1]["objects"]:
                o = frames[-1]["objects"][0]
                mapped = cv2.perspectiveTransform(corners(template), np.array(o["homography"])).reshape(-1, 2)
                error = np.linalg.norm(mapped - truth_corners, axis=1)
                row.update(reported_at_end=True, score=o["score"], mean_corner_error_px=float(error.mean()),
                           largest_corner_error_px=float(error.max()))
            summary.append(row)
            if row["reported_at_end"]:
                print("%s seed %d: first report at frame %s; at frame %d score %.2f, corners off by %.2f px "
                      "(largest %.2f)" % (name, seed, first, len(frames) - 1, row["score"],
                                          row["mean_corner_error_px"], row["largest_corner_error_px"]))
            else:
                print("%s seed %d: %s" % (name, seed, "not reported at frame %d" % (len(frames) - 1)
                                          if first is None else "first report at frame %d, none at the end" % first))
    with open(os.path.join(args.out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
