"""The Speed section of the benchmark report: Google Benchmark's figures (speed.json) as tables and a
plot, the nodelet's latency (latency.json), and the fastest iteration's updates per second."""

import json
import os


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
