"""What the real-camera truths (bench/real_camera.py: mire-2's target; bench/real_camera_cube.py: the
cube's face) share in finding a printed planar target in real frames: where visp-images-data's frames
are, points mapped by a homography, the prototype image of a target with round holes, bright
components shaped like ellipses, the target's sides found from their edges (step 2 of
bench/real_camera.py), the best affine of a homography and the truth of a known frame."""

import math

import cv2
import numpy as np

VISP_DIR = "/usr/share/visp-images-data/ViSP-images"

PROTOTYPE_MARGIN = 8  # px of background around the square in the prototype image


def apply(h, points):
    points = np.asarray(points, dtype=np.float64)
    p = np.hstack([points, np.ones((len(points), 1))]) @ h.T
    return p[:, :2] / p[:, 2:3]


def unit_square_to_prototype(shape):
    """3x3 map from the normalised target ([0, 1]^2) to the pixels of a prototype image of `shape`
    (width, height) with PROTOTYPE_MARGIN around the target (pixel-centre convention: the target
    covers the pixels MARGIN .. size-1-MARGIN, its edges half a pixel outside them)."""
    w, h = (v - 2 * PROTOTYPE_MARGIN for v in shape)
    return np.array([[w, 0, PROTOTYPE_MARGIN - 0.5], [0, h, PROTOTYPE_MARGIN - 0.5], [0, 0, 1.0]])


def unit_square_corners(square_to_prototype_map):
    """The target's corners in prototype pixels, clockwise from the top-left."""
    unit = np.array([[0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], dtype=np.float64)
    return (unit @ square_to_prototype_map.T)[:, :2]


def draw_holed_target(shape, holes):
    """A prototype image of `shape` (width, height): the target white on black with PROTOTYPE_MARGIN
    around it, and round holes in it, each (centre in the normalised target, radius as a share of
    its height). Drawn 8x larger and reduced (anti-aliased edges)."""
    up = 8
    width, height = shape
    big = np.zeros((height * up, width * up), np.uint8)
    m = PROTOTYPE_MARGIN * up
    w, h = (width - 2 * PROTOTYPE_MARGIN) * up, (height - 2 * PROTOTYPE_MARGIN) * up
    big[m:m + h, m:m + w] = 255
    for center, radius in holes:
        cx, cy = m - up / 2 + center[0] * w, m - up / 2 + center[1] * h
        cv2.circle(big, (int(round(cx * 16)), int(round(cy * 16))), int(round(radius * h * 16)), 0, -1,
                   cv2.LINE_8, 4)
    return cv2.resize(big, (width, height), interpolation=cv2.INTER_AREA)


def ellipse_blobs(grey, threshold):
    """(cx, cy, area, 2x2 covariance) of bright components shaped like ellipses."""
    n, labels, stats, _ = cv2.connectedComponentsWithStats((grey > threshold).astype(np.uint8), connectivity=8)
    found = []
    for i in range(1, n):
        area = int(stats[i, cv2.CC_STAT_AREA])
        if area < 12 or area > grey.size // 8:
            continue
        x, y, w, h = stats[i, :4]
        m = cv2.moments((labels[y:y + h, x:x + w] == i).astype(np.uint8), True)
        mu20, mu02, mu11 = m["mu20"] / area, m["mu02"] / area, m["mu11"] / area
        d = math.sqrt((mu20 - mu02) ** 2 / 4 + mu11 ** 2)
        l1, l2 = (mu20 + mu02) / 2 + d, (mu20 + mu02) / 2 - d
        if l2 <= 0:
            continue
        if not 0.85 < area / (4 * math.pi * math.sqrt(l1 * l2)) < 1.15:
            continue
        found.append((x + m["m10"] / m["m00"], y + m["m01"] / m["m00"], area, np.array([[mu20, mu11], [mu11, mu02]])))
    return found


def refine_square(grey, h):
    """Step 2: the square's 4 image corners from its edges, or (None, reason)."""
    g = cv2.GaussianBlur(grey, (0, 0), 0.7).astype(np.float32)
    height, width = g.shape
    unit = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=np.float64)
    centre = apply(h, [[0.5, 0.5]])[0]
    lines = []
    for side in range(4):
        a, b = unit[side], unit[(side + 1) % 4]
        ia, ib = apply(h, [a, b])
        length = np.linalg.norm(ib - ia)
        reach = max(4.0, 0.10 * length)
        points = []
        for t in np.linspace(0.15, 0.85, 31):
            p = apply(h, [a + t * (b - a)])[0]
            direction = apply(h, [a + (t + 0.01) * (b - a)])[0] - p
            normal = np.array([direction[1], -direction[0]])
            normal /= np.linalg.norm(normal)
            if np.dot(normal, p - centre) < 0:
                normal = -normal
            s = np.arange(-reach, reach + 0.5, 0.5)
            xs, ys = p[0] + s * normal[0], p[1] + s * normal[1]
            if xs.min() < 1 or ys.min() < 1 or xs.max() > width - 2 or ys.max() > height - 2:
                continue
            values = cv2.remap(g, xs.astype(np.float32).reshape(1, -1), ys.astype(np.float32).reshape(1, -1),
                               cv2.INTER_LINEAR).ravel()
            step = values[4:] - values[:-4]  # over 2 px, outward: bright outside minus dark inside
            # The rising steps of at least 20 grey levels that are local maxima: the nearest to
            # the predicted side (other edges, of the box or behind it, lie further out).
            peaks = [i for i in range(len(step)) if step[i] >= 20 and (i == 0 or step[i] >= step[i - 1])
                     and (i == len(step) - 1 or step[i] >= step[i + 1])]
            if not peaks:
                continue
            i = min(peaks, key=lambda i: abs(s[i] + 1.0))
            offset = 0.0
            if 0 < i < len(step) - 1:
                denom = step[i - 1] - 2 * step[i] + step[i + 1]
                if denom < 0:
                    offset = 0.5 * (step[i - 1] - step[i + 1]) / denom
            sd = s[i] + 1.0 + 0.5 * offset  # the step's centre between samples i and i+4
            points.append(p + sd * normal)
        if len(points) < 0.6 * 31:
            return None, "side %d: edge found at %d of 31 normals" % (side, len(points))
        pts = np.float32(points)
        for _ in range(2):  # fit, drop the steps more than 2 px off the line, fit again
            vx, vy, x0, y0 = cv2.fitLine(pts, cv2.DIST_HUBER, 0, 0.01, 0.01).ravel()
            residual = (pts[:, 0] - x0) * vy - (pts[:, 1] - y0) * vx
            pts, residual = pts[np.abs(residual) <= 2.0], residual[np.abs(residual) <= 2.0]
            if len(pts) < 0.6 * 31:
                return None, "side %d: %d of 31 steps on a line" % (side, len(pts))
        rms = float(np.sqrt(np.mean(residual ** 2)))
        if rms > 1.5:
            return None, "side %d: line fit RMS %.2f px" % (side, rms)
        lines.append((np.array([x0, y0]), np.array([vx, vy])))
    corners = []
    for side in range(4):  # corner `side` is where side-1 and side meet
        (p1, d1), (p2, d2) = lines[(side - 1) % 4], lines[side]
        m = np.array([[d1[0], -d2[0]], [d1[1], -d2[1]]])
        if abs(np.linalg.det(m)) < 1e-6:
            return None, "parallel sides"
        t = np.linalg.solve(m, p2 - p1)
        corners.append(p1 + t[0] * d1)
    return np.array(corners), ""


def best_affine(h_proto, square_to_proto):
    """Least-squares 2x3 affine prototype->image over a 5x5 grid of the target (`square_to_proto`:
    the unit square -> prototype pixels)."""
    t = np.linspace(0, 1, 5)
    unit = np.array([[x, y] for y in t for x in t])
    proto = apply(square_to_proto, unit)
    image = apply(h_proto, proto)
    design = np.hstack([proto, np.ones((len(proto), 1))])
    solution, *_ = np.linalg.lstsq(design, image, rcond=None)
    return solution.T


def corner_jumped(corners, previous, jump):
    """Whether a corner moved by more than `jump` of the diagonal since the previous known frame
    (None: no previous one)."""
    diagonal = np.linalg.norm(corners[2] - corners[0])
    return previous is not None and np.max(np.linalg.norm(corners - previous, axis=1)) > jump * diagonal


def known_frame(corners, square_to_proto):
    """The truth of a frame whose target corners (image px, clockwise from the prototype's top-left)
    are known: the prototype->image homography, its best affine and the corners."""
    h_unit = cv2.getPerspectiveTransform(np.float32([[0, 0], [1, 0], [1, 1], [0, 1]]), np.float32(corners))
    h_proto = h_unit @ np.linalg.inv(square_to_proto)
    h_proto /= h_proto[2, 2]
    return {"homography": h_proto, "affine": best_affine(h_proto, square_to_proto), "corners": corners}
