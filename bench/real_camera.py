"""Truth for the `real-camera` suite: a printed planar target found in real frames by a method of
its own (blob pattern, then the target's edges), independent of the recognizer under test.

Debian's `visp-images-data` ships `mire-2`: 501 frames (384x288 grey, a hand-held camera) of a box
carrying a printed target, a black rectangle (1.281:1, measured; not a square) with a big white disc
at its centre and four white dots near its corners, in front of a cluttered room. Per frame:

1. The pattern. At global thresholds 160, 130, 190 and 100 (after a Gaussian blur of 0.8 px),
   bright connected components shaped like ellipses (area within 15% of the ellipse of the same
   second moments) are candidates. A configuration is a disc (at least 300 px) and 4 dots (each
   2-30% of the disc's area, within a factor 3 of each other, 1-5 disc radii away, convex in
   angular order around the disc). Of the two labellings that the target's half-turn symmetry
   leaves, the one under which the disc, rectified by the dots' homography, is round (its spreads
   along the target's axes within a factor 1.2) is kept; the configuration is kept when that
   homography maps the disc's centre within 8% of the dots' diagonal of the disc's centroid and the
   disc's area within a factor 1.6; the best configuration over the thresholds wins.
2. The edges. From that homography, each side of the rectangle is searched along 31 normals (from
   15% to 85% of the side, up to 10% of its length either way) for the rising step (dark inside,
   bright outside, at least 20 grey levels over 2 px, a local maximum) nearest the predicted side,
   sub-pixel by a parabola; a line is fitted to each side's steps (Huber; steps more than 2 px off
   dropped and the line fitted again), and adjacent lines meet at the corners. The prototype->image
   homography maps the rectangle's 4 corners onto them.
3. Checks; otherwise the frame is unknown and left unscored (with the reason): every corner at least
   2 px inside the frame; every side with at least 60% of its 31 steps on its line, RMS under 1.5 px;
   the corners within 10% of the side of those of step 1; the dots and the disc mapped by the final
   homography within 4% of the mean side of their centroids; no corner moved by more than 20% of
   the diagonal since the previous frame when that was known.

The corner labelling: step 1 fixes it up to the half turn; in the first known frame the corner
nearest the image's top-left comes first (clockwise on the screen), afterwards the half turn closest
to the last known frame's corners is kept, so the labelling does not flip. The scoring takes the
better of the two labellings (`SYMMETRIES`), as a recognizer cannot tell them apart.

The geometry (`MIRE`) was measured once with `bench/real_camera.py --measure` on every 5th frame:
pass 1 rectifies with the dots provisionally on a square and reads the disc's width/height there
(0.831 in 101 of 101 frames, 5-95% 0.82-0.84): the dots' horizontal spacing is 1.203 times the
vertical one; pass 2 rectifies with the dots on that rectangle, finds the edges as in step 2 (30
frames with all 4 edges), and measures the margins around the dots (left 0.251, right 0.248 of the
horizontal spacing, top 0.208, bottom 0.199 of the vertical one), the disc (centred within 0.001,
round within 0.1%, radius 0.273 of the vertical spacing) and the dots (radius 0.072). With the
margins averaged left/right and top/bottom: a rectangle of width/height 1.281; in coordinates
normalised to it, dots at x 0.1665 / 0.8335 and y 0.1446 / 0.8554, disc at the centre with a radius
of 0.194 of the height, dots 0.0513. (`--measure` run again with the edge search as it is now finds
all 4 edges in 76 frames: margins 0.250, 0.248, 0.209, 0.200, width/height 1.279, dots at x 0.1672 /
0.8346, y 0.1485 / 0.8579: within 0.3% of the side, under 0.7 px on the largest views; `MIRE` keeps
the first figures, with which the benchmark's figures were made.) The prototype is drawn from these numbers (`draw_prototype`,
256 x 203 px, the rectangle 240 x 187 px, white shape on black with the disc and dots as holes),
never cut from a frame. The best affine approximation (`prototype_to_image`) is the least-squares
affine over a 5x5 grid of the rectangle mapped by the homography.

Result on mire-2: 389 of 501 frames known (the others: an edge not found, mostly the target cut by
the frame or its side against a bright background; see --check).
"""

import argparse
import glob
import math
import os

import cv2
import numpy as np

from printed_target import (PROTOTYPE_MARGIN, VISP_DIR, apply, corner_jumped, draw_holed_target, ellipse_blobs,
                            known_frame, refine_square, unit_square_corners, unit_square_to_prototype)

# mire-2's target (measured by `--measure`, see the docstring): a black rectangle of width/height
# ASPECT; positions in coordinates normalised to the rectangle (x over its width, y over its height,
# origin at its top-left corner), radii in units of its height; dots clockwise from the top-left.
MIRE = {
    "aspect": 1.281,
    "disc_center": (0.5, 0.5),
    "disc_radius": 0.194,
    "dots": [(0.1665, 0.1446), (0.8335, 0.1446), (0.8335, 0.8554), (0.1665, 0.8554)],
    "dot_radius": 0.0513,
}

PROTOTYPE_SIZE = 256

# The corner permutations under which the target looks the same: the identity and the half turn
# (it is mirror-symmetric too, but a mirror is no motion of the print: the affine's determinant
# would be negative).
SYMMETRIES = [[0, 1, 2, 3], [2, 3, 0, 1]]


def prototype_shape(geometry=MIRE):
    """(width, height) of the prototype image: the rectangle's longer side is SIZE - 2 MARGIN px."""
    inner = PROTOTYPE_SIZE - 2 * PROTOTYPE_MARGIN
    w, h = (inner, inner / geometry["aspect"]) if geometry["aspect"] >= 1 else (inner * geometry["aspect"], inner)
    return int(round(w)) + 2 * PROTOTYPE_MARGIN, int(round(h)) + 2 * PROTOTYPE_MARGIN


def square_to_prototype(geometry=MIRE):
    """The rectangle's unit_square_to_prototype."""
    return unit_square_to_prototype(prototype_shape(geometry))


def prototype_corners(geometry=MIRE):
    """The rectangle's corners in prototype pixels, clockwise from the top-left."""
    return unit_square_corners(square_to_prototype(geometry))


def draw_prototype(geometry=MIRE):
    """The memory image of the target, drawn from its measured geometry: white shape on black (the
    memory's convention), i.e. the black rectangle printed on the target is the white shape here and
    its white disc and dots are holes in it."""
    holes = [(geometry["disc_center"], geometry["disc_radius"])]
    holes += [(dot, geometry["dot_radius"]) for dot in geometry["dots"]]
    return draw_holed_target(prototype_shape(geometry), holes)


def find_pattern(grey, geometry=MIRE):
    """Step 1: (homography unit square -> image from the dots, dot centroids, disc centroid), or None."""
    blurred = cv2.GaussianBlur(grey, (0, 0), 0.8)
    dots_unit = np.float32(geometry["dots"])
    spread = np.linalg.norm(dots_unit[2] - dots_unit[0])
    best = None
    for threshold in (160, 130, 190, 100):
        blobs = ellipse_blobs(blurred, threshold)
        for disc in blobs:
            if disc[2] < 300:
                continue
            r = math.sqrt(disc[2] / math.pi)
            near = [b for b in blobs if 0.02 * disc[2] < b[2] < 0.3 * disc[2]
                    and r < math.hypot(b[0] - disc[0], b[1] - disc[1]) < 5 * r]
            near = sorted(near, key=lambda b: math.hypot(b[0] - disc[0], b[1] - disc[1]))[:8]
            for combo in combinations(near, 4):
                areas = [b[2] for b in combo]
                if max(areas) > 3 * min(areas):
                    continue
                ordered = sorted(combo, key=lambda b: math.atan2(b[1] - disc[1], b[0] - disc[0]))
                image_dots = np.float32([b[:2] for b in ordered])
                if not cv2.isContourConvex(image_dots.reshape(-1, 1, 2)):
                    continue
                # Which dot is the first: the labelling that makes the disc round once rectified.
                labellings = [np.roll(image_dots, -k, 0) for k in range(2)]
                homographies = [cv2.getPerspectiveTransform(dots_unit, d) for d in labellings]
                scores = [disc_roundness(hk, disc, geometry) if geometry["aspect"] else 0.0 for hk in homographies]
                k = int(np.argmin(scores))
                roundness, image_dots, h = scores[k], labellings[k], homographies[k]
                if geometry["aspect"] and roundness > math.log(1.2):
                    continue
                size = np.linalg.norm(image_dots[2] - image_dots[0]) / spread
                centre = apply(h, [geometry["disc_center"]])[0]
                error = math.hypot(centre[0] - disc[0], centre[1] - disc[1]) / (size * spread)
                if error > 0.08:
                    continue
                # The disc's expected area: the image of its outline, sampled.
                t = np.linspace(0, 2 * math.pi, 36, endpoint=False)
                rim = np.stack([geometry["disc_center"][0] + geometry["disc_radius"] / (geometry["aspect"] or 1) * np.cos(t),
                                geometry["disc_center"][1] + geometry["disc_radius"] * np.sin(t)], 1)
                expected = cv2.contourArea(apply(h, rim).astype(np.float32))
                if not 1 / 1.6 < disc[2] / max(expected, 1e-9) < 1.6:
                    continue
                if best is None or error < best[0]:
                    best = (error, h, image_dots, np.array(disc[:2]))
    return None if best is None else best[1:]


def disc_roundness(h, disc, geometry):
    """|log| of the ratio of the disc's spreads along the target's axes once rectified by h (0 when
    the labelling of h is right: a disc is round)."""
    x, y = disc[0], disc[1]
    inv = np.linalg.inv(h)
    eps = 0.5
    p0 = apply(inv, [[x, y]])[0]
    jac = np.stack([(apply(inv, [[x + eps, y]])[0] - p0) / eps, (apply(inv, [[x, y + eps]])[0] - p0) / eps], 1)
    metric = np.diag([geometry["aspect"], 1.0]) @ jac
    c = metric @ disc[3] @ metric.T
    return abs(math.log(c[0, 0] / c[1, 1]))


def combinations(items, k):
    if k == 0:
        yield ()
        return
    for i in range(len(items) - k + 1):
        for rest in combinations(items[i + 1:], k - 1):
            yield (items[i],) + rest


def detect(grey, geometry=MIRE):
    """Steps 1-3 on one frame, without tracking: (4x2 corners clockwise from the unit square's
    (0, 0) corner as the pattern ordered it, None) or (None, reason)."""
    pattern = find_pattern(grey, geometry)
    if pattern is None:
        return None, "no disc with 4 dots around it"
    h0, image_dots, disc = pattern
    corners, reason = refine_square(grey, h0)
    if corners is None:
        return None, reason
    height, width = grey.shape
    if corners.min() < 2 or corners[:, 0].max() > width - 3 or corners[:, 1].max() > height - 3:
        return None, "a corner within 2 px of the frame's border"
    sides = [np.linalg.norm(corners[i] - corners[(i + 1) % 4]) for i in range(4)]
    mean_side = float(np.mean(sides))
    first = apply(h0, [[0, 0], [1, 0], [1, 1], [0, 1]])
    if np.max(np.linalg.norm(first - corners, axis=1)) > 0.10 * mean_side:
        return None, "the edges' corners are far from the dots' ones"
    h = cv2.getPerspectiveTransform(np.float32([[0, 0], [1, 0], [1, 1], [0, 1]]), np.float32(corners))
    errors = list(np.linalg.norm(apply(h, geometry["dots"]) - image_dots, axis=1))
    errors.append(float(np.linalg.norm(apply(h, [geometry["disc_center"]])[0] - disc)))
    if max(errors) > 0.04 * mean_side:
        return None, "the dots are %.1f px off the square's homography" % max(errors)
    return corners, None


def track(frames_grey, geometry=MIRE, jump=0.20):
    """Steps 1-3 with the labelling carried from frame to frame. Returns one dict per frame:
    {"homography": 3x3 prototype->image, "affine": 2x3} or {"unknown": reason}."""
    out = []
    previous = None  # corners of the previous frame, when it was known
    last = None  # corners of the last known frame (for the labelling)
    for grey in frames_grey:
        corners, reason = detect(grey, geometry)
        if corners is not None:
            # The pattern fixed the labelling up to the target's half turn: pick the half turn.
            if last is None:
                shift = 0 if corners[0].sum() <= corners[2].sum() else 2  # the top-left one first
            else:
                shift = min((0, 2), key=lambda s: np.sum(np.linalg.norm(np.roll(corners, -s, 0) - last, axis=1)))
            corners = np.roll(corners, -shift, 0)
            if corner_jumped(corners, previous, jump):
                corners, reason = None, "a corner jumped more than %.0f%% of the diagonal" % (100 * jump)
        if corners is None:
            out.append({"unknown": reason})
            previous = None
            continue
        out.append(known_frame(corners, square_to_prototype(geometry)))
        previous = last = corners
    return out


def sequence_files(name):
    return sorted(glob.glob(os.path.join(VISP_DIR, name, "*.pgm")))


def disc_aspect(mask, blob):
    """Width/height of the bright component at `blob` from its second moments (a circle: 1)."""
    _, labels = cv2.connectedComponents(mask.astype(np.uint8))
    m = cv2.moments((labels == labels[int(round(blob[1])), int(round(blob[0]))]).astype(np.uint8), True)
    return math.sqrt(m["mu20"] / m["mu02"])


def measure(name="mire-2", every=5):
    """Re-measures the target's geometry (see the docstring), prints it and returns it."""
    files = sequence_files(name)[::every]
    greys = [cv2.imread(f, cv2.IMREAD_GRAYSCALE) for f in files]
    # Pass 1: the dots' rectangle. With the dots provisionally on a square (and no roundness test,
    # aspect None), the disc comes out as
    # an ellipse whose width/height is the ratio of the dots' vertical to horizontal spacing.
    square = {"aspect": None, "dots": [(0, 0), (1, 0), (1, 1), (0, 1)], "disc_center": (0.5, 0.5),
              "disc_radius": 0.25}
    ratios = []
    for grey in greys:
        pattern = find_pattern(grey, square)
        if pattern is not None:
            rect = cv2.warpPerspective(grey, np.array([[200.0, 0, 100], [0, 200.0, 100], [0, 0, 1]])
                                       @ np.linalg.inv(pattern[0]), (400, 400))
            bright = ellipse_blobs(rect, 150)
            if bright:
                d = min(bright, key=lambda b: math.hypot(b[0] - 200, b[1] - 200))
                ratios.append(1 / disc_aspect(rect > 150, d))
    dots_aspect = float(np.median(ratios))
    # Pass 2: with the dots on that rectangle (vertical spacing 1), the rectangle's edges (step 2 of
    # the truth, from a first guess of a margin of 0.2 of the spacing), the disc and the dots.
    provisional = {"aspect": dots_aspect, "dots": [(0, 0), (1, 0), (1, 1), (0, 1)], "disc_center": (0.5, 0.5),
                   "disc_radius": 0.25}
    guess = 0.2
    expand = np.array([[1 + 2 * guess, 0, -guess], [0, 1 + 2 * guess, -guess], [0, 0, 1]])
    scale = 200.0  # rectified view: px per vertical dot spacing
    to_view = np.array([[scale * dots_aspect, 0, 100], [0, scale, 100], [0, 0, 1]])
    rows = []
    for grey in greys:
        pattern = find_pattern(grey, provisional)
        if pattern is None:
            continue
        h_dots = pattern[0]
        corners, _ = refine_square(grey, h_dots @ expand)
        if corners is None:
            continue
        c = apply(np.linalg.inv(h_dots), corners)  # in the dots' normalised frame
        size = (int(200 + scale * dots_aspect), 400)
        rect = cv2.warpPerspective(grey, to_view @ np.linalg.inv(h_dots), size)
        bright = ellipse_blobs(rect, 150)
        centre = (100 + scale * dots_aspect / 2, 200)
        d = min(bright, key=lambda b: math.hypot(b[0] - centre[0], b[1] - centre[1]))
        dots = [min(bright, key=lambda b: math.hypot(b[0] - x, b[1] - y)) for x, y in
                apply(to_view, [[0, 0], [1, 0], [1, 1], [0, 1]])]
        rows.append([-(c[0, 0] + c[3, 0]) / 2, (c[1, 0] + c[2, 0]) / 2 - 1,
                     -(c[0, 1] + c[1, 1]) / 2, (c[2, 1] + c[3, 1]) / 2 - 1,
                     (d[0] - centre[0]) / (scale * dots_aspect), (d[1] - centre[1]) / scale,
                     math.sqrt(d[2] / math.pi) / scale, np.mean([math.sqrt(b[2] / math.pi) for b in dots]) / scale,
                     disc_aspect(rect > 150, d)])
    r = np.array(rows)
    m = np.median(r, 0)
    print("pass 1: %d frames; dots' horizontal/vertical spacing %.3f (5-95%%: %.3f-%.3f)"
          % (len(ratios), dots_aspect, *np.percentile(ratios, [5, 95])))
    print("pass 2: %d frames (pattern and 4 edges found); margins in dot spacings: left %.3f right %.3f "
          "top %.3f bottom %.3f; disc centre offset (%.3f, %.3f); radius %.3f; dot radius %.3f (both in "
          "vertical spacings); disc width/height once rectified %.3f" % (len(rows), *m))
    ml, mr, mt, mb = m[:4]
    width, height = dots_aspect * (1 + ml + mr), 1 + mt + mb
    geometry = {"aspect": round(width / height, 4), "disc_center": (round((ml + 0.5 + m[4]) / (1 + ml + mr), 4),
                                                                 round((mt + 0.5 + m[5]) / height, 4)),
                "disc_radius": round(m[6] / height, 4),
                "dots": [(round(x, 4), round(y, 4)) for x, y in
                         ((ml / (1 + ml + mr), mt / height), ((1 + ml) / (1 + ml + mr), mt / height),
                          ((1 + ml) / (1 + ml + mr), (1 + mt) / height), (ml / (1 + ml + mr), (1 + mt) / height))],
                "dot_radius": round(m[7] / height, 4)}
    print("geometry:", geometry)
    return geometry


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--measure", action="store_true", help="measure the target's geometry again")
    parser.add_argument("--check", metavar="DIR", help="draw the truth on every 50th frame into DIR")
    parser.add_argument("--sequence", default="mire-2")
    args = parser.parse_args()
    if args.measure:
        measure(args.sequence)
    if args.check:
        os.makedirs(args.check, exist_ok=True)
        files = sequence_files(args.sequence)
        greys = [cv2.imread(f, cv2.IMREAD_GRAYSCALE) for f in files]
        truth = track(greys)
        known = sum("homography" in t for t in truth)
        print("%s: %d of %d frames known" % (args.sequence, known, len(truth)))
        reasons = {}
        for t in truth:
            if "unknown" in t:
                key = t["unknown"].split(":")[0]
                reasons[key] = reasons.get(key, 0) + 1
        print(reasons)
        for k in range(0, len(files), 50):
            image = cv2.cvtColor(greys[k], cv2.COLOR_GRAY2BGR)
            if "homography" in truth[k]:
                c = apply(truth[k]["homography"], prototype_corners())
                cv2.polylines(image, [np.int32(np.round(c * 4))], True, (0, 0, 255), 1, cv2.LINE_AA, 2)
                cv2.circle(image, tuple(np.int32(c[0])), 4, (0, 255, 0), -1)
                dots = apply(truth[k]["homography"], apply(square_to_prototype(), MIRE["dots"]))
                for d in dots:
                    cv2.circle(image, tuple(np.int32(np.round(d * 4))), 8, (255, 0, 0), 1, cv2.LINE_AA, 2)
            cv2.imwrite(os.path.join(args.check, "check_%04d.png" % k), image)


if __name__ == "__main__":
    main()
