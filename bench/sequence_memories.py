"""The memories of the benchmark suites, and the instances they hold out: which MPEG-7 silhouettes
each suite's `prototypes/` folder holds (memory_of), the `paper` memory's classes, the 3 most alike
birds of `similar`, the nested `memory-growth` memories and the held-out instances of the
several-instance memories (each drawn once from a fixed seed, whatever --seed)."""

import os

import cv2
import numpy as np

from sequence_files import read_grey
from sequence_suites import GROWTH_SEED, HOLDOUT_SEED


MPEG7_FILES = {}  # (class, instance) -> path; some classes write the instance as 01..09


def mpeg7_classes(mpeg7):
    for name in os.listdir(mpeg7):
        stem, ext = os.path.splitext(name)
        if ext == ".png" and "-" in stem:
            cls, n = stem.rsplit("-", 1)
            MPEG7_FILES[(cls, int(n))] = os.path.join(mpeg7, name)
    return sorted({cls for cls, _ in MPEG7_FILES})


def mpeg7_file(cls, n):
    return MPEG7_FILES[(cls, n)]


def paper_classes(classes):
    """17 classes, every 4th of the sorted list: fixed, not chosen by how well anything does."""
    return classes[::4][:17]


def similar_triple(mpeg7, cls="bird"):
    """The 3 instances of `cls` whose outlines are closest (Hu-moment distance, sum over pairs)."""
    contours = {}
    for n in range(1, 21):
        mask = read_grey(mpeg7_file(cls, n))
        found, _ = cv2.findContours((mask > 127).astype(np.uint8), cv2.RETR_EXTERNAL,
                                    cv2.CHAIN_APPROX_NONE)
        contours[n] = max(found, key=cv2.contourArea)
    best, best_cost = None, None
    ids = sorted(contours)
    for i in ids:
        for j in ids:
            for k in ids:
                if not i < j < k:
                    continue
                d = lambda a, b: cv2.matchShapes(contours[a], contours[b], cv2.CONTOURS_MATCH_I1, 0)
                cost = d(i, j) + d(i, k) + d(j, k)
                if best_cost is None or cost < best_cost:
                    best, best_cost = (i, j, k), cost
    return {"%s-%d" % (cls, n): mpeg7_file(cls, n) for n in best}


def growth_memories(classes):
    """size -> labels of the `memory-growth` memories, nested: 3 of the paper's 17, the 17, the 17 and
    18 other classes, all 70. Drawn once from GROWTH_SEED, whatever --seed."""
    rng = np.random.default_rng(GROWTH_SEED)
    paper = paper_classes(classes)
    rest = [c for c in classes if c not in paper]
    three = sorted(str(c) for c in rng.choice(paper, 3, replace=False))
    extra = sorted(str(c) for c in rng.choice(rest, 35 - len(paper), replace=False))
    return {3: three, 17: sorted(paper), 35: sorted(paper + extra), 70: sorted(classes)}


def holdout_instances(classes):
    """(held out, five): class -> its held-out instance (1..20), for every class; paper class -> the
    5 instances (sorted) of the `within-class-85` memory, among the 19 not held out. Drawn once from
    HOLDOUT_SEED, whatever --seed: the held-out ones first, class by class in name order, then the
    fives in the same order."""
    rng = np.random.default_rng(HOLDOUT_SEED)
    held = {c: int(rng.integers(1, 21)) for c in sorted(classes)}
    five = {}
    for c in sorted(paper_classes(classes)):
        rest = [n for n in range(1, 21) if n != held[c]]
        five[c] = sorted(int(n) for n in rng.choice(rest, 5, replace=False))
    return held, five


def instance_name(cls, n):
    """The file stem of instance n of a class in a sub-directory memory: <class>-<n>, no leading zero."""
    return "%s-%d" % (cls, n)


def memory_of(kind, classes, mpeg7):
    """label -> source file of the memory; label -> {instance name: source file} for the memories
    with several instances per label (written as prototypes/<label>/<instance>.png)."""
    if kind == "paper17":
        return {c: mpeg7_file(c, 1) for c in paper_classes(classes)}
    if kind == "all70":
        return {c: mpeg7_file(c, 1) for c in classes}
    if kind == "all70x19":
        held, _ = holdout_instances(classes)
        return {c: {instance_name(c, n): mpeg7_file(c, n) for n in range(1, 21) if n != held[c]} for c in classes}
    if kind == "paper17x5":
        _, five = holdout_instances(classes)
        return {c: {instance_name(c, n): mpeg7_file(c, n) for n in five[c]} for c in five}
    if kind == "growth":  # the targets: the smallest memory (main writes every memory)
        return {c: mpeg7_file(c, 1) for c in growth_memories(classes)[3]}
    if kind == "similar3":
        return similar_triple(mpeg7)
    if kind in ("paper16+mire", "paper16+cube", "paper16+cut"):  # the drawn target / the cut part: by main
        return {c: mpeg7_file(c, 1) for c in paper_classes(classes)[:16]}
    raise ValueError(kind)
