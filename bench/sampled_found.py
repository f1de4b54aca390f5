#!/usr/bin/python3
"""Found-by-frame over the sampled constructions: for every target of every draw, sequence and recognizer
seed of a bench/sampled_benchmark run, the first frame at which it was reported at the right place (the
recall funnel's `reported`), and the chance that a visible target of a given size is not yet found at
frame k.

Writes --out found.json in bench/found_by_frame.py's form (one series per suite: each target run's first
right report, null: never) and prints per suite a table of P(not found by frame k) by the target's size
in the first frame (the longer side of its prototype under the truth's affine, px).

    bench/sampled_found.py --sampled .build/sampled --tag TAG --out found.json [--suites a,b]
"""
import argparse
import glob
import json
import math
import os

FRAMES_CHECKED = (1, 5, 10, 30, 60)
SIZE_BINS = ((0, 60), (60, 90), (90, 130), (130, 10000))  # px, [low, high)


def target_sizes(truth_path):
    """label -> the target's longer side in the first frame, px."""
    with open(truth_path) as f:
        truth = json.load(f)
    sizes = {}
    first = truth["frames"][0]["objects"] if truth["frames"] else []
    for o in first:
        w, h = truth["prototype_sizes"][o["label"]]
        a = o["prototype_to_image"]
        scale = math.sqrt(abs(a[0][0] * a[1][1] - a[0][1] * a[1][0]))
        sizes[o["label"]] = max(w, h) * scale
    return sizes


def first_reports(funnel_path):
    """label -> first frame reported at the right place (None: never), and the frames run."""
    first, frames = {}, 0
    with open(funnel_path) as f:
        for line in f:
            row = json.loads(line)
            if "frame" not in row:
                continue
            frames = max(frames, row["frame"] + 1)
            for o in row.get("objects", []):
                if not o.get("in_memory", True):
                    continue
                first.setdefault(o["label"], None)
                if o["stages"][-1] and first[o["label"]] is None:
                    first[o["label"]] = row["frame"]
    return first, frames


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sampled", required=True, help="the sampled benchmark's --out")
    parser.add_argument("--tag", required=True)
    parser.add_argument("--out", required=True, help="found.json to write")
    parser.add_argument("--suites", default="", help="comma-separated (default: every suite of the tag)")
    args = parser.parse_args()
    root = os.path.join(args.sampled, "results", args.tag)
    suites = args.suites.split(",") if args.suites else sorted(os.listdir(root))
    record = {"tag": args.tag, "frames": 0, "first_report": {}}
    for suite in suites:
        rows = []  # (size px, first frame or None)
        for funnel in sorted(glob.glob(os.path.join(root, suite, "draw-*", "seed-*", "seq_*.amcr.funnel.jsonl"))):
            draw = funnel.split(os.sep)[-3]
            sequence = os.path.basename(funnel).split(".")[0]
            sizes = target_sizes(os.path.join(args.sampled, "sequences", suite, draw, sequence, "truth.json"))
            first, frames = first_reports(funnel)
            record["frames"] = max(record["frames"], frames)
            for label, frame in first.items():
                rows.append((sizes.get(label, float("nan")), frame))
        if not rows:
            continue
        record["first_report"][suite] = [r[1] for r in rows]
        print("\n`%s` (%s), %d target runs: P(not found by frame k)\n" % (suite, args.tag, len(rows)))
        print("| target size (px) | runs | " + " | ".join("k = %d" % k for k in FRAMES_CHECKED) + " |")
        print("|---|---|" + "---|" * len(FRAMES_CHECKED))
        for low, high in SIZE_BINS + ((0, 10000),):
            chosen = [f for s, f in rows if low <= s < high]
            if not chosen:
                continue
            name = "all" if (low, high) == (0, 10000) else ("%d-%d" % (low, high) if high < 10000 else ">= %d" % low)
            cells = ["%.2f" % (sum(f is None or f >= k for f in chosen) / len(chosen)) for k in FRAMES_CHECKED]
            print("| %s | %d | %s |" % (name, len(chosen), " | ".join(cells)))
    with open(args.out, "w") as f:
        json.dump(record, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
