"""amcr_offline on a still photo, for the benchmark's real-photo scripts (real_tags.py,
real_templates.py): the photo repeated for a number of frames, one run per recognizer seed."""
import json
import os
import subprocess


def parse_seeds(text):
    """"1-3" -> [1, 2, 3]; "1,4" -> [1, 4]."""
    if "-" in text:
        first, last = text.split("-")
        return list(range(int(first), int(last) + 1))
    return [int(v) for v in text.split(",")]


def run_still(binary_dir, prototypes, photo, frames, seed, output, config=""):
    """Runs amcr_offline on `photo` for `frames` frames with recognizer `seed`, the memory read from
    the folder `prototypes`, its JSON lines written to `output`; returns them parsed, one per frame."""
    command = [os.path.join(binary_dir, "amcr_offline"), "--prototypes", prototypes, "--input", photo,
               "--frames", str(frames), "--seed", str(seed), "--output", output]
    if config:
        command += ["--config", config]
    subprocess.run(command, check=True, stderr=subprocess.DEVNULL)
    with open(output) as f:
        return [json.loads(line) for line in f]
