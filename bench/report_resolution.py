"""The "1280x720 beside 640x480" section of the benchmark report: AMCR's figures on the `*-hd` suites
beside those of the 640x480 suites whose frames they scale."""

import math

from report_common import HD_PAIRS, fmt, top1_at


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
