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
- instances (`two-objects`, `copies`, `real-photos`: every instance in view is to be reported): per
  frame, every truth instance is
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
import os

import funnel_report  # bench/funnel_report.py, beside this script
from report_common import GROWTH, HD_PAIRS, METHODS, SUITES
from report_instances import INSTANCE_SUITES, instance_metrics, instance_table
from report_memory_growth import growth_metrics, growth_section
from report_real_camera import REAL_CAMERA_SUITES, REAL_TEXTS, real_camera_metrics, real_camera_table
from report_resolution import hd_section
from report_speed import best_updates, latency_section, speed_section
from report_suites import anisotropy_table, breakdown, plot_accuracy, suite_metrics, suite_table
from report_summary import plot_peers, summary_section
from report_texts import METHODS_TEXT, SUITES_TEXT


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
