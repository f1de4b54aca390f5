"""The files of bench/make_sequences: reading a grey image, the one-line error, truth.json (written
last, so that an interrupted run resumes) and the memories' prototype folders."""

import json
import os
import shutil
import sys

import cv2


def fail(message):
    print("make_sequences: " + message, file=sys.stderr)
    sys.exit(2)


def read_grey(path):
    image = cv2.imread(path, cv2.IMREAD_GRAYSCALE)
    if image is None:
        fail("cannot read %s" % path)
    return image


def write_truth(path, truth):
    """truth.json, one line per frame, written under a temporary name then renamed."""
    tmp = os.path.join(path, "truth.json.tmp")
    with open(tmp, "w") as f:
        f.write("{\n")
        for key, value in truth.items():
            if key != "frames":
                f.write(" %s: %s,\n" % (json.dumps(key), json.dumps(value)))
        f.write(' "frames": [\n  ' + ",\n  ".join(json.dumps(r) for r in truth["frames"]) + "\n ]\n}\n")
    os.replace(tmp, os.path.join(path, "truth.json"))


def write_memory(folder, memory):
    """Copies a memory (memory_of) into `folder`: <label>.png, or <label>/<instance>.png for a label
    with several instances; files already there are kept."""
    os.makedirs(folder, exist_ok=True)
    for label, source in memory.items():
        if isinstance(source, dict):  # several instances: <label>/<instance>.png
            os.makedirs(os.path.join(folder, label), exist_ok=True)
            for instance, file in source.items():
                target = os.path.join(folder, label, instance + ".png")
                if not os.path.exists(target):
                    shutil.copyfile(file, target)
            continue
        target = os.path.join(folder, label + ".png")
        if not os.path.exists(target):
            shutil.copyfile(source, target)
