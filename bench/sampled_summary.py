"""The summary of bench/sampled_benchmark: per sampled suite, the figures of every run (one draw, one
recognizer seed) with the benchmark report's own metric code (bench/report_suites.py,
report_instances.py, report_real_camera.py), their mean, the worst run and the worst draw (mean over
its seeds), as a markdown table and JSON."""

import glob
import json
import math
import os

from report_common import fmt, mean, top1_at
from report_instances import instance_metrics
from report_real_camera import real_camera_metrics
from report_suites import suite_metrics
from sampling import SAMPLED_SUITES

FIRST_REPORT_AIM = 30  # the real cameras: the first report of the target within this many frames

# Per kind of suite: (figure, title, format, whether higher is better).
FIGURES = {
    "rendered": [("top1", "top-1 at frame 60 (or the last)", "pct", True),
                 ("false_per_frame", "false reports per frame", "", False)],
    "clutter": [("false_per_frame", "false reports per frame", "", False)],
    "photo": [("found_late", "instances found per frame from frame 60 (or the last)", "pct", True),
              ("all_found", "all instances found at frame 60 (or the last)", "pct", True)],
    "real": [("first_report", "first report of the target (frame)", "frames", False),
             ("first_within", "first report within %d frames" % FIRST_REPORT_AIM, "pct", True),
             ("right_after", "scored frames at the right place after the first report", "pct", True),
             ("false_per_frame", "false reports per frame", "", False)],
}


def kind_of(suite):
    spec = SAMPLED_SUITES[suite]
    if spec["kind"] == "rendered":
        return "clutter" if SAMPLED_SUITES[suite]["like"].startswith("clutter") else "rendered"
    return spec["kind"]


def run_figures(out, suite, k, res_dir):
    """The figures of one run (draw k, the results in res_dir), or None when it is not complete."""
    draw = os.path.join(suite, "draw-%d" % k)  # under <out>/sequences, as the report's functions read it
    names = [os.path.basename(os.path.dirname(p))
             for p in glob.glob(os.path.join(out, "sequences", draw, "seq_*", "truth.json"))]
    if not names or not all(os.path.exists(os.path.join(res_dir, n + ".amcr.jsonl")) for n in names):
        return None
    kind = kind_of(suite)
    if kind in ("rendered", "clutter"):
        metrics, has_target = suite_metrics(out, draw, ["amcr"], res_dir)
        m = metrics["amcr"]
        return {"top1": top1_at(m, 60) if has_target else None, "false_per_frame": m["fp_per_frame"],
                "time_ms": m["time_mean_ms"]}
    if kind == "photo":
        m = instance_metrics(out, draw, ["amcr"], res_dir)["amcr"]
        return {"found_late": m["found_share_late"], "all_found": m["all_at"]}
    per_seq = real_camera_metrics(out, draw, ["amcr"], res_dir)["amcr"]
    m = per_seq[sorted(per_seq)[0]]
    first = m["first_report"]
    return {"first_report": math.inf if first is None else first,
            "first_within": float(first is not None and first <= FIRST_REPORT_AIM),
            "right_after": m["right_share_after_first"], "false_per_frame": m["false_per_frame"],
            "time_ms": m["time_mean_ms"]}


def aggregate(values, higher_better):
    """values: [(draw, seed, value)]; the mean, the worst run and the worst draw (mean over its seeds).
    Runs without a value (None: e.g. no report to be right after) are left out."""
    known = [(d, s, v) for d, s, v in values if v is not None]
    if not known:
        return {"mean": None, "worst": None, "worst_run": None, "worst_draw": None, "worst_draw_mean": None,
                "runs": 0}
    pick = min if higher_better else max
    worst = pick(known, key=lambda r: r[2])
    draws = {}
    for d, _, v in known:
        draws.setdefault(d, []).append(v)
    draw_means = {d: mean(v) for d, v in draws.items()}
    worst_draw = pick(draw_means, key=lambda d: draw_means[d])
    return {"mean": mean([v for *_, v in known]), "worst": worst[2], "worst_run": {"draw": worst[0], "seed": worst[1]},
            "worst_draw": worst_draw, "worst_draw_mean": draw_means[worst_draw], "runs": len(known)}


def summarise(out, tag, suites, draws, seeds_of):
    """{suite: {"figures": {name: aggregate + "values"}, "runs", "runs_missing", "seconds_per_run"}}."""
    summary = {}
    for suite in suites:
        runs, missing, seconds = [], 0, []
        for k in range(draws):
            for seed in seeds_of(suite):
                res_dir = os.path.join(out, "results", tag, suite, "draw-%d" % k, "seed-%d" % seed)
                figures = run_figures(out, suite, k, res_dir)
                if figures is None:
                    missing += 1
                    continue
                runs.append((k, seed, figures))
                timing = os.path.join(res_dir, "run.json")
                if os.path.exists(timing):
                    with open(timing) as f:
                        seconds.append(json.load(f)["seconds"])
        entry = {"runs": len(runs), "runs_missing": missing, "seconds_per_run": mean(seconds), "figures": {}}
        for name, _, _, higher in FIGURES[kind_of(suite)]:
            values = [(k, s, f[name]) for k, s, f in runs]
            if name == "first_report":  # never reported: the mean over the runs that reported, and how many never
                reported = [(k, s, v) for k, s, v in values if v != math.inf]
                agg = aggregate(reported, higher)
                if len(reported) < len(values):
                    agg["worst"], agg["never"] = math.inf, len(values) - len(reported)
                    agg["worst_run"] = next({"draw": k, "seed": s} for k, s, v in values if v == math.inf)
            else:
                agg = aggregate(values, higher)
            agg["values"] = [{"draw": k, "seed": s, "value": v} for k, s, v in values]
            entry["figures"][name] = agg
        summary[suite] = entry
    return summary


def markdown(summary, tag, config):
    lines = ["Sampled constructions, tag `%s` (config `%s`): per suite, over its draws x recognizer seeds, the "
             "mean, the worst run (draw, seed) and the worst draw (the mean over its seeds)." % (tag, config), "",
             "| suite | figure | mean | worst run | worst draw | runs | s per run |", "|---|---|---|---|---|---|---|"]
    for suite, entry in summary.items():
        first = True
        for name, title, kind, _ in FIGURES[kind_of(suite)]:
            agg = entry["figures"][name]
            mean_text = fmt(agg["mean"], kind)
            if agg.get("never"):
                mean_text += " (never in %d)" % agg["never"]
            worst = "n/a" if agg["worst_run"] is None else "%s (draw %d, seed %d)" % (
                fmt(agg["worst"], kind), agg["worst_run"]["draw"], agg["worst_run"]["seed"])
            worst_draw = "n/a" if agg["worst_draw"] is None else "%s (draw %d)" % (
                fmt(agg["worst_draw_mean"], kind), agg["worst_draw"])
            runs = "%d" % entry["runs"] + (" (%d missing)" % entry["runs_missing"] if entry["runs_missing"] else "")
            seconds = fmt(entry["seconds_per_run"], "ms") if entry["seconds_per_run"] is not None else "n/a"
            lines.append("| %s | %s | %s | %s | %s | %s | %s |" % (
                "`%s`" % suite if first else "", title, mean_text, worst, worst_draw, runs if first else "",
                seconds if first else ""))
            first = False
    return "\n".join(lines) + "\n"


def write_summary(out, tag, config, summary, name=None):
    """<out>/summary-<name>.md and .json (`name` defaults to the tag); returns the markdown."""
    text = markdown(summary, tag, config)
    name = name or tag
    with open(os.path.join(out, "summary-%s.md" % name), "w") as f:
        f.write(text)
    with open(os.path.join(out, "summary-%s.json" % name), "w") as f:
        json.dump(finite({"tag": tag, "config": config, "suites": summary}), f, indent=1)
        f.write("\n")
    return text


def finite(value):
    """JSON has no infinity: a first report that never came is null."""
    if isinstance(value, dict):
        return {k: finite(v) for k, v in value.items()}
    if isinstance(value, list):
        return [finite(v) for v in value]
    return None if isinstance(value, float) and math.isinf(value) else value
