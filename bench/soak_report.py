"""The verdict and the summary of a soak run (bench/soak_driver): what fails it, the figures
printed at the end and stored in soak.json and soak.md, and the machine and commit they came from."""

import os
import statistics
import subprocess

import soak_record
import soak_scene

SECONDS_BEFORE_A_CALL = 5.0  # the output a call's window is compared with
MIN_FRAMES_TO_JUDGE = 20     # fewer answers expected while a call ran: too short a window to judge its rate by
KEEPING_UP = 0.9             # share of the input rate answered before a call for its rate to be judged


def add_output_around_calls(outcomes, recorder, input_rate):
    """Adds to each call the output while it was under way ("output_during") and in the seconds before it
    ("output_before"): answers, rate, latency; the relative change of the rate; and whether the rate is
    judged: a reload, long enough for the answers expected in it, with the recognizer keeping up with the
    input before it (answering at least KEEPING_UP of `input_rate`). A recognizer that cannot keep up
    answers at the CPU share it gets, so any other work on the machine, the rebuild's included (it runs
    at a lower priority but is not free), shows in its rate: that is saturation, not a stalled stream."""
    for o in outcomes:
        start, end = o["wall"]
        before = recorder.window(start - SECONDS_BEFORE_A_CALL, start)
        during = recorder.window(start, end)
        rate_before = before["answers"] / SECONDS_BEFORE_A_CALL
        rate_during = during["answers"] / max(end - start, 1e-9)
        o["output_before"], o["output_during"] = before, during
        o["rate_change"] = round((rate_during - rate_before) / rate_before, 3) if rate_before > 0 else None
        o["keeping_up"] = rate_before >= KEEPING_UP * input_rate
        o["rate_judged"] = bool(o["reloads"] and o["rate_change"] is not None and o["keeping_up"]
                                and rate_before * (end - start) >= MIN_FRAMES_TO_JUDGE)


def reload_rate_failures(outcomes, tolerance):
    """The reloads during which the output rate fell more than `tolerance` below the rate before them."""
    failures = []
    for o in outcomes:
        if o.get("rate_judged") and o["rate_change"] < -tolerance:
            failures.append("t = %g s, %s: output %.1f Hz while it ran (%.2f s), %+.0f %% against the %.1f Hz of "
                            "the %g s before (bound -%g %%)" % (
                                o["t_s"], o["call"], o["output_during"]["rate_hz"], o["seconds"],
                                100.0 * o["rate_change"], o["output_before"]["rate_hz"], SECONDS_BEFORE_A_CALL,
                                100.0 * tolerance))
    return failures


def around_line(o):
    """One call's output before it and while it ran, for the printed summary."""
    b, d = o["output_before"], o["output_during"]
    change = "-" if o["rate_change"] is None else "%+.0f %%" % (100.0 * o["rate_change"])
    return ("t=%5.1f s  %-36s %5.2f s: %s -> %s Hz (%s%s); latency median %s -> %s ms, p95 %s -> %s ms, max %s -> %s ms"
            % (o["t_s"], o["call"], o["seconds"], b["rate_hz"], d["rate_hz"], change,
               "" if o["rate_judged"] else ", not judged: the input outran the recognizer before it"
               if o["reloads"] and not o["keeping_up"] else ", too short to judge" if o["reloads"] else ", not judged",
               b["latency_median_ms"], d["latency_median_ms"],
               b["latency_p95_ms"], d["latency_p95_ms"], b["latency_max_ms"], d["latency_max_ms"]))


def verdict(rows, outcomes, warm_rows, args, died, stalled):
    """The reasons the run failed (empty: it passed) and the RSS figures of the bound."""
    failures = []
    if died:
        failures.append(died)
    if stalled:
        failures.append(stalled)
    silent = [r["t_s"] for r in warm_rows if r["answered"] == 0]
    if silent:
        failures.append("no answer in the interval(s) ending at t = %s s" % ", ".join("%g" % t for t in silent))
    # The memory is judged from the end of the first reload of the larger memory on: holding 70
    # prototypes' tables once raises the allocator's high-water mark, which stays (not memory lost).
    large = [o for o in outcomes if o["call"].startswith("load_prototypes (%d" % soak_scene.LARGE_MEMORY)]
    held_since = large[0]["t_s"] + large[0]["seconds"] + args.interval if large else 0.0
    rss_rows = [r for r in warm_rows if r["t_s"] - args.interval >= held_since]
    third = max(1, len(rss_rows) // 3)
    rss = {"first_third_mb": None, "last_third_mb": None, "bound_mb": args.rss_bound_mb,
           "judged_from_s": round(held_since, 1)}
    if len(rss_rows) >= 3:
        rss["first_third_mb"] = round(statistics.median(r["rss_mb"] for r in rss_rows[:third]), 1)
        rss["last_third_mb"] = round(statistics.median(r["rss_mb"] for r in rss_rows[-third:]), 1)
        if rss["last_third_mb"] - rss["first_third_mb"] > args.rss_bound_mb:
            failures.append("RSS grew from %.1f MB (first third) to %.1f MB (last third), more than %g MB"
                            % (rss["first_third_mb"], rss["last_third_mb"], args.rss_bound_mb))
    else:
        failures.append("too short a run to judge the memory (fewer than 3 intervals after the warm-up and the "
                        "first reload of %d prototypes)" % soak_scene.LARGE_MEMORY)
    for o in outcomes:
        if not o["as_expected"]:
            failures.append("t = %g s, %s: %s" % (o["t_s"], o["call"], o["outcome"]))
    failures += reload_rate_failures(outcomes, args.reload_rate_tolerance)
    return failures, rss


def summary(args, target, rows, warm_rows, recorder, outcomes, rss, failures, loads, achieved_rate):
    latency, processing = recorder.all_latency, recorder.all_processing
    warm_answers = sum(r["answered"] for r in warm_rows)
    seconds = args.interval * len(warm_rows) or 1.0
    figures = {
        "settings": {"minutes": args.minutes, "rate_hz": args.rate, "size": args.size, "process": args.process,
                     "interval_s": args.interval, "out": args.out, "prototypes": sorted(soak_scene.PROTOTYPES), "target": target,
                     "reload_rate_tolerance": args.reload_rate_tolerance},
        "load_average_before_after": loads,
        "input_rate_achieved_hz": round(achieved_rate, 1),
        "published": recorder.published_total, "answered": recorder.answered_total,
        "not_answered": recorder.published_total - recorder.answered_total,
        "output_rate_hz_after_warmup": round(warm_answers / seconds, 1),
        "latency_ms_after_warmup": {"median": soak_record.rounded(statistics.median(latency) if latency else None),
                                    "p95": soak_record.rounded(soak_record.percentile(latency, 0.95)),
                                    "max": soak_record.rounded(max(latency, default=None))},
        "processing_ms_after_warmup": {
            "median": soak_record.rounded(statistics.median(processing) if processing else None),
            "p95": soak_record.rounded(soak_record.percentile(processing, 0.95)),
            "max": soak_record.rounded(max(processing, default=None))},
        "rss": rss, "rss_range_mb": [min(r["rss_mb"] for r in rows), max(r["rss_mb"] for r in rows)] if rows else None,
        "threads_range": [min(r["threads"] for r in rows), max(r["threads"] for r in rows)] if rows else None,
        "open_fds_range": [min(r["open_fds"] for r in rows), max(r["open_fds"] for r in rows)] if rows else None,
        "reported_share_after_warmup": soak_record.rounded(
            sum((r["reported_share"] or 0.0) * r["answered"] for r in warm_rows) / max(1, warm_answers), 3),
        "answers_with_other_labels": sum(r["other_labels"] for r in rows),
        "last_diagnostics": recorder.diagnostics,
        "calls": outcomes, "failures": failures, "passed": not failures,
    }
    lat, proc = figures["latency_ms_after_warmup"], figures["processing_ms_after_warmup"]
    print("\n==== Soak summary ====")
    print("settings: %s min, %s at %g Hz (achieved %.1f Hz), %s, %d prototypes, target '%s'"
          % (args.minutes, args.size, args.rate, achieved_rate, args.process, len(soak_scene.PROTOTYPES), target))
    print("load average (1 min) before/after: %s / %s" % tuple(loads))
    print("RSS: first third %s MB, last third %s MB (bound +%g MB); range %s MB; threads %s; open files %s"
          % (rss["first_third_mb"], rss["last_third_mb"], args.rss_bound_mb, figures["rss_range_mb"],
             figures["threads_range"], figures["open_fds_range"]))
    print("output: %.1f Hz after warm-up; %d frames published, %d answered, %d not answered"
          % (figures["output_rate_hz_after_warmup"], figures["published"], figures["answered"],
             figures["not_answered"]))
    print("latency stamp->receipt: median %s ms, p95 %s ms, max %s ms; processing median %s ms, p95 %s ms"
          % (lat["median"], lat["p95"], lat["max"], proc["median"], proc["p95"]))
    print("target reported in %.1f %% of the answers after warm-up; answers with another label: %d"
          % (100.0 * figures["reported_share_after_warmup"], figures["answers_with_other_labels"]))
    print("diagnostics at the end: %s" % ", ".join("%s %s" % (k, recorder.diagnostics.get(k)) for k in (
        "frames received", "frames processed", "frames skipped (bad input)", "frames dropped (sequence gaps)")))
    print("calls: %d, %d as expected" % (len(outcomes), sum(o["as_expected"] for o in outcomes)))
    print("output around the calls that rebuild (the %g s before -> while the call ran; a reload's rate judged: no "
          "more than %g %% below):" % (SECONDS_BEFORE_A_CALL, 100.0 * args.reload_rate_tolerance))
    for o in outcomes:
        if o.get("rebuilds"):
            print("  " + around_line(o))
    print("verdict: %s" % ("PASSED" if not failures else "FAILED\n  " + "\n  ".join(failures)))
    return figures


def markdown(figures):
    """The run as Markdown (soak.md; docs/soak-latest.md is a copy of the last full run's)."""
    s, rss, lat, proc = figures["settings"], figures["rss"], figures["latency_ms_after_warmup"], \
        figures["processing_ms_after_warmup"]
    diag = figures["last_diagnostics"]
    lines = [
        "# Soak run of %s" % figures["date"], "",
        "`scripts/soak --minutes %g --rate %g --size %s --process %s` at commit %s; %s, %d cores. Load average "
        "(1 min) before/after: %s / %s." % (s["minutes"], s["rate_hz"], s["size"], s["process"], figures["commit"],
                                            figures["machine"]["cpu"], figures["machine"]["cores"],
                                            *figures["load_average_before_after"]),
        "", "Verdict: **%s**" % ("passed" if figures["passed"] else "failed"), ""]
    lines += ["- %s" % f for f in figures["failures"]]
    lines += [
        "", "| figure | value |", "|---|---|",
        "| input rate achieved | %s Hz (%d frames) |" % (figures["input_rate_achieved_hz"], figures["published"]),
        "| output rate after warm-up | %s Hz |" % figures["output_rate_hz_after_warmup"],
        "| frames not answered | %d (diagnostics: %s dropped as sequence gaps, %s skipped) |" % (
            figures["not_answered"], diag.get("frames dropped (sequence gaps)"), diag.get("frames skipped (bad input)")),
        "| latency stamp to receipt (median / p95 / max) | %s / %s / %s ms |" % (lat["median"], lat["p95"], lat["max"]),
        "| processing_ms (median / p95 / max) | %s / %s / %s ms |" % (proc["median"], proc["p95"], proc["max"]),
        "| RSS, median of the first / last third after warm-up | %s / %s MB (bound: +%g MB) |" % (
            rss["first_third_mb"], rss["last_third_mb"], rss["bound_mb"]),
        "| RSS range, threads, open files | %s MB, %s, %s |" % (
            figures["rss_range_mb"], figures["threads_range"], figures["open_fds_range"]),
        "| target reported (share of answers after warm-up) | %.1f %% |" % (100.0 * figures["reported_share_after_warmup"]),
        "| answers with another label | %d |" % figures["answers_with_other_labels"],
        "", "## Calls", "", "| t (s) | call | as expected | outcome | took (s) |", "|---|---|---|---|---|"]
    lines += ["| %s | %s | %s | %s | %s |" % (c["t_s"], c["call"], "yes" if c["as_expected"] else "**no**",
                                             c["outcome"].replace("|", "/"), c["seconds"]) for c in figures["calls"]]
    lines += ["", "## Output around the calls that rebuild", "",
              "The %g s before each call against the time it ran. A reload's rate is judged (at most %g %% below) "
              "when at least %d answers were due while it ran; a reconfiguration's is not (it changes the work "
              "per frame)." % (SECONDS_BEFORE_A_CALL, 100.0 * s.get("reload_rate_tolerance", 0.1),
                               MIN_FRAMES_TO_JUDGE), "",
              "| t (s) | call | took (s) | rate before / during (Hz) | change | latency median before / during (ms) "
              "| p95 | max | judged |", "|---|---|---|---|---|---|---|---|---|"]
    for c in figures["calls"]:
        if not c.get("rebuilds"):
            continue
        b, d = c["output_before"], c["output_during"]
        lines.append("| %s | %s | %s | %s / %s | %s | %s / %s | %s / %s | %s / %s | %s |" % (
            c["t_s"], c["call"], c["seconds"], b["rate_hz"], d["rate_hz"],
            "-" if c["rate_change"] is None else "%+.0f %%" % (100.0 * c["rate_change"]),
            b["latency_median_ms"], d["latency_median_ms"], b["latency_p95_ms"], d["latency_p95_ms"],
            b["latency_max_ms"], d["latency_max_ms"],
            "yes" if c["rate_judged"] else "input outran it" if c["reloads"] and not c.get("keeping_up", True)
            else "too short" if c["reloads"] else "no"))
    cols = ["t_s", "rss_mb", "cpu_percent", "input_hz", "output_hz", "latency_median_ms", "latency_p95_ms",
            "latency_max_ms", "processing_median_ms", "unanswered", "reported_share", "load_1min"]
    lines += ["", "## Per interval", "", "| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    lines += ["| " + " | ".join("-" if r[c] is None else str(r[c]) for c in cols) + " |" for r in figures["rows"]]
    # The output folder is the reader's own: name it <out>, as the options do.
    return "\n".join(lines).replace(s.get("out") or "\0", "<out>") + "\n"


def load_average():
    with open("/proc/loadavg") as f:
        return float(f.read().split()[0])


def commit():
    try:
        return subprocess.run(["git", "-C", os.path.dirname(os.path.abspath(__file__)), "rev-parse", "--short",
                               "HEAD"], capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def cpu_name():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown"
