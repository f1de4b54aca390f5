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
--seed-memory) as look-alikes. amcr_offline runs the still photo for --frames frames per recognizer
seed. For each seed the report gives, at the last frame: the tags reported with the right id and
their corners' error against the truth (the mean over the four corners, in the corner order that
suits most tags, which the report names), the reports with a wrong id, and the first frame each tag
was reported right.

    bench/real_tags.py --out .build/real-tags [--seeds 1-3] [--frames 60] [--extra 0]

Needs libapriltag3 (Debian: `apt-get install libapriltag3`) and visp-images-data; says which is
missing and exits 2 otherwise.
"""
import argparse
import ctypes
import ctypes.util
import json
import os
import sys

import cv2
import numpy as np

from still_photo import parse_seeds, run_still

PHOTO_DIR = "/usr/share/visp-images-data/ViSP-images/AprilTag"
FAMILY = "tag36h11"
CELL_PX = 20       # template px per tag cell: 10 cells (the white border included) = 200 px
MARGIN_PX = 2      # transparent px around the tag: the alpha channel makes the image a template
HERE = os.path.dirname(os.path.abspath(__file__))


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
    centre at +0.5 (AprilRobotics/apriltag issue #121), so half a pixel is taken off both."""
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


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    parser.add_argument("--out", default=os.path.join(HERE, "..", ".build", "real-tags"))
    parser.add_argument("--bin", default=os.path.join(HERE, "..", ".build", "ws", "devel", "lib", "amcr"))
    parser.add_argument("--config", default="", help="parameter file for amcr_offline (default: its defaults)")
    parser.add_argument("--seeds", default="1-3")
    parser.add_argument("--frames", type=int, default=60)
    parser.add_argument("--extra", type=int, default=0, help="other ids of the family added to the memory")
    parser.add_argument("--seed-memory", type=int, default=1)
    parser.add_argument("--as-silhouettes", action="store_true",
                        help="write the tags without alpha channel: two grey levels, read as silhouettes with holes")
    args = parser.parse_args()

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
    cells = None
    for tag_id in ids:
        image, cells = tag_image(lib, family, tag_id)
        if args.as_silhouettes:
            image = image[:, :, 0]
        cv2.imwrite(os.path.join(prototypes, "%s-%d.png" % (FAMILY, tag_id)), image)
    corners = black_square_corners(cells)

    results = []
    for seed in parse_seeds(args.seeds):
        output = os.path.join(args.out, "seed-%d.jsonl" % seed)
        results.append((seed, run_still(args.bin, prototypes, photo, args.frames, seed, output, args.config)))

    # The corner order that suits most right reports (ViSP's detector numbers them its own way):
    # one of the 4 turns of the template's clockwise corners, or of the reversed order.
    orders = [np.roll(np.arange(4), k) for k in range(4)] + [np.roll(np.arange(4)[::-1], k) for k in range(4)]

    def errors(obj, tag_id, order):
        mapped = project(obj["homography"], corners)[orders[order]]
        return float(np.mean(np.linalg.norm(mapped - truth[tag_id], axis=1)))

    votes = np.zeros(len(orders))
    for _, frames in results:
        for obj in frames[-1]["objects"]:
            tag_id = int(obj["label"].split("-")[-1])
            if tag_id in truth:
                votes[int(np.argmin([errors(obj, tag_id, o) for o in range(len(orders))]))] += 1
    shift = int(np.argmax(votes))

    summary = {"photo": photo, "memory": len(ids), "frames": args.frames, "corner_order": orders[shift].tolist(),
               "seeds": []}
    print("AprilTag photo: %d tags, memory of %d %s tags as %s, %d frames, truth corners = template corners %s"
          % (len(truth), len(ids), FAMILY, "silhouettes" if args.as_silhouettes else "grey templates", args.frames,
             orders[shift].tolist()))
    for seed, frames in results:
        last = frames[-1]["objects"]
        right, wrong, errs = 0, 0, []
        first = {}
        for k, frame in enumerate(frames):
            for obj in frame["objects"]:
                tag_id = int(obj["label"].split("-")[-1])
                if tag_id in truth and errors(obj, tag_id, shift) <= 5.0 and tag_id not in first:
                    first[tag_id] = k
        for obj in last:
            tag_id = int(obj["label"].split("-")[-1])
            e = errors(obj, tag_id, shift) if tag_id in truth else float("inf")
            if e <= 5.0:
                right += 1
                errs.append(e)
            else:
                wrong += 1
        within1 = sum(e <= 1.0 for e in errs)
        row = {"seed": seed, "right_id_within_5px": right, "within_1px": within1, "other_reports": wrong,
               "median_corner_error_px": float(np.median(errs)) if errs else None,
               "first_frames": {str(k): v for k, v in sorted(first.items())}}
        summary["seeds"].append(row)
        print("seed %d: at frame %d, %d of %d tags with the right id (corners within 5 px; %d within 1 px, median %s px), "
              "%d other reports; first right frames %s"
              % (seed, len(frames) - 1, right, len(truth), within1,
                 "%.2f" % row["median_corner_error_px"] if errs else "-", wrong, row["first_frames"]))
    with open(os.path.join(args.out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
