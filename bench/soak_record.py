"""What bench/soak_driver measures: the recognizer process (/proc), the messages it answers with, and
one row per interval. Kept apart from the driver so that the figures are defined in one place."""

import os
import statistics
import threading
import time

COLUMNS = ["t_s", "rss_mb", "threads", "open_fds", "cpu_percent", "published", "input_hz", "answered",
           "output_hz", "latency_median_ms", "latency_p95_ms", "latency_max_ms", "processing_median_ms",
           "processing_max_ms", "longest_gap_s", "unanswered", "reported_share", "other_labels",
           "diag_received", "diag_processed", "diag_skipped", "diag_dropped", "diag_level", "load_1min",
           "events"]


def percentile(values, share):
    """The value below which `share` of `values` lie (nearest rank); None for no values."""
    if not values:
        return None
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(share * len(ordered)))]


def rounded(value, digits=1):
    return None if value is None else round(value, digits)


class ProcessProbe:
    """RSS, threads, open files and CPU time of one process, read from /proc/<pid>."""

    def __init__(self, pid):
        self.pid = pid
        self.clock_ticks = os.sysconf("SC_CLK_TCK")
        self.last_cpu = None

    def alive(self):
        try:
            with open("/proc/%d/stat" % self.pid) as f:
                state = f.read().rsplit(")", 1)[1].split()[0]
            return state not in ("Z", "X")
        except OSError:
            return False

    def status(self):
        """{'rss_mb', 'threads', 'open_fds'} from /proc/<pid>/status and fd/."""
        fields = {}
        with open("/proc/%d/status" % self.pid) as f:
            for line in f:
                key, _, value = line.partition(":")
                fields[key] = value.split()
        fds = len(os.listdir("/proc/%d/fd" % self.pid))
        return {"rss_mb": int(fields["VmRSS"][0]) / 1024.0, "threads": int(fields["Threads"][0]), "open_fds": fds}

    def cpu_percent(self):
        """Share of one core used since the previous call (None on the first)."""
        with open("/proc/%d/stat" % self.pid) as f:
            parts = f.read().rsplit(")", 1)[1].split()
        cpu = (int(parts[11]) + int(parts[12])) / self.clock_ticks
        now = time.monotonic()
        previous, self.last_cpu = self.last_cpu, (now, cpu)
        if previous is None or now <= previous[0]:
            return None
        return 100.0 * (cpu - previous[1]) / (now - previous[0])


class Recorder:
    """Collects the answers (~recognitions) and the published frames between two interval rows."""

    def __init__(self, target):
        self.target = target
        self.lock = threading.Lock()
        self.answers = []        # (receipt time, latency ms, processing ms, target reported, others)
        self.history = []        # (receipt time, target reported, latency ms) of every answer
        self.all_latency = []    # after warm-up, for the run's percentiles
        self.all_processing = []
        self.published = 0
        self.published_total = 0
        self.answered_total = 0
        self.last_answer = None
        self.previous_receipt = None  # receipt time of the last answer of the previous interval
        self.diagnostics = {}
        self.events = []
        self.warm = False

    def on_published(self):
        with self.lock:
            self.published += 1
            self.published_total += 1

    def on_recognitions(self, msg):
        now = time.time()
        labels = {o.label for o in msg.objects}
        row = (now, 1000.0 * (now - msg.header.stamp.to_sec()), msg.processing_ms, self.target in labels,
               bool(labels - {self.target}))
        with self.lock:
            self.answers.append(row)
            self.history.append((now, row[3], row[1]))
            self.answered_total += 1
            self.last_answer = time.monotonic()
            if self.warm:
                self.all_latency.append(row[1])
                self.all_processing.append(row[2])

    def on_diagnostics(self, msg):
        for status in msg.status:
            if status.name.endswith("recognizer"):
                values = {v.key: v.value for v in status.values}
                values["level"] = {0: "OK", 1: "WARN", 2: "ERROR", 3: "STALE"}.get(status.level, str(status.level))
                with self.lock:
                    self.diagnostics = values

    def event(self, text):
        with self.lock:
            self.events.append(text)

    def answers_between(self, start, end):
        """The answers received in [start, end) (wall-clock seconds)."""
        with self.lock:
            return [a for a in self.history if start <= a[0] < end]  # (receipt time, target reported, latency ms)

    def window(self, start, end):
        """The output between two wall-clock times: answers, rate and latency of the answers received."""
        answers = self.answers_between(start, end)
        latency = [a[2] for a in answers]
        seconds = max(end - start, 1e-9)
        return {"seconds": round(seconds, 2), "answers": len(answers), "rate_hz": round(len(answers) / seconds, 1),
                "latency_median_ms": rounded(statistics.median(latency) if latency else None),
                "latency_p95_ms": rounded(percentile(latency, 0.95)),
                "latency_max_ms": rounded(max(latency, default=None))}

    def take_interval(self, t_s, seconds, probe):
        """One row of the CSV: the interval since the previous call."""
        with self.lock:
            answers, self.answers = self.answers, []
            published, self.published = self.published, 0
            events, self.events = self.events, []
            diag = dict(self.diagnostics)
        latency = [a[1] for a in answers]
        processing = [a[2] for a in answers]
        # Gaps between answers, the one across the start of the interval included.
        times = ([self.previous_receipt] if self.previous_receipt is not None else []) + [a[0] for a in answers]
        gaps = [b - a for a, b in zip(times, times[1:])]
        if times:
            self.previous_receipt = times[-1]
        status = probe.status()
        with open("/proc/loadavg") as f:
            load = float(f.read().split()[0])
        return {
            "t_s": round(t_s, 1), "rss_mb": round(status["rss_mb"], 1), "threads": status["threads"],
            "open_fds": status["open_fds"], "cpu_percent": rounded(probe.cpu_percent()),
            "published": published, "input_hz": round(published / seconds, 1), "answered": len(answers),
            "output_hz": round(len(answers) / seconds, 1),
            "latency_median_ms": rounded(statistics.median(latency) if latency else None),
            "latency_p95_ms": rounded(percentile(latency, 0.95)), "latency_max_ms": rounded(max(latency, default=None)),
            "processing_median_ms": rounded(statistics.median(processing) if processing else None),
            "processing_max_ms": rounded(max(processing, default=None)),
            "longest_gap_s": rounded(max(gaps, default=None), 2), "unanswered": max(0, published - len(answers)),
            "reported_share": rounded(sum(a[3] for a in answers) / len(answers), 3) if answers else None,
            "other_labels": sum(a[4] for a in answers),
            "diag_received": diag.get("frames received"), "diag_processed": diag.get("frames processed"),
            "diag_skipped": diag.get("frames skipped (bad input)"),
            "diag_dropped": diag.get("frames dropped (sequence gaps)"), "diag_level": diag.get("level"),
            "load_1min": load, "events": "; ".join(events),
        }
