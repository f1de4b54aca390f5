"""The draws of bench/sampled_benchmark: per sampled suite and draw index k, a construction drawn from a
numpy generator keyed by (base seed, the suite's name, k) (deterministic; another k, another draw):
the memory, the noise level of each sequence, and on the real cameras the target's prototype with
its measured geometry perturbed as a user measuring with a ruler gets it wrong. render_draw writes the
draw as a suite folder that `amcr_evaluate --suite` reads, with the rendering functions of
bench/make_sequences, and records the draw in draw.json."""

import json
import os
import sys
import zlib

import cv2
import numpy as np

import printed_target
import real_camera
from occluders import Occluder
from sequence_files import write_memory
from sequence_memories import mpeg7_file
from sequence_photos import cut_part, render_photo
from sequence_real_camera import real_truth, render_real
from sequence_rendering import render_sequence
from sequence_suites import PART_PHOTOS, PHOTO_DIR, SUITES

# The sampled suites: the suite they draw constructions of (`like`), what is rendered (`kind`: a
# rendered suite, the real frames of a camera, the real photo), how many memory prototypes are drawn
# from the 70 MPEG-7 classes (the drawn target or the cut part comes on top of them on the real
# ones; 70: every class), the noise (`drawn`: each sequence's sigma, drawn as in `like`, times a
# factor drawn uniformly in [0, 1]; `none`: no noise added), and sequences and frames (full / quick).
# `draws_of`: the suite whose draws these are (the same memory, motion and frames, only the noise
# differs).
SAMPLED_SUITES = {
    "paper-sampled": dict(like="paper", kind="rendered", memory=17, noise="drawn", sequences=(6, 2), frames=(60, 40)),
    "mpeg7-70-sampled": dict(like="mpeg7-70", kind="rendered", memory=70, noise="drawn", sequences=(6, 1),
                             frames=(60, 40)),
    "clutter-only-sampled": dict(like="clutter-only", kind="rendered", memory=17, noise="drawn", sequences=(4, 2),
                                 frames=(60, 40)),
    "real-camera-sampled": dict(like="real-camera", kind="real", memory=16, noise="none", sequences=(1, 1),
                                frames=(501, 40)),
    "real-camera-cube-sampled": dict(like="real-camera-cube", kind="real", memory=16, noise="none",
                                     sequences=(1, 1), frames=(80, 40)),
    "real-photos-sampled": dict(like="real-photos", kind="photo", memory=16, noise="drawn", sequences=(2, 1),
                                frames=(80, 40)),
    "real-photos-clean": dict(like="real-photos", kind="photo", memory=16, noise="none", sequences=(2, 1),
                              frames=(80, 40), draws_of="real-photos-sampled"),
}
# The occluded suites (bench/occluders.py): the draws of `paper-sampled` with the target partly
# covered in every frame by an occluder in front of it, `occluded` the share of its area covered
# (0: no occluder, the same frames as `paper-sampled`: the reference the others are compared with);
# `clutter-occluded-sampled`: the draws of `clutter-only-sampled` with an occluder moving in view
# ("free": no target to cover). Not among the suites sampled_benchmark runs by default.
OCCLUDED_SHARES = (0, 15, 25, 40)
for _share in OCCLUDED_SHARES:
    SAMPLED_SUITES["occluded-%d-sampled" % _share] = dict(
        like="paper", kind="rendered", memory=17, noise="drawn", sequences=(6, 2), frames=(60, 40),
        draws_of="paper-sampled", occluded=_share / 100.0)
SAMPLED_SUITES["clutter-occluded-sampled"] = dict(
    like="clutter-only", kind="rendered", memory=17, noise="drawn", sequences=(4, 2), frames=(60, 40),
    draws_of="clutter-only-sampled", occluded="free")
DEFAULT_SUITES = [name for name, spec in SAMPLED_SUITES.items() if "occluded" not in spec]
OCCLUSION_SUITES = [name for name, spec in SAMPLED_SUITES.items() if "occluded" in spec]
SPREAD = 0.05  # the drawn target's aspect, hole sizes and hole places: each within +-5% of the measured
SQUARE_CHANCE = 0.25  # a target within SPREAD of square is drawn as a plain square (aspect 1) this often


def fail(message):
    print("sampled_benchmark: " + message, file=sys.stderr)
    sys.exit(2)


def draw_key(seed, suite, k):
    """The integers every generator of draw k of `suite` starts from: the base seed, the name (CRC-32,
    the same in every process) and k; `real-photos-clean` takes the name of the suite it mirrors."""
    name = SAMPLED_SUITES[suite].get("draws_of", suite)
    return [int(seed), zlib.crc32(name.encode()), int(k)]


def measured_target(suite):
    """The real suite's target as a holed rectangle: {"aspect": width / height, "holes": [((x, y) in
    the normalised target, radius as a share of its height)], "shape", "square_to_prototype"}, from
    the geometry its module measured (bench/real_camera.py MIRE, bench/real_camera_cube.py CUBE)."""
    module, _ = real_truth(suite)
    if hasattr(module, "MIRE"):
        g = module.MIRE
        aspect = g["aspect"]
        holes = [(tuple(g["disc_center"]), g["disc_radius"])] + [(tuple(d), g["dot_radius"]) for d in g["dots"]]
    else:
        width, height = module.face_size()
        aspect = width / height
        holes = [(tuple(float(v) for v in d), module.CUBE["dot_radius"] / height) for d in module.face_dots()]
    return target_of(aspect, holes)


def target_of(aspect, holes):
    """A holed target of that aspect: its prototype shape (the longer side as the real suites' own,
    real_camera.prototype_shape) and the map of its unit square to the prototype's pixels."""
    shape = real_camera.prototype_shape({"aspect": aspect})
    return {"aspect": float(aspect), "holes": [((float(x), float(y)), float(r)) for (x, y), r in holes],
            "shape": list(shape), "square_to_prototype": printed_target.unit_square_to_prototype(shape).tolist()}


def perturb_target(rng, target):
    """The target as a user with a ruler measures it: the aspect, each hole's radius and each
    coordinate of each hole's centre (from the target's top-left corner) times a factor drawn
    uniformly in [1 - SPREAD, 1 + SPREAD]; a target whose aspect is within SPREAD of 1 is taken as a
    plain square (aspect 1) with probability SQUARE_CHANCE. Returns (the drawn target, the factors)."""
    n = len(target["holes"])
    aspect_factor = rng.uniform(1 - SPREAD, 1 + SPREAD)
    square = abs(target["aspect"] - 1.0) <= SPREAD and rng.random() < SQUARE_CHANCE
    centre_factors = rng.uniform(1 - SPREAD, 1 + SPREAD, (n, 2))
    radius_factors = rng.uniform(1 - SPREAD, 1 + SPREAD, n)
    aspect = 1.0 if square else target["aspect"] * aspect_factor
    holes = [((x * fx, y * fy), r * fr) for ((x, y), r), (fx, fy), fr in
             zip(target["holes"], centre_factors, radius_factors)]
    factors = {"aspect": 1.0 / target["aspect"] if square else float(aspect_factor), "square": bool(square),
               "hole_centres": centre_factors.round(6).tolist(), "hole_radii": radius_factors.round(6).tolist()}
    return target_of(aspect, holes), factors


def draw_target(target):
    """The prototype image of a holed target (white on black, the holes black): as the real suites'
    draw_prototype."""
    return printed_target.draw_holed_target(tuple(target["shape"]), target["holes"])


def plan_draw(suite, k, seed, classes, sequences):
    """Draw k of `suite`: {"key", "memory": the drawn MPEG-7 classes, "noise_scales": per sequence,
    "target": the perturbed target and its factors (real cameras)}. `sequences`: the full count, so
    that --quick renders a prefix of the same draw."""
    spec = SAMPLED_SUITES[suite]
    key = draw_key(seed, suite, k)
    rng = np.random.default_rng(key)
    if spec["memory"] >= len(classes):
        memory = sorted(classes)
    else:
        memory = sorted(str(c) for c in rng.choice(classes, spec["memory"], replace=False))
    scales = rng.uniform(0.0, 1.0, sequences)
    plan = {"key": key, "memory": memory, "noise_scales": [float(s) if spec["noise"] == "drawn" else 0.0
                                                           for s in scales]}
    if spec["kind"] == "real":
        measured = measured_target(spec["like"])
        drawn, factors = perturb_target(rng, measured)
        plan["target"] = {"measured": measured, "drawn": drawn, "factors": factors}
    return plan


def render_draw(folder, suite, k, seed, mpeg7, classes, mode, counts=None):
    """Renders draw k of `suite` into `folder` (prototypes/ and seq_NNN/ as bench/make_sequences
    writes a suite) and writes draw.json last; a folder whose draw.json is there is kept as it is
    (refused when it holds a draw of other settings). `mode`: 0 full, 1 quick; `counts`: (sequences,
    frames) overriding the suite's. Returns the draw record."""
    spec = SAMPLED_SUITES[suite]
    sequences, frames = spec["sequences"][mode], spec["frames"][mode]
    if counts:
        sequences, frames = counts[0] or sequences, counts[1] or frames
    settings = {"suite": suite, "draw": k, "seed": seed, "sequences": sequences, "frames": frames}
    record_path = os.path.join(folder, "draw.json")
    if os.path.exists(record_path):
        with open(record_path) as f:
            record = json.load(f)
        if {key: record.get(key) for key in settings} != settings:
            fail("%s holds a draw of other settings (%s); use another --out" % (folder, record_path))
        return record
    plan = plan_draw(suite, k, seed, classes, max(sequences, spec["sequences"][0]))
    proto_dir = os.path.join(folder, "prototypes")
    write_memory(proto_dir, {c: mpeg7_file(c, 1) for c in plan["memory"]})
    like = spec["like"]
    record = dict(settings, like=like, key=plan["key"], drawn_memory=plan["memory"], noise=spec["noise"])
    if spec["kind"] == "real":
        _, label = real_truth(like)
        cv2.imwrite(os.path.join(proto_dir, label + ".png"), draw_target(plan["target"]["drawn"]))
        record["target"] = dict(plan["target"], label=label)
    elif spec["kind"] == "photo":
        for name, label in PART_PHOTOS:
            cv2.imwrite(os.path.join(proto_dir, label + ".png"), cut_part(os.path.join(PHOTO_DIR, name))[0])
    record["memory"] = sorted(os.path.splitext(f)[0] for f in os.listdir(proto_dir))
    record["sequences_rendered"] = []
    for index in range(sequences):
        path = os.path.join(folder, "seq_%03d" % index)
        os.makedirs(path, exist_ok=True)
        scale = plan["noise_scales"][index]
        if spec["kind"] == "real":
            drawn = plan["target"]["drawn"]
            render_real(path, suite, index, frames, seed, like=like,
                        drawn={"shape": drawn["shape"], "square_to_prototype": drawn["square_to_prototype"],
                               "source": "drawn from the measured geometry perturbed (draw.json)"})
        elif spec["kind"] == "photo":
            render_photo(path, suite, index, frames, seed, key=plan["key"], noise_scale=scale)
        else:
            memory = {c: mpeg7_file(c, 1) for c in plan["memory"]}
            occluder = None
            if spec.get("occluded"):
                share = None if spec["occluded"] == "free" else spec["occluded"]
                occluder = Occluder(plan["key"], index, share, [c for c in classes if c not in plan["memory"]])
            render_sequence(path, suite, index, dict(SUITES[like]), memory, classes, mpeg7, frames, seed,
                            key=plan["key"], noise_scale=scale, occluder=occluder)
        with open(os.path.join(path, "truth.json")) as f:
            truth = json.load(f)
        record["sequences_rendered"].append({
            "name": os.path.basename(path), "noise_scale": round(scale, 6),
            "noise_sigma": truth.get("noise_sigma", 0.0),
            "targets": sorted({t["label"] for t in truth["targets"]})})
        if "occluder" in truth:
            record["sequences_rendered"][-1]["occluder"] = {
                k: v for k, v in truth["occluder"].items() if k != "covered_per_frame"}
    tmp = record_path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(record, f, indent=1)
        f.write("\n")
    os.replace(tmp, record_path)
    return record
