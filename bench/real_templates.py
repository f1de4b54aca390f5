#!/usr/bin/python3
"""Grey templates cut from real photos, found in other real photos of the same planar object.

Two pairs that Debian's opencv-doc ships (/usr/share/doc/opencv-doc/examples/data), each with its
truth from an independent method:
  box    the whole of `box.png` (a printed box, 324 x 223 px) in `box_in_scene.png` (turned, smaller,
         partly hidden, among other boxes); truth: SIFT matches and a RANSAC homography (OpenCV).
  graf   a 300 x 300 px cut of `graf1.png` (a graffiti wall) in `graf3.png` (the wall seen about 40
         degrees off); truth: the homography the data set gives (`H1to3p.xml`).
Each template is the only prototype (read as a grey template: it is no silhouette). --methods picks
who looks for it: amcr (amcr_offline runs the still target photo for --frames frames per recognizer
seed), and the per-frame baselines LINE-2D (line2d) and shape contexts (sc) of amcr_evaluate, run
once on the photo as a suite of one frame. The report gives per pair and method (for amcr per seed:
its first frame with a report, and the last frame) the best report's corners' error (mean and
largest over the template's 4 corners) against the truth, and the time per frame (amcr: the median).

The baselines are set for each pair's pose, measured on the truth (the template's longer side at
the affine's area scale, and the largest ratio of the affine's singular values, over the template):
  box    153-197 px of 324 (0.47-0.61), up to 1.19:1; given 150-230 px and 1.4
  graf   207-239 px of 300, up to 1.68:1; given 195-255 px and 1.9
Their poses are affine: the best affine to the truth's homography leaves the corners 4.3 px (box)
and 6.9 px (graf) off on average, which bounds their corner error from below.

    bench/real_templates.py --out .build/real-templates [--methods amcr,line2d,sc] [--seeds 1-3] [--frames 60]
"""
import json
import os
import sys

import cv2
import numpy as np

from still_photo import still_photo_parser, BASELINES, parse_methods, parse_seeds, run_baselines, run_still, write_still_suite

DATA = "/usr/share/doc/opencv-doc/examples/data"
GRAF_CUT = (250, 150, 300, 300)  # x, y, width, height in graf1.png
# The baselines' pose range per pair (see above): target size (min, max) px and anisotropy.
POSE_RANGE = {"box": ((150, 230), 1.4), "graf": ((195, 255), 1.9)}


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


def corner_errors(template, objects, truth_corners):
    """The best report's corner errors (mean, largest) against the truth; None without a report."""
    if not objects:
        return None
    mapped = cv2.perspectiveTransform(corners(template), np.array(objects[0]["homography"], float)).reshape(-1, 2)
    error = np.linalg.norm(mapped - truth_corners, axis=1)
    return float(error.mean()), float(error.max())


def describe(row):
    if row["mean_corner_error_px"] is None:
        return "no report, %.1f ms per frame" % row["time_ms"]
    return "score %.2f, corners off by %.2f px (largest %.2f), %.1f ms per frame" % (
        row["score"], row["mean_corner_error_px"], row["largest_corner_error_px"], row["time_ms"])


def main():
    parser = still_photo_parser(__doc__, "real-templates", "1-3")
    parser.add_argument("--methods", default="amcr", help="amcr, line2d and/or sc, comma-separated")
    args = parser.parse_args()
    methods = parse_methods(args.methods)
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

        def row_of(method, objects, time_ms, **more):
            errors = corner_errors(template, objects, truth_corners)
            row = {"pair": name, "method": method, "time_ms": time_ms,
                   "score": objects[0]["score"] if objects else None,
                   "mean_corner_error_px": errors[0] if errors else None,
                   "largest_corner_error_px": errors[1] if errors else None}
            row.update(more)
            summary.append(row)
            return row

        if "amcr" in methods:
            for seed in parse_seeds(args.seeds):
                output = os.path.join(folder, "seed-%d.jsonl" % seed)
                frames = run_still(args.bin, prototypes, scene, args.frames, seed, output, args.config)
                first = next((k for k, f in enumerate(frames) if f["objects"]), None)
                row = row_of("amcr", frames[-1]["objects"], float(np.median([f["time_ms"] for f in frames])),
                             seed=seed, first_report=first)
                print("%s amcr seed %d: first report at frame %s; at frame %d %s"
                      % (name, seed, first, len(frames) - 1, describe(row)))

        baselines = [m for m in methods if m in BASELINES]
        if baselines:
            suite = os.path.join(folder, "suite")
            write_still_suite(suite, scene, [(name, template.shape[::-1], truth)])
            target_size, anisotropy = POSE_RANGE[name]
            results = run_baselines(args.bin, suite, prototypes, baselines, target_size, anisotropy,
                                    os.path.join(folder, "baselines"))
            for method in baselines:
                print("%s %s, the photo once: %s" % (name, method, describe(row_of(method, *results[method]))))
    with open(os.path.join(args.out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
