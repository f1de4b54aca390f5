"""What every section of the benchmark report (bench/report.py) uses: the methods and suites in the
report's order, the suites some sections treat apart, the aims, reading amcr_evaluate's JSON lines,
the prototype->image affine, means and medians that allow no values, and the figures' format."""

import json
import math
import statistics

import numpy as np

METHODS = ["amcr", "line2d", "sc", "orb", "hu", "ght"]
SUITES = ["paper", "mpeg7-70", "within-class", "within-class-1330", "within-class-85", "similar", "clutter-only",
          "two-objects", "copies", "real-photos", "oblique", "faint", "real-camera", "real-camera-cube", "paper-hd",
          "clutter-only-hd"]
# The shown instance is in no memory (the label is the class): no affine or correspondence error.
WITHIN_CLASS_SUITES = ["within-class", "within-class-1330", "within-class-85"]
GROWTH = "memory-growth"
HD_PAIRS = [("paper", "paper-hd"), ("clutter-only", "clutter-only-hd")]  # 640x480 suite, its 1280x720 one
GROWTH_AIM = 1.5  # the aim: time per frame with 70 prototypes at most 1.5x that with 3
HD_AIM = 0.10  # the aim: 1280x720 top-1 within 10 points of 640x480
METHOD_NAMES = {"amcr": "AMCR", "line2d": "LINE-2D", "sc": "shape contexts", "orb": "ORB+RANSAC", "hu": "Hu moments",
                "ght": "GHT Guil"}
CHECKPOINTS = [10, 30, 60]


def read_jsonl(path):
    with open(path) as f:
        return {row["frame"]: row for row in map(json.loads, f) if row}


def corners(size):
    w, h = size
    return np.array([[0, 0, 1], [w - 1, 0, 1], [w - 1, h - 1, 1], [0, h - 1, 1]], dtype=np.float64)


def affine(values):
    return np.asarray(values, dtype=np.float64).reshape(2, 3)


def median(values):
    return statistics.median(values) if values else None


def mean(values):
    return sum(values) / len(values) if values else None


def fmt(value, kind):
    if value is None:
        return "n/a"
    if kind == "pct":
        return "%.0f%%" % (100 * value)
    if kind == "frames":
        return "never" if value == math.inf else "%g" % value
    if kind == "px":
        return "%.2f" % value
    if kind == "count":
        return "%d" % value
    if kind == "ms":
        return "%.1f" % value if value < 100 else "%.0f" % value
    return "%.3f" % value


def top1_at(m, n):
    """Top-1 at frame n, or at the last frame when the sequences are shorter."""
    if not m.get("top1"):
        return None
    return m["top1"].get(n, m["top1"].get(m["last_frame"]) if m["last_frame"] < n else None)
