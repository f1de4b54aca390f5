"""The `memory-growth` section of the benchmark report: AMCR on the same sequences with memories of
3, 17, 35 and 70 prototypes, the time per frame and the recognition as the memory grows."""

import glob
import os

from report_common import GROWTH, GROWTH_AIM, fmt, top1_at
from report_suites import suite_metrics


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
        lines += ["", "Time per frame with %d prototypes against %d: **%.2fx** (the aim: at most %.1fx: %s)."
                  % (r[1], r[0], r[2], GROWTH_AIM, "met" if r[2] <= GROWTH_AIM else "not met")]
    return "\n".join(lines) + "\n"
