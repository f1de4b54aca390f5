"""The occluders of the occluded sampled suites (bench/sampling.py): a patch drawn in front of the
target in every frame, moving with it, that covers a given share of the target's area; or, in
`clutter-occluded-sampled`, a patch of the same kinds moving in a scene with no memory shape.

Per sequence the occluder is drawn from a generator of its own, keyed by the draw's key, the sequence
index and OCCLUDER_STREAM, so the scene's other draws are those of the suite it occludes and the same
sequence gets the same occluder (kind, direction, grey, texture, silhouette) at every share:

  kind        flat (one grey), textured (stripes and grain about a grey) or silhouette (another
              MPEG-7 shape, of a class not in the memory, in one grey), one in three each
  direction   an angle fixed per sequence in the target's prototype: the occluder covers the part
              of the target's area that lies furthest along it (flat, textured: a strip whose inner
              edge is the line leaving that share beyond it; silhouette: the shape slid along the
              direction until it covers that share)
  grey        distinct from the target's ink and from the background's mean under the target by a
              drawn margin (30-70 grey levels)

The cover is computed on the target's mask in a canvas of the prototype scaled to CANVAS_SIDE px, and
the occluder is drawn through the target's prototype->image affine (area shares are kept by an
affine), after the target. The share achieved is measured in every frame on the rendered masks (the
target's and the occluder's alpha above one half) and recorded in truth.json ("occluder")."""

import math

import cv2
import numpy as np

from sequence_files import read_grey
from sequence_memories import mpeg7_file
from sequence_motion import Mover, target_box
from sequence_suites import HEIGHT, WIDTH

OCCLUDER_STREAM = 60719  # the occluder's generator: key + [sequence index, OCCLUDER_STREAM]
KINDS = ("flat", "textured", "silhouette")
CANVAS_SIDE = 200  # the target's longer side in the canvas the cover is computed in, px
PAD = 320  # canvas margin around the target (room for the silhouette), canvas px
STRIP_MARGIN = 0.12  # the strip reaches this share of the target's longer side beyond its outline
SILHOUETTE_TRIES = 8  # rotations of the silhouette tried before the strip is used instead
SHARE_TOLERANCE = 0.01  # the cover in the canvas is within this of the share


def admissible_grey(u, margin, avoid):
    """The grey level at quantile u of those at least `margin` from every value of `avoid` (the
    margin halved until some are)."""
    while margin >= 1:
        levels = [g for g in range(256) if all(abs(g - a) >= margin for a in avoid)]
        if levels:
            return float(levels[min(len(levels) - 1, int(u * len(levels)))]), margin
        margin /= 2
    return float(int(u * 255)), 0.0


class Occluder:
    """One sequence's occluder. `share`: the share of the target to cover (None: a free patch in a
    scene with no target); `others`: MPEG-7 classes not in the memory (the silhouettes)."""

    def __init__(self, key, index, share, others):
        rng = np.random.default_rng(list(key) + [index, OCCLUDER_STREAM])
        self.share = share
        # Every value is drawn whatever the kind, in one order: another kind changes none of them.
        self.kind = KINDS[int(rng.integers(len(KINDS)))]
        self.direction = float(rng.uniform(0.0, 2.0 * math.pi))
        self.margin = float(rng.uniform(30.0, 70.0))
        self.grey_quantile = float(rng.random())
        self.stripe_angle = float(rng.uniform(0.0, math.pi))
        self.stripe_period = float(rng.uniform(6.0, 16.0))
        self.stripe_amplitude = float(rng.uniform(25.0, 50.0))
        self.grain = float(rng.uniform(8.0, 16.0))
        self.texture_seed = int(rng.integers(1 << 31))
        self.silhouette = (str(others[int(rng.integers(len(others)))]), int(rng.integers(1, 21)))
        self.silhouette_span = float(rng.uniform(1.3, 1.7))  # its extent across the direction / the target's
        self.silhouette_turns = rng.uniform(-math.pi, math.pi, SILHOUETTE_TRIES).tolist()
        self.patch_aspect = float(math.exp(rng.uniform(-0.6, 0.6)))  # the free patch (no target)
        self.motion_rng = np.random.default_rng(list(key) + [index, OCCLUDER_STREAM, 1])
        self.shares = []
        self.info = {}

    # The set-up, once the scene's clutter and the target's mask, ink and first pose are known.
    def start(self, clutter, target, inverted):
        """target: (mask, ink, mover) or None (a free patch)."""
        if target is None:
            self._start_free(clutter, inverted)
        else:
            self._start_target(clutter, *target)

    def _canvas_of(self, mask):
        """The target's mask in the canvas (longer side CANVAS_SIDE, PAD around): (mask, q)."""
        h, w = mask.shape
        q = CANVAS_SIDE / max(w, h)
        small = cv2.resize(mask, (max(1, round(w * q)), max(1, round(h * q))), interpolation=cv2.INTER_AREA)
        return cv2.copyMakeBorder(small, PAD, PAD, PAD, PAD, cv2.BORDER_CONSTANT, value=0), q

    def _start_target(self, clutter, mask, ink, mover):
        canvas_target, q = self._canvas_of(mask)
        inside = canvas_target > 127
        ys, xs = np.nonzero(inside)
        d = np.array([math.cos(self.direction), math.sin(self.direction)])
        n = np.array([-d[1], d[0]])
        along, across = xs * d[0] + ys * d[1], xs * n[0] + ys * n[1]
        self.kind_used = self.kind
        cover = None
        if self.kind == "silhouette":
            cover = self._slide_silhouette(canvas_target.shape, inside, d, n, along, across)
            if cover is None:
                self.kind_used = "flat"  # no rotation of the silhouette met the share
        if cover is None:
            t = float(np.quantile(along, 1.0 - self.share))
            reach = STRIP_MARGIN * CANVAS_SIDE
            a0, a1, c0, c1 = t, along.max() + reach, across.min() - reach, across.max() + reach
            corners = np.array([a * d + c * n for a, c in ((a0, c0), (a1, c0), (a1, c1), (a0, c1))])
            cover = np.zeros(canvas_target.shape, np.uint8)
            cv2.fillConvexPoly(cover, np.round(corners * 16).astype(np.int32), 255, cv2.LINE_AA, 4)
        self.canvas = cover
        self.canvas_share = float(np.count_nonzero(inside & (cover > 127)) / np.count_nonzero(inside))
        # canvas pixel (u, v) -> prototype pixel ((u - PAD) / q, (v - PAD) / q)
        self.to_prototype = np.array([[1 / q, 0, -PAD / q], [0, 1 / q, -PAD / q], [0, 0, 1.0]])
        self.target_mask = mask
        self.avoid = [ink]
        self.clutter = clutter
        self.pending_grey = True
        self.info = {"kind": self.kind, "direction_deg": round(math.degrees(self.direction), 2),
                     "share": self.share, "canvas_share": round(self.canvas_share, 4)}
        if self.kind_used != self.kind:
            self.info["kind"], self.info["kind_drawn"] = self.kind_used, self.kind
            self.info["silhouette_fallback"] = "no rotation of the silhouette covered the share; the strip instead"
        if self.kind_used == "silhouette":
            self.info["silhouette"] = "%s-%d" % self.silhouette
            self.info["silhouette_turn_deg"] = round(math.degrees(self.info_turn), 2)

    def _slide_silhouette(self, shape, inside, d, n, along, across):
        """The silhouette turned, scaled to span silhouette_span x the target across d, slid along d
        from beyond the target towards it until it covers the share (bisection on the slide)."""
        sil = read_grey(mpeg7_file(*self.silhouette))
        total = np.count_nonzero(inside)
        centre_across = (across.min() + across.max()) / 2
        span = across.max() - across.min()
        sh, sw = sil.shape
        for turn in self.silhouette_turns:
            c, s = math.cos(turn), math.sin(turn)
            # Its extent across d once turned (the silhouette's own pixels).
            sy, sx = np.nonzero(sil > 127)
            sx, sy = sx - (sw - 1) / 2, sy - (sh - 1) / 2
            rx, ry = c * sx - s * sy, s * sx + c * sy
            ext_across = rx * n[0] + ry * n[1]
            ext_along = rx * d[0] + ry * d[1]
            scale = self.silhouette_span * span / max(1.0, ext_across.max() - ext_across.min())
            mid_across = (ext_across.max() + ext_across.min()) / 2 * scale
            low_along = ext_along.min() * scale  # its nearest point to the target along -d

            def cover_at(offset):
                # the silhouette's nearest point along d at `offset` (a position along d in the canvas)
                centre = (offset - low_along) * d + (centre_across - mid_across) * n
                m = np.array([[c * scale, -s * scale, 0.0], [s * scale, c * scale, 0.0]])
                m[:, 2] = centre - m[:, :2] @ np.array([(sw - 1) / 2, (sh - 1) / 2])
                out = cv2.warpAffine(sil, m, shape[::-1], flags=cv2.INTER_LINEAR)
                return out, np.count_nonzero(inside & (out > 127)) / total

            far, near = along.max() + 1.0, along.min() - 1.0  # no cover at far; at near its edge is past the target
            if cover_at(near)[1] < self.share:
                continue
            for _ in range(40):
                mid = (far + near) / 2
                out, got = cover_at(mid)
                if abs(got - self.share) <= SHARE_TOLERANCE / 2:
                    break
                if got < self.share:
                    far = mid
                else:
                    near = mid
            if abs(got - self.share) <= SHARE_TOLERANCE:
                self.info_turn = turn
                return out
        return None

    def _start_free(self, clutter, inverted):
        """A patch with no target: a strip-like rectangle (flat, textured) or the silhouette, about a
        target's size, moving as a target does (its own generator)."""
        self.kind_used = self.kind
        if self.kind == "silhouette":
            sil = read_grey(mpeg7_file(*self.silhouette))
            canvas, q = self._canvas_of(sil)
            canvas = canvas[PAD - 4:-PAD + 4, PAD - 4:-PAD + 4]
        else:
            w = CANVAS_SIDE * min(1.0, self.patch_aspect)
            h = CANVAS_SIDE * min(1.0, 1.0 / self.patch_aspect)
            canvas = np.zeros((int(h) + 8, int(w) + 8), np.uint8)
            cv2.rectangle(canvas, (4, 4), (int(w) + 3, int(h) + 3), 255, -1)
        self.canvas = canvas
        self.to_prototype = np.eye(3)
        self.mover = Mover(self.motion_rng, canvas.shape[::-1], target_box(self.motion_rng, 1, 0))
        ink = 255.0 - 37.5 if inverted else 37.5  # the middle of the scene's ink range
        self.avoid = [ink]
        self.clutter = clutter
        self.pending_grey = True
        self.info = {"kind": self.kind, "direction_deg": None, "share": None}
        if self.kind == "silhouette":
            self.info["silhouette"] = "%s-%d" % self.silhouette

    def _choose_grey(self, canvas_to_image):
        """The occluder's grey: away from the ink and from the background's mean under it in frame 0."""
        alpha = cv2.warpAffine(self.canvas, canvas_to_image, (WIDTH, HEIGHT), flags=cv2.INTER_LINEAR) > 127
        background = float(self.clutter[alpha].mean()) if alpha.any() else float(self.clutter.mean())
        grey, margin = admissible_grey(self.grey_quantile, self.margin, self.avoid + [background])
        self.grey = grey
        self.info.update({"grey": grey, "grey_margin": round(margin, 2), "background_mean": round(background, 2),
                          "ink": round(float(self.avoid[0]), 2)})
        if self.kind_used == "textured":
            self.info.update({"stripe_period_px": round(self.stripe_period, 2),
                              "stripe_amplitude": round(self.stripe_amplitude, 2), "grain_sigma": round(self.grain, 2)})
            # The texture in the canvas, so that it moves with the occluder.
            h, w = self.canvas.shape
            ys, xs = np.mgrid[0:h, 0:w].astype(np.float32)
            u = xs * math.cos(self.stripe_angle) + ys * math.sin(self.stripe_angle)
            grain = np.random.default_rng(self.texture_seed).normal(0.0, self.grain, (h, w)).astype(np.float32)
            self.texture = np.clip(grey + self.stripe_amplitude * np.sign(np.sin(2 * math.pi * u / self.stripe_period))
                                   + grain, 0, 255).astype(np.float32)
        self.clutter = None
        self.pending_grey = False

    def paint(self, frame, target_matrix):
        """Draws the occluder into `frame` (before the lighting) over the target at `target_matrix`
        (its prototype->image affine; None for a free patch, which moves on its own) and returns the
        share of the target's area it covers (None without a target)."""
        if target_matrix is None:
            matrix = self.mover.pose(len(self.shares))
        else:
            matrix = np.asarray(target_matrix, dtype=np.float64)
        canvas_to_image = (np.vstack([matrix, [0, 0, 1.0]]) @ self.to_prototype)[:2]
        if self.pending_grey:
            self._choose_grey(canvas_to_image)
        alpha = cv2.warpAffine(self.canvas.astype(np.float32) / 255.0, canvas_to_image, (WIDTH, HEIGHT),
                               flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
        if self.kind_used == "textured":
            value = cv2.warpAffine(self.texture, canvas_to_image, (WIDTH, HEIGHT), flags=cv2.INTER_LINEAR,
                                   borderMode=cv2.BORDER_REPLICATE)
        else:
            value = self.grey
        frame *= 1.0 - alpha
        frame += alpha * value
        if target_matrix is None:
            self.shares.append(None)
            return None
        target = cv2.warpAffine(self.target_mask.astype(np.float32) / 255.0, matrix, (WIDTH, HEIGHT),
                                flags=cv2.INTER_LINEAR) > 0.5
        covered = float(np.count_nonzero(target & (alpha > 0.5)) / max(1, np.count_nonzero(target)))
        self.shares.append(covered)
        return covered

    def record(self):
        """What truth.json and draw.json keep of the occluder."""
        info = dict(self.info)
        known = [s for s in self.shares if s is not None]
        if known:
            info["covered_share"] = {"mean": round(float(np.mean(known)), 4), "min": round(float(min(known)), 4),
                                     "max": round(float(max(known)), 4)}
            info["covered_per_frame"] = [round(s, 4) for s in known]
        return info
