"""The recall funnel of a benchmark run: where AMCR loses a shape that is in view.

amcr_evaluate writes <out>/results/<suite>/<sequence>.amcr.funnel.jsonl (bench/recall_funnel.h): for
every frame and every true object, how many V-particles lie on it, whether the proposal index
returns its true place, whether an M-particle near the true place is alive, whether a V-particle's
dominant cluster converged on it, whether the extraction verified an object there, whether its
score passed the decision threshold, and whether it was reported at the right place.

An object is *found* when it is reported at the right place at frame CHECKPOINT (the last known
frame up to it: the real camera's unknown frames are not judged; the last frame when shorter).
A missed object *stops* at the first stage that no frame up to the checkpoint reached; when every
stage was reached in some frame it was reported, then lost ("lost").
"""

import glob
import json
import os
import statistics

STAGES = ["on_object", "proposed", "alive", "cluster", "verified", "passed", "reported"]
STAGE_TEXT = {
    "on_object": "a V-particle on the object",
    "proposed": "the index returns its true place (or an M-particle is alive there)",
    "alive": "an M-particle near the true place (8 table px, 25 deg)",
    "cluster": "a converged dominant cluster at the true place",
    "verified": "the extraction verified an object of the label at the right place",
    "passed": "its outline score reached the decision threshold",
    "reported": "reported at the right place",
}
CHECKPOINT = 60


def read_funnel(path):
    """Per-frame lines (frame -> objects) and the summary line of one sequence."""
    frames, summary = {}, []
    with open(path) as f:
        for line in f:
            row = json.loads(line)
            if "summary" in row:
                summary = row["summary"]
            else:
                frames[row["frame"]] = row["objects"]
    return frames, summary


def object_outcomes(frames):
    """For each object of the sequence: its frames up to the checkpoint, found or not, where it stopped."""
    known = sorted(k for k, objects in frames.items() if objects)
    if not known:
        return []
    upto = [k for k in known if k + 1 <= CHECKPOINT] or known[:1]
    judged = upto[-1]
    outcomes = []
    for i in range(len(frames[judged])):
        rows = [frames[k][i] for k in upto]
        found = rows[-1]["reported"]
        stop = None
        if not found:
            stop = next((s for j, s in enumerate(STAGES) if not any(r["stages"][j] for r in rows)), "lost")
        outcomes.append({"label": rows[-1]["label"], "in_memory": rows[-1]["in_memory"], "rows": rows,
                         "found": found, "stop": stop, "judged_frame": judged + 1})
    return outcomes


def suite_funnel(res_dir):
    """The funnel of one suite's AMCR run, or None when it wrote none."""
    paths = sorted(glob.glob(os.path.join(res_dir, "*.amcr.funnel.jsonl")))
    if not paths:
        return None
    objects = []
    for path in paths:
        name = os.path.basename(path).split(".")[0]
        for o in object_outcomes(read_funnel(path)[0]):
            o["sequence"] = name
            objects.append(o)
    if not objects:
        return None
    rows = [r for o in objects for r in o["rows"]]
    on = [r for r in rows if r["v_on"] > 0]
    indexable = [r for r in rows if r["v_indexable"] > 0]
    alive = [r for r in rows if r["v_alive"] > 0]
    ranks = [r["best_rank"] for r in rows if r["best_rank"] >= 0]
    quantiles = [r["best_likelihood_quantile"] for r in alive if r.get("best_likelihood_quantile", -1) >= 0]
    stops = {}
    for o in objects:
        if not o["found"]:
            stops.setdefault(o["stop"], []).append(o)
    med = lambda values: statistics.median(values) if values else None  # noqa: E731
    return {
        "objects": len(objects),
        "found": sum(o["found"] for o in objects),
        "in_memory": all(o["in_memory"] for o in objects),
        "frames": len(rows),
        "stage_share": {s: sum(r["stages"][j] for r in rows) / len(rows) for j, s in enumerate(STAGES)},
        "stops": {s: len(v) for s, v in stops.items()},
        "missed": [(o["sequence"], o["label"], o["stop"]) for o in objects if not o["found"]],
        "v_on_median": med([r["v_on"] for r in rows]),
        "indexable_share": len(indexable) / len(on) if on else None,
        "proposal_hit_share": sum(r["v_proposed"] > 0 for r in indexable) / len(indexable) if indexable else None,
        "rank_median": med(ranks),
        "best_share_median": med([r["best_share"] for r in alive]),
        "likelihood_quantile_median": med(quantiles),
    }


def fmt(value, percent=False):
    if value is None:
        return "-"
    return "%.0f%%" % (100 * value) if percent else ("%.2f" % value if isinstance(value, float) else str(value))


def funnel_table(f):
    """Markdown: the share of frames at each stage and where the missed objects stopped."""
    lines = ["Recall funnel (AMCR; frames 1-%d; bench/funnel_report.py): %d of %d objects found at frame %d." % (
        CHECKPOINT, f["found"], f["objects"], CHECKPOINT)]
    if not f["in_memory"]:
        lines.append("(the shown instance is not in the memory: only the label's report is judged)")
    lines += ["", "| stage | frames (object x frame) reaching it | missed objects stopping here |", "|---|---|---|"]
    for s in STAGES:
        lines.append("| %s: %s | %s | %d |" % (s, STAGE_TEXT[s], fmt(f["stage_share"][s], True), f["stops"].get(s, 0)))
    lines.append("| lost: reported, then lost before frame %d | | %d |" % (CHECKPOINT, f["stops"].get("lost", 0)))
    lines += ["", "V-particles on the object per frame, median %s; of frames with one, %s have one with all 8 rays "
              "on edges; of those, the index returns the true place in %s (median rank %s of the candidates). "
              "Where a near M-particle is alive, the largest share of a V-particle's M-particles near the truth "
              "is %s (median; a cluster needs cluster_min_share) and the share of M-particles more likely than "
              "the best near one %s (median)." % (
                  fmt(f["v_on_median"]), fmt(f["indexable_share"], True), fmt(f["proposal_hit_share"], True),
                  fmt(f["rank_median"]), fmt(f["best_share_median"]), fmt(f["likelihood_quantile_median"]))]
    if f["missed"]:
        lines += ["", "Missed: " + ", ".join("%s %s (%s)" % m for m in f["missed"]) + "."]
    return "\n".join(lines)


def overview_table(funnels):
    """Markdown: every suite's found share and where its missed objects stopped."""
    head = "| suite | found at frame %d | " % CHECKPOINT + " | ".join(STAGES) + " | lost |"
    lines = ["Where the missed objects stopped (the first stage no frame up to %d reached):" % CHECKPOINT, "", head,
             "|---|---|" + "---|" * (len(STAGES) + 1)]
    for suite, f in funnels.items():
        lines.append("| %s | %d / %d | " % (suite, f["found"], f["objects"]) +
                     " | ".join(str(f["stops"].get(s, 0)) for s in STAGES + ["lost"]) + " |")
    return "\n".join(lines)
