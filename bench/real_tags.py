#!/usr/bin/python3
"""Twelve AprilTags in a real photo, recognized with grey-template prototypes.

The photo is visp-images-data's `AprilTag/AprilTag.pgm` (640 x 480, a printed sheet of tag36h11
ids 8-19 on a desk, seen obliquely, each tag 40-90 px); its truth is the four corners of each tag as
ViSP's AprilTag detector found them (`ground_truth_detection.txt`), an independent method. The
prototypes are the tags as the AprilTag library draws them (`apriltag_to_image`, Debian's
libapriltag3), scaled up by whole pixels per cell, with an alpha channel over the tag, so that they
are read as grey templates (docs/configuration.md, "Silhouettes and grey templates"): a tag differs
from another only inside its black square.

The memory is the 12 tags of the photo, plus --extra other ids of the family (drawn at random with
--seed-memory) as look-alikes. --methods picks who recognizes them: amcr (amcr_offline runs the
still photo for --frames frames per recognizer seed), and the per-frame baselines LINE-2D (line2d)
and shape contexts (sc) of amcr_evaluate, run once on the photo as a suite of one frame. The
baselines are set for the tags' poses, measured on the truth: the 204 px tag image at 51-89 px (its
longer side at the affine's area scale), views up to 2.2:1 (the largest ratio of an affine's singular
values); they get 45-95 px and 2.3 (--target-size 45,95 --anisotropy 2.3), and LINE-2D as many
reports as the memory has tags. Their poses are affine: a tag's perspective leaves 0.5-2 px between
the best affine and its corners.

For each method (for amcr each seed, at the last frame) the report gives: the tags reported with the
right id and their corners within 5 px of the truth, how many within 1 px, the median corner error
(the mean over the four corners, in the corner order that the tags' pattern in the photo shows, which
the report names), the other reports (another id, or corners off by more than 5 px), the time per
frame (amcr: the median over its frames), and for amcr the first frame each tag was reported right.

    bench/real_tags.py --out .build/real-tags [--methods amcr,line2d,sc] [--seeds 1-3] [--frames 60] [--extra 0]

Needs libapriltag3 (Debian: `apt-get install libapriltag3`) and visp-images-data; says which is
missing and exits 2 otherwise.
"""
import ctypes
import ctypes.util
import json
import os
import sys

import cv2
import numpy as np

from still_photo import still_photo_parser, BASELINES, grey_photo, parse_methods, parse_seeds, run_baselines, run_still, write_still_suite

PHOTO_DIR = "/usr/share/visp-images-data/ViSP-images/AprilTag"
FAMILY = "tag36h11"
CELL_PX = 20       # template px per tag cell: 10 cells (the white border included) = 200 px
MARGIN_PX = 2      # transparent px around the tag: the alpha channel makes the image a template
TARGET_SIZE = (45, 95)  # the baselines' pose range (see above)
ANISOTROPY = 2.3
RIGHT_PX, CLOSE_PX = 5.0, 1.0  # corner errors: a right report, and one within the aims' 1 px
# The ways the truth's 4 corners may follow the template's clockwise ones: 4 turns, in either direction.
ORDERS = [np.roll(np.arange(4), k) for k in range(4)] + [np.roll(np.arange(4)[::-1], k) for k in range(4)]


class ImageU8(ctypes.Structure):
    _fields_ = [("width", ctypes.c_int32), ("height", ctypes.c_int32), ("stride", ctypes.c_int32),
                ("buf", ctypes.POINTER(ctypes.c_uint8))]


class Family(ctypes.Structure):
    _fields_ = [("ncodes", ctypes.c_uint32), ("codes", ctypes.POINTER(ctypes.c_uint64)),
                ("width_at_border", ctypes.c_int), ("total_width", ctypes.c_int),
                ("reversed_border", ctypes.c_bool), ("nbits", ctypes.c_uint32),
                ("bit_x", ctypes.POINTER(ctypes.c_uint32)), ("bit_y", ctypes.POINTER(ctypes.c_uint32)),
                ("h", ctypes.c_uint32), ("name", ctypes.c_char_p), ("impl", ctypes.c_void_p)]


def load_family():
    name = ctypes.util.find_library("apriltag") or "libapriltag.so.3"
    try:
        lib = ctypes.CDLL(name)
    except OSError as e:
        sys.exit("real_tags: the AprilTag library is missing (%s): apt-get install libapriltag3" % e)
    create = getattr(lib, FAMILY + "_create")
    create.restype = ctypes.POINTER(Family)
    lib.apriltag_to_image.restype = ctypes.POINTER(ImageU8)
    lib.apriltag_to_image.argtypes = [ctypes.POINTER(Family), ctypes.c_int]
    return lib, create()


def tag_image(lib, family, tag_id):
    """The tag as the library draws it (one px per cell, white border included), as grey + alpha."""
    image = lib.apriltag_to_image(family, tag_id)
    w, h, stride = image.contents.width, image.contents.height, image.contents.stride
    cells = np.ctypeslib.as_array(image.contents.buf, shape=(h * stride,)).reshape(h, stride)[:, :w].copy()
    grey = cv2.resize(cells, (w * CELL_PX, h * CELL_PX), interpolation=cv2.INTER_NEAREST)
    grey = cv2.copyMakeBorder(grey, MARGIN_PX, MARGIN_PX, MARGIN_PX, MARGIN_PX, cv2.BORDER_CONSTANT, value=255)
    alpha = np.zeros_like(grey)
    alpha[MARGIN_PX:-MARGIN_PX, MARGIN_PX:-MARGIN_PX] = 255
    return cv2.merge([grey, grey, grey, alpha]), w


def black_square_corners(cells):
    """The tag's black square in template px (pixel-centre convention), clockwise from top left."""
    lo = MARGIN_PX + CELL_PX - 0.5
    hi = MARGIN_PX + (cells - 1) * CELL_PX - 0.5
    return np.array([[lo, lo], [hi, lo], [hi, hi], [lo, hi]])


def read_truth(path):
    """Tag id -> its 4 corners (x, y), pixel centres at whole numbers as everywhere in amcr. The file
    gives ViSP's image points, (row, column), as the AprilTag library computes them: with a pixel's
    centre at +0.5 (the library's convention, confirmed by its maintainers), so half a pixel is
    taken off both."""
    truth, tag = {}, None
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line:
                continue
            if "_id:" in line:
                tag = int(line.split("_")[-1])
                truth[tag] = []
            else:
                row, column = (float(v) for v in line.split())
                truth[tag].append([column - 0.5, row - 0.5])
    return {k: np.array(v) for k, v in truth.items()}


def project(h, points):
    p = np.hstack([points, np.ones((len(points), 1))]) @ np.array(h).T
    return p[:, :2] / p[:, 2:3]


def template_to_photo(corners, truth_corners, order):
    """The template -> photo homography that takes the template's corners in `order` to the truth's."""
    return cv2.getPerspectiveTransform(np.float32(corners[ORDERS[order]]), np.float32(truth_corners))


def corner_order(photo, truth, templates, corners):
    """The index into ORDERS under which the photo, warped back onto each template, looks most like it
    (the summed correlation over the tags' black squares): ViSP numbers the corners its own way."""
    lo, hi = int(np.ceil(corners[0, 0])), int(corners[2, 0])
    scores = []
    for order in range(len(ORDERS)):
        score = 0.0
        for tag_id, truth_corners in truth.items():
            template = templates[tag_id]
            h = template_to_photo(corners, truth_corners, order)
            back = cv2.warpPerspective(photo, h, template.shape[::-1], flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP)
            score += cv2.matchTemplate(back[lo:hi, lo:hi], template[lo:hi, lo:hi], cv2.TM_CCOEFF_NORMED)[0, 0]
        scores.append(score)
    return int(np.argmax(scores))


def score_reports(objects, truth, corners, order):
    """The reports `objects` (label, template -> image "homography") against the truth: the corner errors
    of the right ones (right id, within RIGHT_PX) and how many others."""
    errors, others = [], 0
    for obj in objects:
        tag_id = int(obj["label"].split("-")[-1])
        if tag_id not in truth:
            others += 1
            continue
        mapped = project(obj["homography"], corners)[ORDERS[order]]
        error = float(np.mean(np.linalg.norm(mapped - truth[tag_id], axis=1)))
        if error <= RIGHT_PX:
            errors.append(error)
        else:
            others += 1
    return {"right_id_within_5px": len(errors), "within_1px": sum(e <= CLOSE_PX for e in errors),
            "median_corner_error_px": float(np.median(errors)) if errors else None, "other_reports": others}


def describe(row, tags):
    median = row["median_corner_error_px"]
    return ("%d of %d tags with the right id (corners within 5 px; %d within 1 px, median %s px), %d other reports, "
            "%.1f ms per frame" % (row["right_id_within_5px"], tags, row["within_1px"],
                                   "-" if median is None else "%.2f" % median, row["other_reports"], row["time_ms"]))


def main():
    parser = still_photo_parser(__doc__, "real-tags", "1-3")
    parser.add_argument("--methods", default="amcr", help="amcr, line2d and/or sc, comma-separated")
    parser.add_argument("--extra", type=int, default=0, help="other ids of the family added to the memory")
    parser.add_argument("--seed-memory", type=int, default=1)
    parser.add_argument("--as-silhouettes", action="store_true",
                        help="write the tags without alpha channel: two grey levels, read as silhouettes with holes")
    args = parser.parse_args()
    methods = parse_methods(args.methods)

    photo = os.path.join(PHOTO_DIR, "AprilTag.pgm")
    if not os.path.exists(photo):
        print("real_tags: %s is missing: apt-get install visp-images-data" % photo, file=sys.stderr)
        return 2
    truth = read_truth(os.path.join(PHOTO_DIR, "ground_truth_detection.txt"))
    lib, family = load_family()
    ncodes = family.contents.ncodes

    prototypes = os.path.join(args.out, "prototypes")
    os.makedirs(prototypes, exist_ok=True)
    for name in os.listdir(prototypes):
        os.remove(os.path.join(prototypes, name))
    ids = sorted(truth)
    others = [i for i in range(ncodes) if i not in truth]
    rng = np.random.default_rng(args.seed_memory)
    ids += sorted(rng.choice(others, size=min(args.extra, len(others)), replace=False).tolist())
    cells, templates = None, {}
    for tag_id in ids:
        image, cells = tag_image(lib, family, tag_id)
        templates[tag_id] = image[:, :, 0]
        if args.as_silhouettes:
            image = image[:, :, 0]
        cv2.imwrite(os.path.join(prototypes, "%s-%d.png" % (FAMILY, tag_id)), image)
    corners = black_square_corners(cells)
    order = corner_order(grey_photo(photo), truth, templates, corners)
    label = lambda tag_id: "%s-%d" % (FAMILY, tag_id)  # noqa: E731

    summary = {"photo": photo, "memory": len(ids), "frames": args.frames, "corner_order": ORDERS[order].tolist(),
               "methods": {}}
    print("AprilTag photo: %d tags, memory of %d %s tags as %s, truth corners = template corners %s"
          % (len(truth), len(ids), FAMILY, "silhouettes" if args.as_silhouettes else "grey templates",
             ORDERS[order].tolist()))

    if "amcr" in methods:
        rows = []
        for seed in parse_seeds(args.seeds):
            frames = run_still(args.bin, prototypes, photo, args.frames, seed,
                               os.path.join(args.out, "seed-%d.jsonl" % seed), args.config)
            first = {}
            for k, frame in enumerate(frames):
                for obj in frame["objects"]:
                    tag_id = int(obj["label"].split("-")[-1])
                    if tag_id not in first and score_reports([obj], truth, corners, order)["right_id_within_5px"]:
                        first[tag_id] = k
            row = score_reports(frames[-1]["objects"], truth, corners, order)
            row.update(seed=seed, time_ms=float(np.median([f["time_ms"] for f in frames])),
                       first_frames={str(k): v for k, v in sorted(first.items())})
            rows.append(row)
            print("amcr seed %d, at frame %d: %s; first right frames %s"
                  % (seed, len(frames) - 1, describe(row, len(truth)), row["first_frames"]))
        summary["methods"]["amcr"] = {"seeds": rows}

    baselines = [m for m in methods if m in BASELINES]
    if baselines:
        suite = os.path.join(args.out, "suite")
        write_still_suite(suite, photo, [(label(t), templates[t].shape[::-1], template_to_photo(corners, c, order))
                                         for t, c in sorted(truth.items())])
        results = run_baselines(args.bin, suite, prototypes, baselines, TARGET_SIZE, ANISOTROPY,
                                os.path.join(args.out, "baselines"), ["--line2d-reports", str(len(ids))])
        for method in baselines:
            objects, time_ms = results[method]
            row = score_reports(objects, truth, corners, order)
            row["time_ms"] = time_ms
            summary["methods"][method] = row
            print("%s, the photo once: %s" % (method, describe(row, len(truth))))
    with open(os.path.join(args.out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
