"""A suite's section of the benchmark report: per method and sequence the frames' outcomes against the
truth, the suite's metrics and table, top-1 by the conditions of the sequences and, in `oblique`, by
anisotropy, and the plot of top-1 over the frames."""

import glob
import json
import math
import os

import cv2
import numpy as np

from report_common import (CHECKPOINTS, METHOD_NAMES, METHODS, WITHIN_CLASS_SUITES, affine, corners, fmt, mean, median,
                           read_jsonl)
from report_instances import centre_of

ANISOTROPY_BANDS = [(1.5, 2.0), (2.0, 2.5), (2.5, 3.0)]


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
