"""Truth for the `real-camera-cube` suite: one face of a dotted cube found in real frames by a method
of its own (the face's ring of dots, then the face's edges), independent of the recognizer under test.

Debian's `visp-images-data` ships `cube`: 80 frames (384x288 grey) of a hand-held camera (still over
frames 0-16 and 70-79) looking at a black cube with white dots, over a cluttered comic-book collage.
The face towards the camera is in view, whole, in every frame; from frame 40 on the cube's bottom and
left faces show too, ever less obliquely. That front face is the target: a black square whose 12
white dots are the border of a 4x4 grid (3 dot spacings across), a ring shifted a little towards one
corner. Per frame:

1. The ring. At global thresholds 160, 130, 190 and 100 (after a Gaussian blur of 0.8 px), bright
   components shaped like ellipses (printed_target.ellipse_blobs) are candidates. A dot and two of its
   6 nearest neighbours (areas within a factor 2.5, 50-130 degrees apart, the prototype's
   handedness) are taken as grid (0, 0), (1, 0), (0, 1); the 12 grid positions are predicted and the
   nearest blobs taken (within 0.35, 0.25, 0.2 spacings, the homography fitted to them each time).
   A ring has all 12 dots, each once, areas within a factor 3, and a grid -> image homography that
   fits them within an RMS of 0.05 spacings. Of the rings found, among those at least 0.8 of the
   largest one's area (the face most facing the camera), the best fitting wins. It fixes the
   labelling up to a quarter turn. (On cube: found at every threshold in all 80 frames, never on
   the side faces, whose dots are too squashed; RMS 0.05-0.10 px; dot spacing 15.3-19.3 px.)
2. The edges. Around the face predicted from the ring with the mean margin on every side, each side
   is searched and fitted as for mire-2 (printed_target.refine_square: the rising step nearest the
   predicted side along 31 normals, dark inside, bright outside or the thin bright line along the
   cube's edge where another face adjoins; Huber line fits; adjacent lines meet at the corners).
   The labelling: the quarter turn under which the face's four margins (corners brought back to the
   grid) are nearest the measured ones, i.e. the two wider margins are the face's left and bottom.
3. Checks; otherwise the frame is unknown and left unscored (with the reason): every corner at least
   2 px inside the frame; refine_square's own (60% of the steps on each line, RMS under 1.5 px);
   each end of each side within 1.5 px of where the ring and the measured margins put it (worst of
   the known frames: 1.1 px); every dot within 1.2 px of its place under the face's homography
   (worst known: 0.9 px); no corner moved by more than 20% of the diagonal since the previous frame
   when that was known.

The geometry (`CUBE`) was measured with `bench/real_camera_cube.py --measure` on all 80 frames (the
ring and 4 edges found in all; medians, 5-95% in brackets), in the labelling of the first frame:
the margins from the outer dots' centres to the edges are left 0.670 (0.647-0.690), bottom 0.643
(0.634-0.670), top 0.493 (0.488-0.513), right 0.491 (0.483-0.500) dot spacings; the face's
width/height 1.006, i.e. square within the edges' spread (the wider margins read 0.03-0.04
spacings, about 0.6 px, more in frames 0-30 than in frames 47-79, where the cube's left and bottom
faces adjoin those sides: probably the thin bright line between two faces against a step to the
collage); the dots round once rectified by the ring (width/height 0.990, 0.934-1.064), so on a
square grid; their radius 0.224 (0.222-0.228) spacings. `CUBE` keeps the square: wide margins 0.657
(left, bottom), narrow 0.492 (top, right): a side of 4.149 spacings (63.6-80.2 px in the frames),
dots at x 0.1584 / 0.3994 / 0.6404 / 0.8814 and y 0.1186 / 0.3596 / 0.6006 / 0.8416 of the side,
radius 0.054 of it. The prototype is drawn from these numbers (`draw_prototype`, 256 x 256 px, the
face 240 x 240 px, white square on black with the dots as holes, the mire's convention), never cut
from a frame.

`SYMMETRIES` are the four quarter turns: the outline is the same square under each, and the ring is
4-fold symmetric but for its shift (2.8% of the side off the face's centre): a quarter turn moves
every dot by 0.165 spacings (4.0% of the side), a half turn by 0.233 (5.6%), 3.2 and 4.5 px on the
largest views, about a dot's radius. The scoring takes the best of the four labellings. The best
affine approximation (`printed_target.best_affine`) is the least-squares affine over a 5x5 grid of the
face mapped by the homography. Over the known frames the target (the prototype's longer side at the
affine's area scale) is 68-86 px and the affine's anisotropy 1.04-1.31 (`--check` prints both).

Result on cube: 77 of 80 frames known. Frames 43-45 are unknown: the face's top edge, where the
collage beyond its left end is dark, is pulled outward there (an end 2.1-3.3 px off the ring's
prediction); see --check.
"""

import argparse
import glob
import math
import os

import cv2
import numpy as np

import printed_target  # beside this file: what the mire's truth and this one share (blob finder, edge search)

VISP_DIR = printed_target.VISP_DIR
SEQUENCE = "cube"

# The 12 dots of a face: the border of a 4x4 grid, in grid units (one dot spacing), clockwise from
# the top-left dot.
SIDE_NAMES = ["left", "top", "right", "bottom"]  # the face's sides, clockwise; side i ends at corner i
RING = np.float64([(0, 0), (1, 0), (2, 0), (3, 0), (3, 1), (3, 2), (3, 3), (2, 3), (1, 3), (0, 3), (0, 2), (0, 1)])

# The face (measured by `--measure`, see the docstring): margins from the outer dots' centres to the
# face's edges, in dot spacings, labelled as the face stands in the sequence's first frame (the two
# wider margins are its left and bottom ones); the dots' radius in dot spacings.
CUBE = {
    "margins": {"left": 0.657, "top": 0.492, "right": 0.492, "bottom": 0.657},
    "dot_radius": 0.224,
}

PROTOTYPE_SIZE = 256
PROTOTYPE_MARGIN = printed_target.PROTOTYPE_MARGIN  # px of background around the face in the prototype image

# The corner permutations a recognizer cannot tell apart: the four quarter turns. The face is square
# and its ring of dots 4-fold symmetric but for the ring's shift towards one corner (the margins
# above): a quarter turn leaves the outline where it was and moves every dot by 4% of the side
# (about 3 px on the largest views), less than a dot's diameter.
SYMMETRIES = [[0, 1, 2, 3], [1, 2, 3, 0], [2, 3, 0, 1], [3, 0, 1, 2]]

THRESHOLDS = (160, 130, 190, 100)  # the dots' bright components are looked for at these grey levels
RING_RMS = 0.05  # the ring's homography fits its 12 dots within this RMS, in dot spacings
SIDE_TOLERANCE = 1.5  # px: each end of a side found from the edges this near the dots' prediction at most
DOT_TOLERANCE = 1.2  # px: every dot this near its place under the face's homography at most
JUMP = 0.20  # no corner moved by more than this share of the diagonal since the previous known frame


def face_size(geometry=CUBE):
    """(width, height) of the face in dot spacings."""
    m = geometry["margins"]
    return 3 + m["left"] + m["right"], 3 + m["top"] + m["bottom"]


def face_dots(geometry=CUBE):
    """The 12 dots' centres in coordinates normalised to the face ([0, 1]^2, x over its width, y over
    its height, origin at its top-left corner), in RING's order."""
    width, height = face_size(geometry)
    m = geometry["margins"]
    return np.stack([(RING[:, 0] + m["left"]) / width, (RING[:, 1] + m["top"]) / height], 1)


def prototype_shape(geometry=CUBE):
    """(width, height) of the prototype image: the face's longer side is SIZE - 2 MARGIN px."""
    inner = PROTOTYPE_SIZE - 2 * PROTOTYPE_MARGIN
    width, height = face_size(geometry)
    w, h = (inner, inner * height / width) if width >= height else (inner * width / height, inner)
    return int(round(w)) + 2 * PROTOTYPE_MARGIN, int(round(h)) + 2 * PROTOTYPE_MARGIN


def square_to_prototype(geometry=CUBE):
    """3x3 map from the normalised face ([0, 1]^2) to prototype pixels (as the mire's, with the
    same margin: printed_target.unit_square_to_prototype)."""
    return printed_target.unit_square_to_prototype(prototype_shape(geometry))


def prototype_corners(geometry=CUBE):
    """The face's corners in prototype pixels, clockwise from the top-left."""
    return printed_target.unit_square_corners(square_to_prototype(geometry))


def draw_prototype(geometry=CUBE):
    """The memory image of the face, drawn from its measured geometry with the mire's convention
    (real_camera.draw_prototype): white shape on black, i.e. the black face is the white shape and
    its white dots are holes in it."""
    radius = geometry["dot_radius"] / face_size(geometry)[1]  # a share of the face's height
    return printed_target.draw_holed_target(prototype_shape(geometry), [(dot, radius) for dot in face_dots(geometry)])


apply = printed_target.apply


def ring_candidates(points, areas):
    """Every 12-dot ring among the blobs: (homography grid -> image, blob index per dot, RMS in
    spacings). A hypothesis is a dot and two of its 6 nearest neighbours (of an area within a factor
    2.5) as grid (0, 0), (1, 0) and (0, 1), at 50-130 degrees, the same handedness as the prototype;
    the ring is predicted from it and the nearest blobs taken (within 0.35, then 0.25, then 0.2
    spacings, the homography fitted to the blobs taken each time); all 12 must be taken, each once."""
    found = []
    for a in range(len(points)):
        d = np.linalg.norm(points - points[a], axis=1)
        alike = (areas > areas[a] / 2.5) & (areas < areas[a] * 2.5)
        alike[a] = False
        near = [j for j in np.argsort(d) if alike[j]][:6]
        for b in near:
            for c in near:
                u, v = points[b] - points[a], points[c] - points[a]
                if b == c or u[0] * v[1] - u[1] * v[0] <= 0:  # a mirror is no view of the face
                    continue
                if abs(np.dot(u, v)) > 0.64 * np.linalg.norm(u) * np.linalg.norm(v):
                    continue
                if not 0.5 < np.linalg.norm(u) / np.linalg.norm(v) < 2:
                    continue
                h = np.vstack([cv2.getAffineTransform(np.float32([[0, 0], [1, 0], [0, 1]]),
                                                      np.float32([points[a], points[b], points[c]])), [0, 0, 1]])
                spacing = min(np.linalg.norm(u), np.linalg.norm(v))
                taken = None
                for tolerance in (0.35, 0.25, 0.2):
                    dist = np.linalg.norm(apply(h, RING)[:, None, :] - points[None], axis=2)
                    nearest = dist.argmin(1)
                    good = dist[np.arange(len(RING)), nearest] < tolerance * spacing
                    if good.sum() < 6 or len(set(nearest[good])) < good.sum():
                        taken = None
                        break
                    taken = nearest if good.all() else None
                    h, _ = cv2.findHomography(RING[good], points[nearest[good]], 0)
                    if h is None:
                        taken = None
                        break
                if taken is None:
                    continue
                pitch = math.sqrt(cv2.contourArea(np.float32(points[taken])) / 9)
                rms = math.sqrt(np.mean(np.sum((apply(h, RING) - points[taken]) ** 2, 1))) / pitch
                found.append((h, taken, rms))
    return found


def find_ring(grey):
    """Step 1: (homography grid -> image, 12x2 dot centroids in RING's order) of the face most
    facing the camera, or None."""
    blurred = cv2.GaussianBlur(grey, (0, 0), 0.8)
    rings = []
    for threshold in THRESHOLDS:
        blobs = printed_target.ellipse_blobs(blurred, threshold)
        if len(blobs) < len(RING):
            continue
        points = np.float64([b[:2] for b in blobs])
        areas = np.float64([b[2] for b in blobs])
        for h, taken, rms in ring_candidates(points, areas):
            if rms <= RING_RMS and areas[taken].max() <= 3 * areas[taken].min():
                rings.append((cv2.contourArea(np.float32(points[taken])), rms, h, points[taken]))
    if not rings:
        return None
    # The face most facing the camera has the largest ring; of its finds (the 4 starting dots, the
    # thresholds), the one that fits its dots best.
    largest = max(r[0] for r in rings)
    _, _, h, dots = min((r for r in rings if r[0] >= 0.8 * largest), key=lambda r: r[1])
    return h, dots


def margins_of(corners, h_grid):
    """The face's margins (left, top, right, bottom) in dot spacings: its corners (clockwise from the
    grid's (0, 0) side) brought back to the grid by h_grid, each side's two ends averaged; and every
    end on its own (4x2: per side, its two ends)."""
    c = apply(np.linalg.inv(h_grid), corners)
    ends = np.array([[-c[3, 0], -c[0, 0]], [-c[0, 1], -c[1, 1]],
                     [c[1, 0] - 3, c[2, 0] - 3], [c[2, 1] - 3, c[3, 1] - 3]])
    return ends.mean(1), ends


def find_edges(grey, h_grid, margin):
    """Step 2: the face's 4 image corners from its edges (printed_target.refine_square, searched around
    the face predicted from the dots with `margin` on every side), or (None, reason)."""
    expand = np.array([[3 + 2 * margin, 0, -margin], [0, 3 + 2 * margin, -margin], [0, 0, 1]])
    return printed_target.refine_square(grey, h_grid @ expand)


def detect(grey, geometry=CUBE):
    """Steps 1-3 on one frame: (4x2 corners clockwise from the face's top-left, None) or (None,
    reason). The labelling comes from the face itself: the two wider margins are the left and bottom."""
    ring = find_ring(grey)
    if ring is None:
        return None, "no ring of 12 dots"
    h_grid, dots = ring
    m = geometry["margins"]
    corners, reason = find_edges(grey, h_grid, np.mean(list(m.values())))
    if corners is None:
        return None, reason
    height, width = grey.shape
    if corners.min() < 2 or corners[:, 0].max() > width - 3 or corners[:, 1].max() > height - 3:
        return None, "a corner within 2 px of the frame's border"
    found, ends = margins_of(corners, h_grid)
    # The labelling, from the face itself: the quarter turn of the ring's labelling under which the
    # margins found are nearest the face's (the wider two meet at its bottom-left corner).
    expected = [m[name] for name in SIDE_NAMES]
    turn = min(range(4), key=lambda t: np.sum((found - np.roll(expected, t)) ** 2))
    expected = np.roll(expected, turn)
    pitch = math.sqrt(cv2.contourArea(np.float32(dots)) / 9)  # the dot spacing in px, on average
    off = np.abs(ends - expected[:, None]).max(1) * pitch
    side = int(np.argmax(off))
    if off[side] > SIDE_TOLERANCE:
        return None, "the face's %s side: an end %.1f px off the dots' prediction" % (
            SIDE_NAMES[(side - turn) % 4], off[side])
    corners = np.roll(corners, -turn, 0)
    h = cv2.getPerspectiveTransform(np.float32([[0, 0], [1, 0], [1, 1], [0, 1]]), np.float32(corners))
    predicted = apply(h, face_dots(geometry))
    error = np.linalg.norm(predicted[:, None, :] - dots[None], axis=2).min(1).max()
    if error > DOT_TOLERANCE:
        return None, "a dot %.1f px off the face's homography" % error
    return corners, None


def track(frames_grey, geometry=CUBE, jump=JUMP):
    """Steps 1-3 on every frame, with the jump check. Returns one dict per frame: {"homography": 3x3
    prototype->image, "affine": 2x3, "corners": 4x2} or {"unknown": reason}."""
    out = []
    previous = None  # corners of the previous frame, when it was known
    for grey in frames_grey:
        corners, reason = detect(grey, geometry)
        if corners is not None and printed_target.corner_jumped(corners, previous, jump):
            corners, reason = None, "a corner jumped more than %.0f%% of the diagonal" % (100 * jump)
        if corners is None:
            out.append({"unknown": reason})
            previous = None
            continue
        out.append(printed_target.known_frame(corners, square_to_prototype(geometry)))
        previous = corners
    return out


def sequence_files(name=SEQUENCE):
    return sorted(glob.glob(os.path.join(VISP_DIR, name, "*.pgm")))


def rectified_dots(grey, h_grid, scale=40.0, threshold=130):
    """The dots' radius (spacings) and width/height once rectified by h_grid (scale px per spacing):
    the bright components at `threshold` nearest each grid position, medians."""
    to_view = np.array([[scale, 0, 2 * scale], [0, scale, 2 * scale], [0, 0, 1]])
    size = int(7 * scale)
    view = cv2.warpPerspective(grey, to_view @ np.linalg.inv(h_grid), (size, size), flags=cv2.INTER_CUBIC)
    blobs = printed_target.ellipse_blobs(view, threshold)
    radii, aspects = [], []
    for x, y in apply(to_view, RING):
        b = min(blobs, key=lambda b: math.hypot(b[0] - x, b[1] - y))
        if math.hypot(b[0] - x, b[1] - y) < 0.2 * scale:
            radii.append(math.sqrt(b[2] / math.pi) / scale)
            aspects.append(math.sqrt(b[3][0, 0] / b[3][1, 1]))
    return float(np.median(radii)), float(np.median(aspects))


def measure(name=SEQUENCE, every=1):
    """Re-measures the face's geometry (see the docstring), prints it and returns it."""
    greys = [cv2.imread(f, cv2.IMREAD_GRAYSCALE) for f in sequence_files(name)[::every]]
    rows = []
    for grey in greys:
        ring = find_ring(grey)
        if ring is None:
            continue
        h_grid = ring[0]
        corners, _ = find_edges(grey, h_grid, 0.57)
        if corners is None:
            continue
        found, _ = margins_of(corners, h_grid)
        # The two wider margins, sides i and i+1 of the ring's labelling, become the left and the
        # bottom ones (sides 0 and 3): the face as it stands in the first frame.
        wide = max(range(4), key=lambda i: found[i] + found[(i + 1) % 4])
        radius, aspect = rectified_dots(grey, h_grid)
        rows.append(list(np.roll(found, -(wide + 1))) + [radius, aspect])
    r = np.array(rows)
    m = np.median(r, 0)
    low, high = np.percentile(r, 5, 0), np.percentile(r, 95, 0)
    print("%d of %d frames (ring and 4 edges found)" % (len(rows), len(greys)))
    for i, what in enumerate(["margin left", "margin top", "margin right", "margin bottom", "dot radius",
                              "dot width/height"]):
        print("  %s: median %.3f (5-95%%: %.3f-%.3f)" % (what, m[i], low[i], high[i]))
    wide, narrow = (m[0] + m[3]) / 2, (m[1] + m[2]) / 2
    print("  face width/height %.4f" % ((3 + m[0] + m[2]) / (3 + m[1] + m[3])))
    geometry = {"margins": {"left": round(wide, 3), "top": round(narrow, 3), "right": round(narrow, 3),
                            "bottom": round(wide, 3)}, "dot_radius": round(m[4], 3)}
    print("geometry (margins averaged over the wide pair and the narrow pair):", geometry)
    return geometry


def face_poses(truth, geometry=CUBE):
    """Per known frame: the target's size in px at the affine's area scale (the prototype's longer side
    times the square root of the affine's determinant) and the affine's anisotropy (ratio of its
    singular values): what scripts/benchmark tells the peers."""
    longer = max(prototype_shape(geometry))
    poses = []
    for t in truth:
        if "affine" in t:
            s = np.linalg.svd(t["affine"][:, :2], compute_uv=False)
            poses.append((longer * math.sqrt(s[0] * s[1]), s[0] / s[1]))
    return poses


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--measure", action="store_true", help="measure the face's geometry again")
    parser.add_argument("--check", metavar="DIR", nargs="?", const="",
                        help="print per frame known or unknown (and why) and the poses' range; with DIR, draw "
                             "the truth on every 10th frame into DIR")
    parser.add_argument("--sequence", default=SEQUENCE)
    args = parser.parse_args()
    if args.measure:
        measure(args.sequence)
    if args.check is not None:
        files = sequence_files(args.sequence)
        greys = [cv2.imread(f, cv2.IMREAD_GRAYSCALE) for f in files]
        truth = track(greys)
        for k, t in enumerate(truth):
            print("frame %3d: %s" % (k, "known" if "homography" in t else "unknown (%s)" % t["unknown"]))
        known = sum("homography" in t for t in truth)
        print("%s: %d of %d frames known" % (args.sequence, known, len(truth)))
        poses = np.array(face_poses(truth))
        if len(poses):
            print("face size %.1f-%.1f px (prototype's longer side at the affine's area scale), anisotropy "
                  "%.3f-%.3f" % (poses[:, 0].min(), poses[:, 0].max(), poses[:, 1].min(), poses[:, 1].max()))
    if args.check:
        os.makedirs(args.check, exist_ok=True)
        for k in range(0, len(files), 10):
            image = cv2.cvtColor(greys[k], cv2.COLOR_GRAY2BGR)
            if "homography" in truth[k]:
                h = truth[k]["homography"]
                c = apply(h, prototype_corners())
                cv2.polylines(image, [np.int32(np.round(c * 4))], True, (0, 0, 255), 1, cv2.LINE_AA, 2)
                cv2.circle(image, tuple(np.int32(c[0])), 3, (0, 255, 0), -1)
                for d in apply(h, apply(square_to_prototype(), face_dots())):
                    cv2.circle(image, tuple(np.int32(np.round(d * 4))), 8, (255, 0, 0), 1, cv2.LINE_AA, 2)
            cv2.imwrite(os.path.join(args.check, "check_%04d.png" % k), image)


if __name__ == "__main__":
    main()
