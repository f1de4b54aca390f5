#!/usr/bin/python3
"""Turn a benchmark run into figures: metrics per suite and method, Markdown tables, PNG plots.

Reads <out>/sequences (truth), <out>/results/<suite>/<seq>.<method>.jsonl (amcr_evaluate),
<out>/speed.json (Google Benchmark) and <out>/latency.json (nodelet latency), when present.
Writes <out>/report.md, <out>/summary.md (the summary and the speed only), <out>/metrics.json
and <out>/plots/*.png.

Definitions (frames are numbered from 1):
- top-1 at frame N: the best-scored report of frame N has a label of an object in view;
- held from: the first frame from which the top-1 stays correct to the last frame;
- false positives per frame: reports whose label is not in view (every report in clutter-only);
- affine error: mean distance (px) between the prototype's 4 corners mapped by the reported and by
  the true prototype->image affine, over reports with a right label (not for within-class,
  within-class-1330 and within-class-85, where the memory holds other instances than the one shown:
  the label is the class);
- correspondence error: median distance (px) between a reported image point and the true image of
  its prototype point.
- `oblique`: the same, and top-1 split by the sequence's anisotropy (1.5-2, 2-2.5, 2.5-3).
- `real-camera`, `real-camera-cube` (truth: a homography per frame, or unknown): frames whose truth
  is unknown are not
  scored. Corner error of a report of the target: the target's 4 corners (`score_points`) mapped by
  the reported affine against the truth homography, the best over the target's `symmetries`; at the
  right place when every corner is within 10% of the target's image diagonal (mean of its two
  diagonals). Metrics: the frame of the first report of the target (any place), the share of scored
  frames from that one on with the target reported at the right place, false reports per frame
  (labels other than the target's, over every frame run), reports of the target at a wrong place per
  scored frame, and the median over scored frames of the mean corner error of the best-scored report
  of the target.
- `memory-growth` (results/memory-growth/memory-<n>/, one run per memory of n prototypes on the same
  sequences): per memory the median time per frame, its ratio to the 3-prototype memory's, top-1 at
  frame 60 (at the last frame when shorter) and the median over sequences of the frames to the first
  correct report (the first frame whose best-scored report has the target's label; never = inf).
- instances (`two-objects`, `copies`, `real-photos`; issue 15): per frame, every truth instance is
  matched one-to-one to a report of its label whose outline centre (the centroid of the prototype's
  silhouette mapped by the reported affine, so that a shape that looks the same turned, as a brick,
  reported turned is still at its centre) lies within max(10 px, 0.3 x the instance's size: the
  prototype's longer side times the truth affine's scale) of the instance's centre (the truth's
  "center", else that centroid mapped by the truth affine); the matching has the most pairs. Metrics: the mean share of
  instances found per frame (all frames; frames >= 60, or the last frame when shorter), the share of
  sequences with all instances found at frame 60 (the last when shorter), and all found and held:
  all found at that frame and in at least 90% of the frames after it. When reports carry "track_id":
  the mean number of distinct track ids per instance found at least once (fragmentation); when they
  carry "state": the share of the matched reports per state. With copies in view, the affine error
  takes the instance of the label nearest the report (and, in `real-photos`, whose part is symmetric
  under a half turn, the better of the truth affine and it turned by half a turn).
- recall funnel (AMCR, every suite with truth; bench/funnel_report.py): the share of frames at each
  stage from a V-particle on the object to the report, and where each object not reported at the
  right place at frame 60 stopped.
- `paper-hd`, `clutter-only-hd` (the same frames at 1280x720): their figures beside those of `paper`
  and `clutter-only` of the same run; differences in points; corner errors in each suite's own pixels
  (1280x720 ones are 1.5x as large for the same error on the scene).
"""

import argparse
import glob
import json
import math
import os
import statistics

import cv2
import numpy as np

import funnel_report  # bench/funnel_report.py, beside this script

METHODS = ["amcr", "line2d", "sc", "orb", "hu", "ght"]
SUITES = ["paper", "mpeg7-70", "within-class", "within-class-1330", "within-class-85", "similar", "clutter-only",
          "two-objects", "copies", "real-photos", "oblique", "faint", "real-camera", "real-camera-cube", "paper-hd",
          "clutter-only-hd"]
# The shown instance is in no memory (the label is the class): no affine or correspondence error.
WITHIN_CLASS_SUITES = ["within-class", "within-class-1330", "within-class-85"]
GROWTH = "memory-growth"
HD_PAIRS = [("paper", "paper-hd"), ("clutter-only", "clutter-only-hd")]  # 640x480 suite, its 1280x720 one
GROWTH_AIM = 1.5  # issue 14: time per frame with 70 prototypes at most 1.5x that with 3
HD_AIM = 0.10  # issue 14: 1280x720 top-1 within 10 points of 640x480
ANISOTROPY_BANDS = [(1.5, 2.0), (2.0, 2.5), (2.5, 3.0)]
RIGHT_PLACE = 0.10  # real-camera: every corner within this share of the target's image diagonal
REAL_CAMERA_SUITES = ["real-camera", "real-camera-cube"]  # real frames: a homography per frame, or unknown
METHOD_NAMES = {"amcr": "AMCR", "line2d": "LINE-2D", "sc": "shape contexts", "orb": "ORB+RANSAC", "hu": "Hu moments",
                "ght": "GHT Guil"}
CHECKPOINTS = [10, 30, 60]
INSTANCE_SUITES = ["two-objects", "copies", "real-photos"]  # issue 15: every instance in view is to be reported
INSTANCE_RADIUS = (10.0, 0.3)  # a report finds an instance within max(10 px, 0.3 x the instance's size)
INSTANCE_AT = 60  # "all found" at this frame (the last one when shorter)
INSTANCE_HOLD = 0.9  # "held": all found in at least this share of the frames after INSTANCE_AT


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


def evaluate_sequence(truth, rows, sizes, geometry):
    """Per-frame outcomes of one method on one sequence."""
    frames = []
    for t in truth["frames"]:
        k = t["frame"]
        if k not in rows:
            continue
        labels = [o["label"] for o in t["objects"]]
        reported = rows[k]["objects"]
        top = reported[0]["label"] if reported else None
        outcome = {"frame": k + 1, "time_ms": rows[k]["time_ms"],
                   "top1": bool(labels) and top in labels,
                   "all_found": bool(labels) and all(l in {r["label"] for r in reported} for l in labels),
                   "false_positives": sum(r["label"] not in labels for r in reported),
                   "affine_errors": [], "corr_errors": []}
        if geometry:
            for r in reported:
                if r["label"] not in labels:
                    continue
                got = affine(r["prototype_to_image"])
                # The instance of that label nearest the report (several when copies are in view).
                size = sizes[r["label"]]
                true = affine(min((o for o in t["objects"] if o["label"] == r["label"]), key=lambda o: np.linalg.norm(
                    centre_of(o["prototype_to_image"], size) - centre_of(got, size)))["prototype_to_image"])
                c = corners(sizes[r["label"]])
                candidates = [true]
                if truth.get("half_turn_symmetric"):  # the instance turned by half a turn looks the same
                    candidates.append(true @ np.array([[-1.0, 0.0, size[0] - 1], [0.0, -1.0, size[1] - 1], [0, 0, 1]]))
                error, true = min(((float(np.mean(np.linalg.norm(c @ got.T - c @ a.T, axis=1))), a)
                                   for a in candidates), key=lambda e: e[0])
                outcome["affine_errors"].append(error)
                for xi, yi, xp, yp in r["correspondences"]:
                    expected = true @ np.array([xp, yp, 1.0])
                    outcome["corr_errors"].append(float(math.hypot(xi - expected[0], yi - expected[1])))
        frames.append(outcome)
    return frames


def centre_of(matrix, size, point=None):
    """A prototype point (default: the centre of its image of `size` = (w, h)) mapped by a
    prototype->image affine."""
    w, h = size
    x, y = ((w - 1) / 2.0, (h - 1) / 2.0) if point is None else point
    return affine(matrix) @ np.array([x, y, 1.0])


def instance_size(matrix, size):
    """A truth instance's size in the image: the prototype's longer side times the affine's scale."""
    return max(size) * math.sqrt(abs(np.linalg.det(affine(matrix)[:, :2])))


def match_instances(objects, reported, sizes, centres=None):
    """One-to-one matching of a frame's truth instances to the reports: a report may find an instance
    of its own label whose centre ("center" when the truth gives it, else the prototype's centre
    mapped by the truth's affine) is within max(10 px, 0.3 x the instance's size) of the report's
    outline centre (the prototype's centre mapped by the reported affine). The prototype's centre is
    `centres[label]` when given (the report uses the silhouette's centroid: a shape that looks the
    same turned, as a brick, then has its centre where it is), else the middle of its image. The
    matching has the most pairs (augmenting paths, nearer reports tried first). Returns per instance
    its report's index in `reported`, or None."""
    candidates = []
    for o in objects:
        if "prototype_to_image" not in o:
            candidates.append([])
            continue
        size, point = sizes[o["label"]], (centres or {}).get(o["label"])
        centre = np.asarray(o["center"], dtype=np.float64) if "center" in o else \
            centre_of(o["prototype_to_image"], size, point)
        radius = max(INSTANCE_RADIUS[0], INSTANCE_RADIUS[1] * instance_size(o["prototype_to_image"], size))
        near = [(float(np.linalg.norm(centre_of(r["prototype_to_image"], size, point) - centre)), j)
                for j, r in enumerate(reported) if r["label"] == o["label"]]
        candidates.append([j for d, j in sorted(near) if d <= radius])
    owner = {}  # report index -> instance index

    def augment(i, seen):
        for j in candidates[i]:
            if j not in seen:
                seen.add(j)
                if j not in owner or augment(owner[j], seen):
                    owner[j] = i
                    return True
        return False

    for i in range(len(objects)):
        augment(i, set())
    found = [None] * len(objects)
    for j, i in owner.items():
        found[i] = j
    return found


def instance_sequence(truth, rows, sizes, centres=None):
    """Instance-level figures of one method on one sequence: per frame run (1-based, frames with
    objects in view and a known truth) the share of instances found and whether all are; "all found
    at frame 60" (the last frame when shorter), "all found and held" (that, and all found in at least
    90% of the frames after it); per truth instance (its index in the frame's objects) the track ids
    of the reports that found it, and the states of those reports, when the method reports them."""
    total = len(truth["frames"])
    at = min(INSTANCE_AT, total)
    shares, all_found, tracks, states = {}, {}, {}, {}
    for t in truth["frames"]:
        k = t["frame"]
        if k not in rows or t.get("unknown") or not t["objects"]:
            continue
        reported = rows[k]["objects"]
        found = match_instances(t["objects"], reported, sizes, centres)
        shares[k + 1] = sum(j is not None for j in found) / len(found)
        all_found[k + 1] = all(j is not None for j in found)
        for i, j in enumerate(found):
            if j is not None and "track_id" in reported[j]:
                tracks.setdefault(i, set()).add(reported[j]["track_id"])
            if j is not None and "state" in reported[j]:
                states[reported[j]["state"]] = states.get(reported[j]["state"], 0) + 1
    after = [all_found[n] for n in all_found if n > at]
    return {"shares": shares, "all_at": all_found.get(at, False),
            "held": all_found.get(at, False) and (not after or sum(after) / len(after) >= INSTANCE_HOLD),
            "tracks": tracks, "states": states, "at": at}


def instance_metrics(out, suite, methods):
    """method -> instance-level metrics over a suite's sequences (instance_sequence)."""
    seq_dir = os.path.join(out, "sequences", suite)
    sizes, centres = {}, {}
    for p in glob.glob(os.path.join(seq_dir, "prototypes", "*.png")):
        image = cv2.imread(p, cv2.IMREAD_GRAYSCALE)
        label = os.path.splitext(os.path.basename(p))[0]
        sizes[label] = (image.shape[1], image.shape[0])
        m = cv2.moments((image > 127).astype(np.uint8), True)
        centres[label] = (m["m10"] / m["m00"], m["m01"] / m["m00"])  # the silhouette's centroid
    metrics = {}
    for method in methods:
        per_seq = []
        for path in sorted(glob.glob(os.path.join(seq_dir, "seq_*", "truth.json"))):
            result = os.path.join(out, "results", suite, "%s.%s.jsonl" % (os.path.basename(os.path.dirname(path)), method))
            if os.path.exists(result):
                with open(path) as f:
                    per_seq.append(instance_sequence(json.load(f), read_jsonl(result), sizes, centres))
        if per_seq:
            metrics[method] = instance_summary(per_seq)
    return metrics


def instance_summary(per_seq):
    """Pools instance_sequence's figures over sequences."""
    shares = [v for s in per_seq for v in s["shares"].values()]
    late = [v for s in per_seq for n, v in s["shares"].items() if n >= s["at"]]
    m = {"sequences": len(per_seq), "found_share": mean(shares), "found_share_late": mean(late),
         "all_at": mean([s["all_at"] for s in per_seq]), "all_held": mean([s["held"] for s in per_seq]),
         "at": min(s["at"] for s in per_seq)}
    tracks = [len(ids) for s in per_seq for ids in s["tracks"].values()]
    if tracks:  # the method reports track ids: track ids per instance found at least once
        m["tracks_per_instance"] = mean(tracks)
    states = {}
    for s in per_seq:
        for state, n in s["states"].items():
            states[state] = states.get(state, 0) + n
    if states:
        m["states"] = {state: n / sum(states.values()) for state, n in sorted(states.items())}
    return m


def instance_table(metrics):
    methods = [m for m in METHODS if m in metrics]
    at = min(metrics[m]["at"] for m in methods)
    lines = ["Instances (issue 15): per frame, each instance in view is matched to at most one report of its label "
             "whose outline centre (its silhouette's centroid) is within max(%g px, %g x the instance's size) of the instance's centre, one "
             "report to one instance at most. All found and held: all instances found at frame %d and in at least "
             "%d%% of the frames after it." % (INSTANCE_RADIUS[0], INSTANCE_RADIUS[1], at, 100 * INSTANCE_HOLD), "",
             "| | " + " | ".join(METHOD_NAMES[m] for m in methods) + " |", "|---" * (len(methods) + 1) + "|"]
    rows = [("instances found per frame, mean (all frames)", "found_share", "pct"),
            ("instances found per frame, mean (frames >= %d)" % at, "found_share_late", "pct"),
            ("sequences with all instances found at frame %d" % at, "all_at", "pct"),
            ("sequences with all found and held by frame %d" % at, "all_held", "pct")]
    if any("tracks_per_instance" in metrics[m] for m in methods):
        rows.append(("track ids per instance (instances found at least once)", "tracks_per_instance", ""))
    for title, key, kind in rows:
        lines.append("| %s | %s |" % (title, " | ".join(fmt(metrics[m].get(key), kind) for m in methods)))
    if any("states" in metrics[m] for m in methods):
        lines.append("| reports finding an instance, by state | %s |" % " | ".join(
            ", ".join("%s %s" % (k, fmt(v, "pct")) for k, v in metrics[m].get("states", {}).items()) or "n/a"
            for m in methods))
    return "\n".join(lines) + "\n"


def held_from(frames, total):
    """1-based frame from which top-1 stays right to the end; None when never (or not every frame ran)."""
    if len(frames) != total:
        return None
    start = None
    for f in frames:
        if f["top1"]:
            start = f["frame"] if start is None else start
        else:
            start = None
    return start


def suite_metrics(out, suite, methods, res_dir=None):
    seq_dir = os.path.join(out, "sequences", suite)
    res_dir = res_dir or os.path.join(out, "results", suite)
    sizes = {}
    for p in glob.glob(os.path.join(seq_dir, "prototypes", "*.png")):
        image = cv2.imread(p, cv2.IMREAD_GRAYSCALE)
        sizes[os.path.splitext(os.path.basename(p))[0]] = (image.shape[1], image.shape[0])
    truths = {}
    for path in sorted(glob.glob(os.path.join(seq_dir, "seq_*", "truth.json"))):
        with open(path) as f:
            truths[os.path.basename(os.path.dirname(path))] = json.load(f)
    has_target = any(t["frames"][0]["objects"] for t in truths.values())
    geometry = suite not in WITHIN_CLASS_SUITES

    metrics = {}
    for method in methods:
        per_seq = {}
        for name, truth in truths.items():
            path = os.path.join(res_dir, "%s.%s.jsonl" % (name, method))
            if os.path.exists(path):
                per_seq[name] = (evaluate_sequence(truth, read_jsonl(path), sizes, geometry), len(truth["frames"]))
        if not per_seq:
            continue
        all_frames = [f for frames, _ in per_seq.values() for f in frames]
        m = {"sequences": len(per_seq), "frames_run": len(all_frames)}
        accuracy = {}
        last = min(total for _, total in per_seq.values())
        for n in [c for c in CHECKPOINTS if c < last] + [last]:
            at = [f for frames, _ in per_seq.values() for f in frames if f["frame"] == n]
            if at and has_target:
                accuracy[n] = sum(f["top1"] for f in at) / len(at)
        m["top1"] = accuracy
        m["last_frame"] = last
        if has_target:
            at_last = [frames[-1] for frames, total in per_seq.values() if frames and frames[-1]["frame"] == total]
            m["all_found_last"] = mean([f["all_found"] for f in at_last])
            held = [held_from(frames, total) for frames, total in per_seq.values()]
            if all(len(frames) == total for frames, total in per_seq.values()):
                m["held_share"] = sum(h is not None for h in held) / len(held)
                m["held_median"] = median([h if h is not None else math.inf for h in held])
            curve = {}
            for f in all_frames:
                curve.setdefault(f["frame"], []).append(f["top1"])
            m["curve"] = {k: sum(v) / len(v) for k, v in sorted(curve.items())}
            # Frames to the first correct report: the first frame whose top-1 is right (inf: never).
            firsts = [next((f["frame"] for f in frames if f["top1"]), math.inf) for frames, _ in per_seq.values()]
            m["first_correct_median"] = median(firsts)
            m["first_correct"] = firsts
        m["fp_per_frame"] = mean([f["false_positives"] for f in all_frames])
        m["affine_median"] = median([e for f in all_frames for e in f["affine_errors"]])
        m["affine_last_median"] = median([f["affine_errors"][0] for frames, _ in per_seq.values()
                                          for f in frames[-1:] if f["affine_errors"]])
        m["corr_median"] = median([e for f in all_frames for e in f["corr_errors"]])
        times = [f["time_ms"] for f in all_frames]
        m["time_mean_ms"] = mean(times)
        m["time_median_ms"] = median(times)
        init = os.path.join(res_dir, "init.%s.json" % method)
        if os.path.exists(init):
            with open(init) as f:
                m["init"] = json.load(f)
        metrics[method] = m
    return metrics, has_target


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


def real_camera_metrics(out, suite, methods):
    seq_dir = os.path.join(out, "sequences", suite)
    metrics = {}
    for path in sorted(glob.glob(os.path.join(seq_dir, "seq_*", "truth.json"))):
        name = os.path.basename(os.path.dirname(path))
        with open(path) as f:
            truth = json.load(f)
        for method in methods:
            result = os.path.join(out, "results", suite, "%s.%s.jsonl" % (name, method))
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


def anisotropy_table(out, suite):
    """Top-1 (at the last frame, and over all frames) per anisotropy band, per method."""
    cells = {}
    for path in sorted(glob.glob(os.path.join(out, "sequences", suite, "seq_*", "truth.json"))):
        name = os.path.basename(os.path.dirname(path))
        with open(path) as f:
            truth = json.load(f)
        if "anisotropy" not in truth:
            return ""
        band = next((b for b in ANISOTROPY_BANDS if b[0] <= truth["anisotropy"] < b[1]), ANISOTROPY_BANDS[-1])
        labels = [o["label"] for o in truth["frames"][-1]["objects"]]
        for method in METHODS:
            result = os.path.join(out, "results", suite, "%s.%s.jsonl" % (name, method))
            if not os.path.exists(result):
                continue
            rows = read_jsonl(result)
            top = lambda k: bool(rows[k]["objects"]) and rows[k]["objects"][0]["label"] in labels
            c = cells.setdefault((band, method), {"last": [], "all": []})
            last = truth["frames"][-1]["frame"]
            if last in rows:
                c["last"].append(top(last))
            c["all"] += [top(k) for k in rows]
    methods = [m for m in METHODS if any(k[1] == m for k in cells)]
    if not methods:
        return ""
    lines = ["Top-1 by anisotropy (the affine's singular-value ratio; degrees off the print's normal = "
             "arccos(1/anisotropy)): at the last frame (sequences), and over all frames run:", "",
             "| anisotropy | " + " | ".join(METHOD_NAMES[m] for m in methods) + " |", "|---" * (len(methods) + 1) + "|"]
    for band in ANISOTROPY_BANDS:
        row = []
        for m in methods:
            c = cells.get((band, m))
            row.append("n/a" if not c or not c["last"] else "%s of %d at the last frame, %s of frames" % (
                fmt(mean(c["last"]), "pct"), len(c["last"]), fmt(mean(c["all"]), "pct")))
        lines.append("| %.1f-%.1f (%.0f-%.0f deg) | %s |" % (band[0], band[1], math.degrees(math.acos(1 / band[0])),
                                                             math.degrees(math.acos(1 / band[1])), " | ".join(row)))
    return "\n".join(lines) + "\n"


def growth_metrics(out):
    """memory size -> AMCR's metrics on `memory-growth` with that memory."""
    found = {}
    for d in glob.glob(os.path.join(out, "results", GROWTH, "memory-*")):
        n = os.path.basename(d).split("-", 1)[1]
        if n.isdigit():
            metrics, _ = suite_metrics(out, GROWTH, ["amcr"], res_dir=d)
            if "amcr" in metrics:
                found[int(n)] = metrics["amcr"]
    return dict(sorted(found.items()))


def growth_ratio(growth):
    """(smallest, largest, ratio of their median times per frame), or None."""
    if len(growth) < 2:
        return None
    small, large = min(growth), max(growth)
    a, b = growth[small]["time_median_ms"], growth[large]["time_median_ms"]
    return (small, large, b / a) if a and b is not None else None


def growth_section(growth):
    small = min(growth)
    base = growth[small]["time_median_ms"]
    m0 = next(iter(growth.values()))
    at = min(60, m0["last_frame"])
    lines = ["AMCR on the same %d sequences (%d frames) with memories of %s prototypes (nested; the "
             "targets are in the smallest): time per frame and recognition as the memory grows." % (
                 m0["sequences"], m0["last_frame"], ", ".join(map(str, growth))), "",
             "| memory (prototypes) | time per frame, median (ms) | ratio to %d prototypes | time per frame, mean "
             "(ms) | top-1 at frame %d | median frames to the first correct report | first correct report, per "
             "sequence | set-up (s) |" % (small, at),
             "|---|---|---|---|---|---|---|---|"]
    for n, m in growth.items():
        ratio = m["time_median_ms"] / base if base else None
        lines.append("| %d | %s | %s | %s | %s | %s | %s | %s |" % (
            n, fmt(m["time_median_ms"], "ms"), "n/a" if ratio is None else "%.2fx" % ratio,
            fmt(m["time_mean_ms"], "ms"), fmt(top1_at(m, 60), "pct"), fmt(m.get("first_correct_median"), "frames"),
            ", ".join(fmt(f, "frames") for f in m.get("first_correct", [])),
            fmt(m.get("init", {}).get("init_ms", 0) / 1000, "px")))
    r = growth_ratio(growth)
    if r:
        lines += ["", "Time per frame with %d prototypes against %d: **%.2fx** (issue 14's aim: at most %.1fx: %s)."
                  % (r[1], r[0], r[2], GROWTH_AIM, "met" if r[2] <= GROWTH_AIM else "not met")]
    return "\n".join(lines) + "\n"


def hd_section(everything):
    """The 1280x720 suites beside their 640x480 ones (AMCR)."""
    lines = ["AMCR on the same frames at 640x480 and at 1280x720 (`*-hd`: scaled 1.5x and centred, see "
             "Suites); difference = 1280x720 - 640x480:", "",
             "| suite | figure | 640x480 | 1280x720 | difference |", "|---|---|---|---|---|"]
    for low, high in HD_PAIRS:
        a = everything.get(low, {}).get("amcr")
        b = everything.get(high, {}).get("amcr")
        if not b:
            continue
        if not a:
            lines.append("| %s / %s | | not in this run (add `%s` to --suites) | | |" % (low, high, low))
        rows = []
        if b.get("top1"):
            rows += [("top-1 at frame %d" % min(60, b["last_frame"]), lambda m: top1_at(m, 60), "pct"),
                     ("share with a held correct decision", lambda m: m.get("held_share"), "pct"),
                     ("median frames to the first correct report", lambda m: m.get("first_correct_median"), "frames")]
        rows.append(("false positives per frame", lambda m: m["fp_per_frame"], ""))
        if b.get("top1"):
            rows.append(("affine corner error, median (px of the frame)", lambda m: m["affine_median"], "px"))
        rows.append(("time per frame, median (ms)", lambda m: m["time_median_ms"], "ms"))
        for title, get, kind in rows:
            va, vb = (get(a) if a else None), get(b)
            diff = ""
            if va is not None and vb is not None and va != math.inf and vb != math.inf:
                if kind == "pct":
                    diff = "%+.0f points" % (100 * (vb - va))
                elif kind == "ms":
                    diff = "%.2fx" % (vb / va) if va else ""
                elif kind == "":
                    diff = "%+.3f" % (vb - va)
            lines.append("| %s | %s | %s | %s | %s |" % (high, title, fmt(va, kind), fmt(vb, kind), diff))
    return "\n".join(lines) + "\n"


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


def suite_table(suite, metrics, has_target):
    methods = [m for m in METHODS if m in metrics]
    rows = []
    header = "| | " + " | ".join(METHOD_NAMES[m] for m in methods) + " |"
    rows.append(header)
    rows.append("|---" * (len(methods) + 1) + "|")

    def row(title, get, kind):
        rows.append("| %s | %s |" % (title, " | ".join(fmt(get(metrics[m]), kind) for m in methods)))

    row("sequences (frames run)", lambda m: None, "")
    rows[-1] = "| sequences (frames run) | %s |" % " | ".join(
        "%d (%d)" % (metrics[m]["sequences"], metrics[m]["frames_run"]) for m in methods)
    if has_target:
        last = max(metrics[m]["last_frame"] for m in methods)
        for n in [c for c in CHECKPOINTS if c < last] + [last]:
            row("top-1 at frame %d" % n, lambda m, n=n: m["top1"].get(n), "pct")
        if suite == "two-objects":
            row("both objects reported at the last frame", lambda m: m.get("all_found_last"), "pct")
        row("share with a held correct decision", lambda m: m.get("held_share"), "pct")
        row("median frames to the held correct decision", lambda m: m.get("held_median"), "frames")
    row("false positives per frame", lambda m: m["fp_per_frame"], "")
    if has_target and suite not in WITHIN_CLASS_SUITES:
        row("affine corner error, median over frames (px)", lambda m: m["affine_median"], "px")
        row("affine corner error at the last frame, median (px)", lambda m: m["affine_last_median"], "px")
        row("correspondence error, median (px)", lambda m: m["corr_median"], "px")
    row("time per frame, mean (ms)", lambda m: m["time_mean_ms"], "ms")
    row("time per frame, median (ms)", lambda m: m["time_median_ms"], "ms")
    row("set-up (prototypes), s", lambda m: m.get("init", {}).get("init_ms", 0) / 1000, "px")
    if any("templates" in metrics[m].get("init", {}) for m in methods):
        row("templates", lambda m: m.get("init", {}).get("templates"), "count")
    return "\n".join(rows)


def plot_accuracy(plt, suite, metrics, path):
    fig, ax = plt.subplots(figsize=(6, 3.6))
    for m in METHODS:
        if m in metrics and metrics[m].get("curve"):
            curve = metrics[m]["curve"]
            style = "o" if len(curve) < 10 else "-"
            ax.plot(list(curve), list(curve.values()), style, label=METHOD_NAMES[m])
    ax.set_xlabel("frame")
    ax.set_ylabel("top-1 accuracy")
    ax.set_ylim(-0.02, 1.02)
    ax.set_title(suite)
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def plot_peers(plt, everything, path):
    """Every method over the suites: top-1 at frame 60 (false positives per frame where nothing is shown) and the
    mean time per frame, side by side."""
    suites = list(everything)
    methods = [m for m in METHODS if any(m in everything[s] for s in suites)]
    if not suites or not methods:
        return False
    fig, (top, time) = plt.subplots(2, 1, figsize=(max(6, 0.9 * len(suites) + 2), 6.4), sharex=True)
    width = 0.8 / len(methods)
    for i, method in enumerate(methods):
        xs = [k + (i - (len(methods) - 1) / 2) * width for k in range(len(suites))]
        heights, times = [], []
        for suite in suites:
            m = everything[suite].get(method)
            value = None
            if m:
                value = top1_at(m, 60) if m.get("top1") else -m["fp_per_frame"]
            heights.append(value if value is not None else 0.0)
            times.append(m["time_mean_ms"] if m and m.get("time_mean_ms") else 0.0)
        top.bar(xs, heights, width, label=METHOD_NAMES[method])
        time.bar(xs, times, width, label=METHOD_NAMES[method])
    top.axhline(0, color="black", linewidth=0.5)
    top.set_ylabel("top-1 at frame 60\n(below 0: false positives per frame)", fontsize=8)
    top.set_ylim(-1.02, 1.02)
    top.grid(alpha=0.3, axis="y")
    top.legend(fontsize=7, ncol=3, loc="lower left")
    time.set_yscale("log")
    time.set_ylabel("time per frame, mean (ms)", fontsize=8)
    time.grid(alpha=0.3, axis="y", which="both")
    time.set_xticks(range(len(suites)))
    time.set_xticklabels(suites, rotation=30, ha="right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return True


def speed_section(out, plt):
    path = os.path.join(out, "speed.json")
    if not os.path.exists(path):
        return "Speed: not measured in this run (speed.json missing).\n"
    with open(path) as f:
        bench = json.load(f)
    steps, tables, budget, index = [], [], [], []
    for b in bench["benchmarks"]:
        if b.get("run_type", "iteration") != "iteration":
            continue
        if b["name"].startswith("BM_RecognizerStep"):
            v, m, p = (int(x) for x in b["name"].split("/")[1:4])
            ms = b["real_time"] if b["time_unit"] == "ms" else b["real_time"] / 1e6
            steps.append((v, m, p, ms, b.get("items_per_second", 0)))
        elif b["name"].startswith("BM_BudgetStep"):
            v, p = (int(x) for x in b["name"].split("/")[1:3])
            budget.append((p, v, b["real_time"], b.get("mean_m_per_v", 0), b.get("items_per_second", 0)))
        elif b["name"].startswith("BM_ProposalIndex"):
            index.append((int(b["name"].split("/")[1]), b["real_time"], b.get("entries", 0)))
        elif b["name"].startswith("BM_PrototypeTable"):
            side = int(b["name"].split("/")[1])
            tables.append((side, b["real_time"], b.get("table_MB", 0)))
    context = bench.get("context", {})
    lines = ["Google Benchmark on one core (%s CPUs at %s MHz reported; %s)."
             % (context.get("num_cpus"), context.get("mhz_per_cpu"), context.get("date")), "",
             "| V-particles | M per prototype | prototypes | relational particles | ms per iteration | updates/s |",
             "|---|---|---|---|---|---|"]
    for v, m, p, ms, ups in sorted(steps, key=lambda s: (s[2], s[0], s[1])):
        lines.append("| %d | %d | %d | %d | %.2f | %.2f M |" % (v, m, p, v * m * p, ms, ups / 1e6))
    if budget:
        lines += ["", "With the defaults (a budget of M-particles per V-particle, the proposal index, KLD-sampling):", "",
                  "| prototypes | V-particles | ms per iteration | mean M per V | updates/s |", "|---|---|---|---|---|"]
        lines += ["| %d | %d | %.2f | %.0f | %.2f M |" % (p, v, ms, m, ups / 1e6) for p, v, ms, m, ups in sorted(budget)]
    if index:
        lines += ["", "| prototypes | proposal index build (ms) | entries |", "|---|---|---|"]
        lines += ["| %d | %.0f | %d |" % t for t in sorted(index)]
    if tables:
        lines += ["", "| prototype_size (px) | table build (ms) | table size (MB) |", "|---|---|---|"]
        lines += ["| %d | %.0f | %.2f |" % t for t in sorted(tables)]
    if plt and steps:
        fig, ax = plt.subplots(figsize=(6, 3.6))
        for label, key, fixed in (("V varies (60 M, 3 prototypes)", 0, lambda s: s[1] == 60 and s[2] == 3),
                                  ("M varies (30 V, 3 prototypes)", 1, lambda s: s[0] == 30 and s[2] == 3),
                                  ("prototypes vary (30 V x 60 M)", 2, lambda s: s[0] == 30 and s[1] == 60)):
            series = sorted((s[0] * s[1] * s[2], s[3]) for s in steps if fixed(s))
            if len(series) > 1:
                ax.plot([x for x, _ in series], [y for _, y in series], "o-", label=label)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("relational particles (V x M x prototypes)")
        ax.set_ylabel("ms per iteration")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "plots", "time_per_iteration.png"), dpi=100)
        plt.close(fig)
        lines += ["", "![time per iteration](plots/time_per_iteration.png)"]
    return "\n".join(lines) + "\n"


def latency_section(out):
    path = os.path.join(out, "latency.json")
    if not os.path.exists(path):
        return "Nodelet latency: not measured in this run.\n"
    with open(path) as f:
        lat = json.load(f)
    counts = "the default counts" if lat.get("counts") == "defaults" else "the paper's counts (30 V x 60 M)"
    threads = lat.get("threads", 1)
    return ("Nodelet latency (amcr_node, %s): %d frames of 640x480 at %s Hz, %d prototypes, %s, %s: "
            "processing time median %.1f ms (mean %.1f); publish-to-receipt latency median %.1f ms, "
            "95th percentile %.1f ms (median of the first third %.1f ms, of the last %.1f ms); "
            "%d of %d frames answered (the input queue holds one frame).\n"
            % (lat["what"], lat["frames"], lat["rate"], lat["prototypes"], counts,
               "every core" if threads == 0 else "%d thread(s)" % threads,
               lat["processing_median_ms"], lat["processing_mean_ms"], lat["latency_median_ms"],
               lat["latency_p95_ms"], lat.get("latency_first_third_median_ms", float("nan")),
               lat.get("latency_last_third_median_ms", float("nan")), lat["answered"], lat["frames"]))


SUITES_TEXT = """\
Rendered by `bench/make_sequences` (seeded; one generator per sequence): 640x480 grey frames, an
MPEG-7 silhouette printed dark on light (70%) or light on dark (30%) over a real photo from
opencv-doc (contrast-reduced, random crop), under a random affine (longer side 120-240 px, any
rotation, shear up to 0.3, anisotropic scale up to about 1.5:1) that drifts, spins 0.3-1.5
degrees per frame and breathes in scale and shear; 3-5 static distractor silhouettes of MPEG-7
classes not in memory (random polygons, ellipses and crosses in the 70-class suites, where every
class is in memory), 3-6 lines, a lighting gradient (10-35%), blur (sigma 0-1.2) and noise
(sigma 2-8). `paper`: 17 classes in memory (every 4th class in name order, instance 1), the same
instance shown; `mpeg7-70`: all 70 classes; `within-class`: memory instance 1 of all 70 classes,
another instance shown; `within-class-1330`: memory the 19 instances of each of the 70 classes
other than one held out per class (drawn once, whatever the seed), the held-out instance shown,
label the class; the `within-class` sequences (same seeds and draws: background, pose, motion,
clutter, noise) with the memory and the shown instance changed only; `within-class-85`: memory 5
of those 19 instances for each of the paper's 17 classes, the held-out instance of one of them
shown (seeds of its own; distractors of classes not in memory); `similar`: the 3 birds closest in Hu moments; `clutter-only`: the paper
memory, no memory shape in view; `two-objects`: two of the paper memory at once, in the two
halves of the frame. `oblique`: the `paper` sequences (same seeds, memory, clutter, motion) with
the target seen obliquely: squashed along an image axis (random per sequence) to anisotropy
1.5-3 (48-70 degrees off the normal), area kept, no shear. `faint`: the `paper` sequences (same
seeds) printed faint and out of focus: the contrast cut to a quarter about grey 128 after the
lighting, 2 px (sigma) of defocus added to the drawn blur, the noise as drawn. `memory-growth` (issue 14): 6
sequences (2 with --quick) whose targets are 3 fixed classes, run once per memory of 3, 17, 35 and
70 prototypes (nested: 3 of the paper's 17, the 17, the 17 and 18 other classes, all 70; fixed,
whatever the seed); distractors are random blobs. `paper-hd` and `clutter-only-hd` (issue 14): the
`paper` and `clutter-only` frames (same seeds, draws and noise) resampled 1.5x (bilinear) to
960x720 and centred in 1280x720, the 160 px left and right showing the photo mirrored (no shape);
the truth is the 640x480 truth composed with x' = 1.5 x + 160.25, y' = 1.5 y + 0.25, exact.
`copies` (issue 15): 4-6 copies of one prototype of the paper memory (class drawn per sequence),
each at its own pose (longer side 90-150 px, any rotation), none overlapping (3 px apart at least),
moving together (drift, slow spin, breathing scale) over the `paper` clutter. `real-photos` (issue
15): opencv-doc's photo `pca_test1.jpg` (six alike dark parts on a backlit panel) under a synthetic
camera motion (drift, slow turn and zoom) with mild noise; memory: the part cut from the photo
(Otsu, the component of median area) and 16 of the paper memory; its truth affines are approximate
(from the parts' moments), their centres are the parts' centroids. The Hu-moments baseline's affine
comes from moments too, so its affine error there says how alike the two are, not how right.
Frames are numbered from 1.
"""

REAL_TEXT = """\
Real frames (Debian's visp-images-data, grey, at their own size); memory: the target `mire`
drawn from its measured geometry (bench/real_camera.py) and 16 of the paper's prototypes. The truth
is a homography per frame from the target's own pattern and edges (bench/real_camera.py), unknown
frames unscored. Aim of issue 13: >= 90% of the scored frames at the right place after the first
report, the first report within 30 frames."""

REAL_CUBE_TEXT = """\
Real frames of visp-images-data's `cube` (80, 384x288 grey: a hand-held camera over a black cube with
white dots on a comic-book collage); memory: the target `cube-face` (the face towards the camera, a
square with a ring of 12 dots) drawn from its measured geometry (bench/real_camera_cube.py) and 16 of
the paper's prototypes. The truth is a homography per frame from the face's dots and edges
(bench/real_camera_cube.py), unknown frames unscored; its four quarter turns count as one (its dots
are 4-fold symmetric but for a shift of 4% of the side). The face is small: 68-86 px."""
REAL_TEXTS = {"real-camera": REAL_TEXT, "real-camera-cube": REAL_CUBE_TEXT}

METHODS_TEXT = """\
Every method gets the same prototypes (the suite's `prototypes/` folder) and the same frames, one
core each (OpenCV threads off), and reports labels with a prototype->image affine per frame:
- **AMCR**: `config/amcr.yaml` as committed (60 V-particles, a budget of 1000 M-particles each shared by the prototypes, the proposal index, KLD-sampling),
  one recognizer per sequence, reset between sequences; what it reports (score >= the decision
  threshold) is taken as it is.
- **LINE-2D** (Hinterstoisser et al.; OpenCV contrib's `cv::linemod`, `getDefaultLINE()`: quantised
  gradient orientations over two pyramid levels, T = 5 and 8 px, 63 features): one template per
  prototype, size, rotation and stretch, each the prototype printed dark on light (orientations
  count modulo 180 degrees, so either print polarity matches) with its mask dilated 2 px: sizes over
  the suite's range in steps of at most 1.12x, rotations every 5 degrees, and the identity and 6
  stretches (area kept, along 6 axes over 180 degrees) at 2/3 of the suite's largest anisotropy in
  the logarithm (1.7 for the `paper` suites and `real-camera-cube`, 3.1 for `oblique` and
  `real-camera`): about 4,500
  templates per prototype, built once per memory (the set-up row). The rotation step, the stretches
  and the gradient threshold were chosen on `paper` seed 1, the threshold on seed 3. Each frame matched on its own at similarity >= 93% (chosen on seed 3 of `paper` and
  `clutter-only`, which no figure here scores), gradient threshold 60, non-maximum suppression
  between matches (centres within half the smaller size), at most 5 reports; the affine is the
  template's, so it carries the sampling steps' error. It runs on every 10th frame of every sequence
  (frames 10, 30, 60 and the last among them), each frame on its own: its figures at those frames are
  what it does on any frame.
- **Shape contexts** (Belongie, Malik and Puzicha, the paper's comparison;
  `cv::ShapeContextDistanceExtractor`): candidates are the closed contours of the frame binarised as
  for Hu moments, opened and closed with a 7 px disc (cuts crossing lines off), following Canny edges
  for 60% of their points, one per outline, the 12 largest in the suite's size range; each resampled
  to 50 points and compared with every prototype's outline from 8 starting turns (OpenCV's rotation
  invariant mode is not invariant), affine alignment, 3 iterations; a candidate goes to its nearest
  prototype, reported at a distance <= 0.1 (set on drawn scenes), the affine fitted (RANSAC, 3 px) to
  the extractor's last point matches, which are its correspondences. At 1.9 ms per comparison it
  takes seconds per frame, so it runs on every 60th frame (60 and the last) of every sequence.
- **ORB+RANSAC** (find_object_2d's method): prototypes rescaled to 200 px, described in both print
  polarities (400 ORB features each), all in one FLANN LSH index; 1500 ORB features per frame,
  ratio test 0.8 over the whole memory, RANSAC homography (5 px) per prototype, reported with at
  least 10 inliers; the affine is the least-squares fit of the homography at the prototype's corners
  and centre; the inliers are its correspondences. Stateless: each frame on its own.
- **Hu moments**: Otsu and adaptive (51 px, C 10) thresholds in both polarities, contours of
  800 px^2 to 40% of the frame, `cv::matchShapes` (I1) against each prototype's outer contour,
  reported when the distance is below 0.05 (each contour to its best prototype only); the affine
  from the moments (centroids, principal axes scaled by their spread, signs by third-order skew).
- **GHT Guil** (`cv::GeneralizedHoughGuil`): prototypes rescaled to 160 px, one detector per
  prototype and print polarity, full circle in 2-degree steps, scale 0.5-2.0 in steps of 0.05,
  vote thresholds 0.2/0.04/0.02 of the template's edge points (angle/scale/position, set by hand
  on clean rotated copies and one cluttered frame: lower ones take tens of seconds per prototype on
  clutter), reported with position votes of at least 0.03 of the edge points, ranked by votes per
  edge point; a similarity only (no shear, no anisotropic scale). It is slow on clutter, from
  0.3 s to minutes per prototype and polarity (one `paper` frame took 3 to 16 minutes with 17
  prototypes), so the full run gives it the last frame of every `similar` sequence (3 prototypes)
  and of one `paper` sequence only (the "frames run" row), and none of the other suites. It keeps
  no state from frame to frame, so a frame says what it does on any frame, but the sample is small:
  read its figures as indicative.
"""


def breakdown(out, suite, method="amcr"):
    """Top-1 at the last frame of `method`, split by the conditions of the sequences."""
    groups = {}
    for path in sorted(glob.glob(os.path.join(out, "sequences", suite, "seq_*", "truth.json"))):
        name = os.path.basename(os.path.dirname(path))
        result = os.path.join(out, "results", suite, "%s.%s.jsonl" % (name, method))
        if not os.path.exists(result):
            continue
        with open(path) as f:
            truth = json.load(f)
        last = truth["frames"][-1]
        if not last["objects"]:
            return ""
        rows = read_jsonl(result)
        reported = rows.get(last["frame"], {}).get("objects", [])
        right = bool(reported) and reported[0]["label"] in [o["label"] for o in last["objects"]]
        a = affine(last["objects"][0]["prototype_to_image"])[:, :2]
        singular = np.linalg.svd(a, compute_uv=False)
        size = truth["prototype_sizes"][last["objects"][0]["label"]]
        longer = max(size) * math.sqrt(abs(np.linalg.det(a)))
        keys = ["print: %s" % ("light on dark" if truth["inverted"] else "dark on light"),
                "target size: %s" % ("< 160 px" if longer < 160 else ">= 160 px"),
                "anisotropy (singular value ratio): %s" % ("> 1.3" if singular[0] / singular[1] > 1.3 else "<= 1.3"),
                "blur sigma: %s" % ("> 0.6" if truth["blur_sigma"] > 0.6 else "<= 0.6"),
                "noise sigma: %s" % ("> 5" if truth["noise_sigma"] > 5 else "<= 5")]
        for k in keys:
            groups.setdefault(k, []).append(right)
    if not groups:
        return ""
    lines = ["%s, top-1 at the last frame by condition of the sequence (size: the longer side of the "
             "target's bounding box of the prototype, approximately):" % METHOD_NAMES[method], "",
             "| condition | sequences | top-1 |", "|---|---|---|"]
    for k in sorted(groups):
        lines.append("| %s | %d | %s |" % (k, len(groups[k]), fmt(mean(groups[k]), "pct")))
    return "\n".join(lines) + "\n"


def top1_at(m, n):
    """Top-1 at frame n, or at the last frame when the sequences are shorter."""
    if not m.get("top1"):
        return None
    return m["top1"].get(n, m["top1"].get(m["last_frame"]) if m["last_frame"] < n else None)


def best_updates(out):
    """(updates/s, benchmark name) of the fastest BM_RecognizerStep, or None."""
    path = os.path.join(out, "speed.json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        steps = [b for b in json.load(f)["benchmarks"] if b["name"].startswith("BM_RecognizerStep")
                 and b.get("run_type", "iteration") == "iteration"]
    if not steps:
        return None
    best = max(steps, key=lambda b: b.get("items_per_second", 0))
    return best.get("items_per_second", 0), best["name"]


def summary_section(everything, updates=None, growth=None):
    """One table over the suites, and the aims of the issue against the figures."""
    methods = [m for m in METHODS if any(m in metrics for metrics in everything.values())]  # those this run ran
    lines = ["## Summary", "",
             "Top-1 at frame 60 (at the last frame where sequences are shorter; GHT: at the frames it ran; LINE-2D "
             "runs on every 10th frame, shape contexts on every 60th, frame 60 and the last among them), "
             "false positives per frame, median affine corner error (px), mean time per frame (ms):", "",
             "| suite | " + " | ".join(METHOD_NAMES[m] for m in methods) + " |", "|---" * (len(methods) + 1) + "|"]
    for suite, metrics in everything.items():
        cells = []
        for method in methods:
            m = metrics.get(method)
            if not m:
                cells.append("not run")
                continue
            top = top1_at(m, 60)
            if method == "ght" and m.get("top1"):
                top = mean(list(m["top1"].values()))
            cells.append("%s, %s FP, %s px, %s ms" % (fmt(top, "pct") if top is not None else "-",
                                                      fmt(m["fp_per_frame"], ""), fmt(m["affine_median"], "px"),
                                                      fmt(m["time_mean_ms"], "ms")))
        lines.append("| %s | %s |" % (suite, " | ".join(cells)))

    def get(suite, method, key, *more):
        value = everything.get(suite, {}).get(method, {})
        for k in (key,) + more:
            value = value.get(k) if isinstance(value, dict) else None
        return value

    aims = []
    for suite in ("paper", "mpeg7-70"):
        if suite in everything:
            got = top1_at(everything[suite]["amcr"], 60)
            best = max((top1_at(m, 60) or 0.0 for k, m in everything[suite].items() if k != "amcr"), default=0.0)
            aims.append("- top-1 on `%s` by frame 60 >= 95%%: **%s** (%s); ahead of every baseline (best %s): **%s**"
                        % (suite, fmt(got, "pct"), "met" if got is not None and got >= 0.95 else "not met",
                           fmt(best, "pct"), "yes" if got is not None and got > best else "no"))
    fp = get("clutter-only", "amcr", "fp_per_frame")
    if fp is not None:
        aims.append("- false positives per frame on `clutter-only` <= 0.05: **%.3f** (%s)"
                    % (fp, "met" if fp <= 0.05 else "not met"))
    errors = [everything[s]["amcr"]["affine_median"] for s in everything
              if "amcr" in everything[s] and everything[s]["amcr"].get("affine_median") is not None]
    if errors:
        worst = max(errors)
        aims.append("- median affine corner error < 3 px: **%.2f px** at worst over the suites (%s)"
                    % (worst, "met" if worst < 3 else "not met"))
    if updates:
        aims.append("- relational-particle updates per second on one core >= 10 M: **%.2f M** at best (%s, the "
                    "whole iteration counted) (%s)" % (updates[0] / 1e6, updates[1],
                                                      "met" if updates[0] >= 1e7 else "not met"))
    lines += ["", "The aims of issue 5 against these figures:", ""] + aims
    later = []
    r = growth_ratio(growth or {})
    if r:
        later.append("- time per frame from %d to %d prototypes (`%s`, median) grows at most %.1fx: **%.2fx** (%s)"
                     % (r[0], r[1], GROWTH, GROWTH_AIM, r[2], "met" if r[2] <= GROWTH_AIM else "not met"))
    for low, high in HD_PAIRS:
        a = top1_at(everything.get(low, {}).get("amcr", {}), 60)
        b = top1_at(everything.get(high, {}).get("amcr", {}), 60)
        fa, fb = get(low, "amcr", "fp_per_frame"), get(high, "amcr", "fp_per_frame")
        if a is not None and b is not None:
            later.append("- top-1 at frame 60 on `%s` within %d points of `%s`: **%s against %s** (%s)" % (
                high, 100 * HD_AIM, low, fmt(b, "pct"), fmt(a, "pct"), "met" if b >= a - HD_AIM - 1e-9 else "not met"))
        elif fa is not None and fb is not None and not get(high, "amcr", "top1"):
            later.append("- false positives per frame on `%s` against `%s`: **%.3f against %.3f**" % (high, low, fb, fa))
        elif b is not None or fb is not None:
            later.append("- `%s`: %s**%s** false positives per frame (`%s` is not in this run: run both to compare)"
                         % (high, "top-1 at frame 60 **%s**, " % fmt(b, "pct") if b is not None else "", fmt(fb, ""), low))
    if later:
        lines += ["", "The aims of issue 14 against these figures:", ""] + later
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", required=True)
    parser.add_argument("--header", default="", help="Markdown put at the top (machine, date, commit)")
    args = parser.parse_args()
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        plt = None
    os.makedirs(os.path.join(args.out, "plots"), exist_ok=True)

    parts = ["# AMCR benchmark", "", args.header, "", "## Methods", "", METHODS_TEXT,
             "## Suites", "", SUITES_TEXT]
    everything = {}
    found = [os.path.basename(d) for d in glob.glob(os.path.join(args.out, "results", "*"))]
    real = {}
    growth = {}
    funnels = {}
    for suite in [s for s in SUITES if s in found] + sorted(s for s in found if s not in SUITES):
        if suite == GROWTH:
            growth = growth_metrics(args.out)
            continue
        funnel = funnel_report.suite_funnel(os.path.join(args.out, "results", suite))
        if funnel:
            funnels[suite] = funnel
        if suite in REAL_CAMERA_SUITES:
            real[suite] = real_camera_metrics(args.out, suite, METHODS)
            if real[suite]:
                parts += ["## %s" % suite, "", REAL_TEXTS[suite], "", real_camera_table(real[suite]), ""]
                if funnel:
                    parts += [funnel_report.funnel_table(funnel), ""]
            continue
        metrics, has_target = suite_metrics(args.out, suite, METHODS)
        if not metrics:
            continue
        everything[suite] = metrics
        parts += ["## %s" % suite, "", suite_table(suite, metrics, has_target), ""]
        if suite in INSTANCE_SUITES:
            instances = instance_metrics(args.out, suite, METHODS)
            for method, m in instances.items():
                metrics[method]["instances"] = m
            if instances:
                parts += [instance_table(instances), ""]
        if "amcr" in metrics and has_target and suite not in ("two-objects", "real-photos"):
            parts += [breakdown(args.out, suite), ""]
        if suite == "oblique":
            parts += [anisotropy_table(args.out, suite), ""]
        if funnel:
            parts += [funnel_report.funnel_table(funnel), ""]
        if plt and has_target:
            plot_accuracy(plt, suite, metrics, os.path.join(args.out, "plots", "accuracy_%s.png" % suite))
            parts += ["![%s](plots/accuracy_%s.png)" % (suite, suite), ""]
    if any(high in everything for _, high in HD_PAIRS):
        parts += ["## 1280x720 beside 640x480", "", hd_section(everything), ""]
    if growth:
        parts += ["## %s" % GROWTH, "", growth_section(growth), ""]
    speed = speed_section(args.out, plt)
    updates = best_updates(args.out)
    summary = [summary_section(everything, updates, growth), ""]
    if plt and plot_peers(plt, everything, os.path.join(args.out, "plots", "peers.png")):
        summary += ["![every method on every suite](plots/peers.png)", ""]
    if funnels:
        summary += [funnel_report.overview_table(funnels), ""]
    parts[4:4] = summary
    parts += ["## Speed", "", speed, latency_section(args.out)]
    if plt is None:
        parts.append("(plots skipped: python3-matplotlib is not installed)")
    with open(os.path.join(args.out, "report.md"), "w") as f:
        f.write("\n".join(parts) + "\n")
    # The short version: the run, the summary, the speed (for docs/benchmark-latest.md).
    short = ["# AMCR benchmark: summary", "", args.header, "", summary_section(everything, updates, growth), ""]
    if funnels:
        short += [funnel_report.overview_table(funnels), ""]
    short += ["## Speed", "", speed.replace(
                 "![time per iteration](plots/time_per_iteration.png)",
                 "The plot of time per iteration against particle count is `plots/time_per_iteration.png`"
                 " in the run's output folder (not in the repository)."), latency_section(args.out)]
    with open(os.path.join(args.out, "summary.md"), "w") as f:
        f.write("\n".join(short) + "\n")
    with open(os.path.join(args.out, "metrics.json"), "w") as f:
        json.dump(dict(everything, **{s: m for s, m in real.items() if m}, **({"funnel": funnels} if funnels else {}),
                       **({GROWTH: {str(n): m for n, m in growth.items()}} if growth else {})), f, indent=1, default=str)
    print("report: %s" % os.path.join(args.out, "report.md"))


if __name__ == "__main__":
    main()
