"""The Summary section of the benchmark report: one table over the suites and methods, the aims
against the figures, and the plot of every method on every suite."""

from report_common import GROWTH, GROWTH_AIM, HD_AIM, HD_PAIRS, METHOD_NAMES, METHODS, fmt, mean, top1_at
from report_memory_growth import growth_ratio


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
    lines += ["", "The aims for accuracy and speed against these figures:", ""] + aims
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
        lines += ["", "The aims for memory size and resolution against these figures:", ""] + later
    return "\n".join(lines)


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
