"""The sections of the real-camera suites (`real-camera`, `real-camera-cube`) in the benchmark report:
their text, and per sequence and method the target's first report, the share of scored frames at the
right place against the truth homography, the false reports and the corner error."""

import glob
import json
import math
import os

import numpy as np

from report_common import METHOD_NAMES, METHODS, affine, fmt, mean, median, read_jsonl

RIGHT_PLACE = 0.10  # real-camera: every corner within this share of the target's image diagonal
REAL_CAMERA_SUITES = ["real-camera", "real-camera-cube"]  # real frames: a homography per frame, or unknown

REAL_TEXT = """\
Real frames (Debian's visp-images-data, grey, at their own size); memory: the target `mire`
drawn from its measured geometry (bench/real_camera.py) and 16 of the paper's prototypes. The truth
is a homography per frame from the target's own pattern and edges (bench/real_camera.py), unknown
frames unscored. The aim for a real camera's views: >= 90% of the scored frames at the right place
after the first report, the first report within 30 frames."""

REAL_CUBE_TEXT = """\
Real frames of visp-images-data's `cube` (80, 384x288 grey: a hand-held camera over a black cube with
white dots on a comic-book collage); memory: the target `cube-face` (the face towards the camera, a
square with a ring of 12 dots) drawn from its measured geometry (bench/real_camera_cube.py) and 16 of
the paper's prototypes. The truth is a homography per frame from the face's dots and edges
(bench/real_camera_cube.py), unknown frames unscored; its four quarter turns count as one (its dots
are 4-fold symmetric but for a shift of 4% of the side). The face is small: 68-86 px."""
REAL_TEXTS = {"real-camera": REAL_TEXT, "real-camera-cube": REAL_CUBE_TEXT}


def apply_h(h, points):
    p = np.hstack([points, np.ones((len(points), 1))]) @ np.asarray(h, dtype=np.float64).T
    return p[:, :2] / p[:, 2:3]


def real_camera_sequence(truth, rows):
    """Per-sequence figures of one method on a real-camera sequence."""
    label = truth["targets"][0]["label"]
    points = np.asarray(truth["score_points"], dtype=np.float64)
    symmetries = truth.get("symmetries", [[0, 1, 2, 3]])
    first, scored, right, errors, false_reports, wrong_place, frames_run = None, 0, 0, [], 0, 0, 0
    after, right_after = 0, 0
    for t in truth["frames"]:
        k = t["frame"]
        if k not in rows:
            continue
        frames_run += 1
        reported = rows[k]["objects"]
        mine = [r for r in reported if r["label"] == label]
        false_reports += len(reported) - len(mine)
        if mine and first is None:
            first = k + 1
        if t.get("unknown"):
            continue
        scored += 1
        true = apply_h(t["objects"][0]["homography"], points)
        diagonal = (np.linalg.norm(true[2] - true[0]) + np.linalg.norm(true[3] - true[1])) / 2
        here = False
        for i, r in enumerate(mine):
            got = points @ affine(r["prototype_to_image"])[:, :2].T + affine(r["prototype_to_image"])[:, 2]
            dist = min((np.linalg.norm(got[perm] - true, axis=1) for perm in symmetries), key=np.max)
            ok = float(np.max(dist)) <= RIGHT_PLACE * diagonal
            here = here or ok
            wrong_place += not ok
            if i == 0:
                errors.append(float(np.mean(dist)))
        right += here
        if first is not None and k + 1 >= first:
            after += 1
            right_after += here
    return {"frames_run": frames_run, "scored": scored, "first_report": first, "right_share_after_first":
            right_after / after if after else None, "scored_after_first": after, "right_share": right / scored
            if scored else None, "false_per_frame": false_reports / frames_run if frames_run else None,
            "wrong_place_per_scored": wrong_place / scored if scored else None, "corner_error_median": median(errors),
            "time_mean_ms": mean([rows[k]["time_ms"] for k in rows])}


def real_camera_metrics(out, suite, methods, res_dir=None):
    """method -> sequence -> real_camera_sequence's figures; the results in `res_dir` (default
    <out>/results/<suite>)."""
    seq_dir = os.path.join(out, "sequences", suite)
    res_dir = res_dir or os.path.join(out, "results", suite)
    metrics = {}
    for path in sorted(glob.glob(os.path.join(seq_dir, "seq_*", "truth.json"))):
        name = os.path.basename(os.path.dirname(path))
        with open(path) as f:
            truth = json.load(f)
        for method in methods:
            result = os.path.join(res_dir, "%s.%s.jsonl" % (name, method))
            if os.path.exists(result):
                m = real_camera_sequence(truth, read_jsonl(result))
                m["source"] = truth.get("source", name)
                metrics.setdefault(method, {})[name] = m
    return metrics


def real_camera_table(metrics):
    lines = []
    names = sorted({n for per in metrics.values() for n in per})
    for name in names:
        methods = [m for m in METHODS if name in metrics.get(m, {})]
        first = metrics[methods[0]][name]
        lines += ["%s (%d frames run, %d scored; right place: every corner within %d%% of the target's "
                  "diagonal):" % (first["source"], first["frames_run"], first["scored"], 100 * RIGHT_PLACE), "",
                  "| | " + " | ".join(METHOD_NAMES[m] for m in methods) + " |", "|---" * (len(methods) + 1) + "|"]
        for title, key, kind in (("first report of the target (frame)", "first_report", "frames"),
                                 ("scored frames at the right place from the first report on",
                                  "right_share_after_first", "pct"),
                                 ("scored frames at the right place (all)", "right_share", "pct"),
                                 ("false reports per frame (other labels)", "false_per_frame", ""),
                                 ("reports of the target at a wrong place per scored frame",
                                  "wrong_place_per_scored", ""),
                                 ("corner error of the target's best report, median (px)", "corner_error_median",
                                  "px"),
                                 ("time per frame, mean (ms)", "time_mean_ms", "ms")):
            values = [metrics[m][name][key] for m in methods]
            if key == "first_report":  # never reported
                values = [math.inf if v is None else v for v in values]
            lines.append("| %s | %s |" % (title, " | ".join(fmt(v, kind) for v in values)))
        lines.append("")
    return "\n".join(lines)
