#!/usr/bin/python3
"""Found-by-frame curves: the share of runs (recognizer seeds x draws) whose target was first reported
at the right place by frame k, one curve per series, drawn with Debian's matplotlib (python3-matplotlib).

Each --run NAME=FILE.json reads a `found.json` (bench/real_camera_cut.py writes one): {"frames": N,
"first_report": {series: [first frame or null, ...]}}; a curve per (NAME, series), labelled "NAME,
series". Prints the share found within the first 10 and 30 frames per curve.

    bench/found_by_frame.py --run before=A/found.json --run after=B/found.json --out docs/images/x.png \
        [--title TEXT] [--series-label "memory of %s"]
"""
import argparse
import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def curve(firsts, frames):
    """Share of runs found by frame k (first report at a frame < k), k = 0 .. frames."""
    n = max(1, len(firsts))
    return [sum(f is not None and f < k for f in firsts) / n for k in range(frames + 1)]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--run", action="append", required=True, help="NAME=found.json")
    parser.add_argument("--out", required=True)
    parser.add_argument("--title", default="")
    parser.add_argument("--series-label", default="%s")
    args = parser.parse_args()
    fig, ax = plt.subplots(figsize=(9.5, 4.2), dpi=100)
    styles = ["--", "-", ":", "-."]
    for r, spec in enumerate(args.run):
        name, _, path = spec.partition("=")
        with open(path) as f:
            record = json.load(f)
        frames = record["frames"]
        for s, (series, firsts) in enumerate(sorted(record["first_report"].items(), key=lambda kv: int(kv[0]))):
            shares = curve(firsts, frames)
            label = "%s, %s" % (name, args.series_label % series)
            ax.step(range(frames + 1), shares, where="post", linestyle=styles[r % len(styles)],
                    color="C%d" % s, label=label)
            print("%-32s found within 10 frames %3.0f%%, within 30 %3.0f%%, at all %3.0f%% (%d runs)" % (
                label, 100 * shares[min(10, frames)], 100 * shares[min(30, frames)], 100 * shares[-1], len(firsts)))
    ax.set_xlabel("frame")
    ax.set_ylabel("share of runs found by then")
    ax.set_ylim(-0.02, 1.02)
    ax.grid(alpha=0.3)
    if args.title:
        ax.set_title(args.title)
    ax.legend(fontsize=8, loc="center left", bbox_to_anchor=(1.01, 0.5))
    fig.tight_layout()
    fig.savefig(args.out)


if __name__ == "__main__":
    main()
