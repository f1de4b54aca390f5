"""The report's instance figures (`two-objects`, `copies`, `real-photos`): each instance in view matched
one-to-one to a report of its label near its centre, per frame, pooled over a suite's sequences, and
the table."""

import glob
import json
import math
import os

import cv2
import numpy as np

from report_common import METHOD_NAMES, METHODS, affine, fmt, mean, read_jsonl

INSTANCE_SUITES = ["two-objects", "copies", "real-photos"]  # every instance in view is to be reported
INSTANCE_RADIUS = (10.0, 0.3)  # a report finds an instance within max(10 px, 0.3 x the instance's size)
INSTANCE_AT = 60  # "all found" at this frame (the last one when shorter)
INSTANCE_HOLD = 0.9  # "held": all found in at least this share of the frames after INSTANCE_AT


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


def instance_metrics(out, suite, methods, res_dir=None):
    """method -> instance-level metrics over a suite's sequences (instance_sequence); the results in
    `res_dir` (default <out>/results/<suite>)."""
    seq_dir = os.path.join(out, "sequences", suite)
    res_dir = res_dir or os.path.join(out, "results", suite)
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
            result = os.path.join(res_dir, "%s.%s.jsonl" % (os.path.basename(os.path.dirname(path)), method))
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
    lines = ["Instances (each one in view is to be reported): per frame, each instance in view is matched to at most "
             "one report of its label "
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
