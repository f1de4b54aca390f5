#!/usr/bin/python3
"""Many copies of one grey template in view: 36 parts on a board, as LEDs on a board or parts on a tray.

Each draw is a 640 x 480 board (grey 150) with 25 scattered lines and a 6 x 6 grid of copies of one
drawn part (a dark square body with a light disc and a light bar, so that no turn of it looks the
same), each turned at random, its body 52-60 px across, blurred (sigma 0.8 px) with sensor noise
(sigma 4 grey levels). The prototype is the part with its board margin and an alpha channel over
the body and a 4 px rim, so it is read as a grey template. The truth is the drawing's own affine of
each copy. amcr_offline runs the still scene for --frames frames per recognizer seed; the report
gives per draw and seed the copies reported within 3 px (mean over the body's corners), the others
reported, the median corner error, and the copies found by frames 10, 20, ...

    bench/repeated_parts.py --out .build/repeated-parts [--draws 1-3] [--seeds 1-2] [--frames 60] [--config FILE]
                            [--board 1600x1200 --grid 5x6]

--board and --grid draw another board (its copies spread evenly over it); without --config, a board
larger than 640 px is read at its own size (working_resolution).

The parts are 52-60 px, below the default min_object_size (64 px), and 36 is more than a config
with max_objects under 36 reports: the --config given should set min_object_size (40 here) and
max_objects; without one the script writes one with min_object_size 40 and the defaults otherwise.
"""
import json
import os
import sys

import cv2
import numpy as np

from still_photo import still_photo_parser, parse_seeds, run_still

HERE = os.path.dirname(os.path.abspath(__file__))
SIDE = 160                    # the part's template image, px
BODY = (20, 139)              # its body, first and last px on both axes
ROWS, COLUMNS = 6, 6
RIGHT_WITHIN = 3.0            # px: a copy reported this close (mean over the body's corners) is found


def draw_part():
    """The template (grey) and its alpha (the body and a 4 px rim of board)."""
    part = np.full((SIDE, SIDE), 150, np.uint8)
    cv2.rectangle(part, (BODY[0], BODY[0]), (BODY[1], BODY[1]), 45, -1)
    cv2.circle(part, (60, 62), 22, 215, -1)
    cv2.rectangle(part, (40, 108), (120, 122), 185, -1)
    alpha = np.zeros_like(part)
    alpha[BODY[0] - 4:BODY[1] + 5, BODY[0] - 4:BODY[1] + 5] = 255
    return part, alpha


def draw_scene(draw, part, alpha, size=(640, 480), grid=(ROWS, COLUMNS)):
    """The board (`size`: width, height) with a grid (rows, columns) of copies, and each copy's
    template px -> image px affine (2 x 3). The default board and grid are the 640 x 480 board with
    6 x 6 copies 104 x 78 px apart; another board spreads its grid evenly over the board."""
    rng = np.random.default_rng(draw)
    width, height = size
    rows, columns = grid
    board = np.full((height, width), 150, np.uint8)
    for _ in range(int(round(25 * width * height / (640 * 480)))):
        p = rng.integers(0, [width, height], size=2)
        q = p + rng.integers(-60, 60, size=2)
        cv2.line(board, (int(p[0]), int(p[1])), (int(q[0]), int(q[1])), int(rng.integers(60, 230)),
                 int(rng.integers(1, 3)))
    body_mask = np.zeros_like(part)
    body_mask[BODY[0]:BODY[1] + 1, BODY[0]:BODY[1] + 1] = 255
    truth = []
    centre = 0.5 * (SIDE - 1)
    default = (width, height, rows, columns) == (640, 480, ROWS, COLUMNS)
    for r in range(rows):
        for c in range(columns):
            x = (60 + c * 104 if default else (c + 0.5) * width / columns) + rng.uniform(-4, 4)
            y = (45 + r * 78 if default else (r + 0.5) * height / rows) + rng.uniform(-4, 4)
            scale = rng.uniform(52, 60) / (BODY[1] - BODY[0] + 1)
            m = cv2.getRotationMatrix2D((centre, centre), rng.uniform(0, 360), scale)
            m[:, 2] += [x - centre, y - centre]
            warped = cv2.warpAffine(part, m, (width, height), flags=cv2.INTER_AREA)
            inside = cv2.warpAffine(body_mask, m, (width, height)) > 127
            board[inside] = warped[inside]
            truth.append(m)
    noisy = cv2.GaussianBlur(board, (0, 0), 0.8) + rng.normal(0, 4, board.shape)
    return np.clip(noisy, 0, 255).astype(np.uint8), truth


def body_corners(affine):
    corners = np.array([[BODY[0], BODY[0], 1], [BODY[1], BODY[0], 1], [BODY[1], BODY[1], 1], [BODY[0], BODY[1], 1]],
                       float).T
    return (np.asarray(affine).reshape(2, 3) @ corners).T


def score(objects, truth):
    """(copies found, other reports, corner errors of the found ones)."""
    found, errors, other = set(), [], 0
    for o in objects:
        mapped = body_corners(o["prototype_to_image"])
        k = min(range(len(truth)), key=lambda i: np.linalg.norm(body_corners(truth[i]).mean(0) - mapped.mean(0)))
        e = float(np.mean(np.linalg.norm(body_corners(truth[k]) - mapped, axis=1)))
        if e <= RIGHT_WITHIN and k not in found:
            found.add(k)
            errors.append(e)
        else:
            other += 1
    return len(found), other, errors


def main():
    parser = still_photo_parser(__doc__, "repeated-parts", "1-2", "parameter file for amcr_offline (see above)")
    parser.add_argument("--draws", default="1-3")
    parser.add_argument("--board", default="640x480", help="the board's size, WIDTHxHEIGHT px (default 640x480)")
    parser.add_argument("--grid", default="%dx%d" % (ROWS, COLUMNS), help="ROWSxCOLUMNS copies (default 6x6)")
    args = parser.parse_args()
    try:
        size = tuple(int(v) for v in args.board.split("x"))
        grid = tuple(int(v) for v in args.grid.split("x"))
        if len(size) != 2 or len(grid) != 2 or min(size + grid) < 1:
            raise ValueError
    except ValueError:
        parser.error("--board wants WIDTHxHEIGHT and --grid ROWSxCOLUMNS, positive numbers: got %r and %r"
                     % (args.board, args.grid))

    prototypes = os.path.join(args.out, "prototypes")
    os.makedirs(prototypes, exist_ok=True)
    part, alpha = draw_part()
    cv2.imwrite(os.path.join(prototypes, "part.png"), cv2.merge([part, part, part, alpha]))
    config = args.config
    if not config:
        config = os.path.join(args.out, "config.yaml")
        # A board larger than the default working resolution is read at its own size, so that the
        # parts stay 52-60 px in the working image.
        changed = {"min_object_size:": "min_object_size: 40.0\n"}
        if max(size) > 640:
            changed["working_resolution:"] = "working_resolution: %d\n" % max(size)
        with open(os.path.join(HERE, "..", "config", "amcr.yaml")) as f:
            lines = [next((v for k, v in changed.items() if line.startswith(k)), line) for line in f]
        with open(config, "w") as f:
            f.writelines(lines)

    summary = []
    print("%d copies of a drawn part per draw on a %d x %d board, %d frames, config %s"
          % (grid[0] * grid[1], size[0], size[1], args.frames, config))
    for draw in parse_seeds(args.draws):
        image, truth = draw_scene(draw, part, alpha, size, grid)
        photo = os.path.join(args.out, "draw-%d.png" % draw)
        cv2.imwrite(photo, image)
        for seed in parse_seeds(args.seeds):
            output = os.path.join(args.out, "draw-%d-seed-%d.jsonl" % (draw, seed))
            frames = run_still(args.bin, prototypes, photo, args.frames, seed, output, config)
            found, other, errors = score(frames[-1]["objects"], truth)
            by_frame = [score(frames[k]["objects"], truth)[0] for k in range(9, len(frames), 10)]
            row = {"draw": draw, "seed": seed, "found": found, "other": other,
                   "median_corner_error_px": float(np.median(errors)) if errors else None, "found_by_frame": by_frame}
            summary.append(row)
            print("draw %d seed %d: %d of %d found (median %s px), %d other reports; by frames 10, 20, ...: %s"
                  % (draw, seed, found, len(truth), "%.2f" % row["median_corner_error_px"] if errors else "-", other,
                     by_frame))
    with open(os.path.join(args.out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
