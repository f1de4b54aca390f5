"""The fixed text of the benchmark report's Methods and Suites sections: how each method is run, and
how the suites are rendered."""

SUITES_TEXT = """\
Rendered by `bench/make_sequences` (seeded; one generator per sequence): 640x480 grey frames, an
MPEG-7 silhouette printed dark on light (70%) or light on dark (30%) over a real photo from
opencv-doc (contrast-reduced, random crop), under a random affine (longer side 120-240 px, any
rotation, shear up to 0.3, anisotropic scale up to about 1.5:1) that drifts, spins 0.3-1.5
degrees per frame and breathes in scale and shear; 3-5 static distractor silhouettes of MPEG-7
classes not in memory (random polygons, ellipses and crosses in the 70-class suites, where every
class is in memory), 3-6 lines, a lighting gradient (10-35%), blur (sigma 0-1.2) and noise
(sigma 2-8). `paper`: 17 classes in memory (every 4th class in name order, instance 1), the same
instance shown; `mpeg7-70`: all 70 classes; `within-class`: memory instance 1 of all 70 classes,
another instance shown; `within-class-1330`: memory the 19 instances of each of the 70 classes
other than one held out per class (drawn once, whatever the seed), the held-out instance shown,
label the class; the `within-class` sequences (same seeds and draws: background, pose, motion,
clutter, noise) with the memory and the shown instance changed only; `within-class-85`: memory 5
of those 19 instances for each of the paper's 17 classes, the held-out instance of one of them
shown (seeds of its own; distractors of classes not in memory); `similar`: the 3 birds closest in Hu moments; `clutter-only`: the paper
memory, no memory shape in view; `two-objects`: two of the paper memory at once, in the two
halves of the frame. `oblique`: the `paper` sequences (same seeds, memory, clutter, motion) with
the target seen obliquely: squashed along an image axis (random per sequence) to anisotropy
1.5-3 (48-70 degrees off the normal), area kept, no shear. `faint`: the `paper` sequences (same
seeds) printed faint and out of focus: the contrast cut to a quarter about grey 128 after the
lighting, 2 px (sigma) of defocus added to the drawn blur, the noise as drawn. `memory-growth` (time
per frame as the memory grows): 6 sequences (2 with --quick) whose targets are 3 fixed classes, run
once per memory of 3, 17, 35 and 70 prototypes (nested: 3 of the paper's 17, the 17, the 17 and 18
other classes, all 70; fixed, whatever the seed); distractors are random blobs. `paper-hd` and
`clutter-only-hd` (the same scenes at a higher resolution): the `paper` and `clutter-only` frames
(same seeds, draws and noise) resampled 1.5x (bilinear) to 960x720 and centred in 1280x720, the 160
px left and right showing the photo mirrored (no shape); the truth is the 640x480 truth composed
with x' = 1.5 x + 160.25, y' = 1.5 y + 0.25, exact. `copies` (several instances in view): 4-6 copies
of one prototype of the paper memory (class drawn per sequence), each at its own pose (longer side
90-150 px, any rotation), none overlapping (3 px apart at least), moving together (drift, slow spin,
breathing scale) over the `paper` clutter. `real-photos` (several instances in a real photo):
opencv-doc's photo `pca_test1.jpg` (six alike dark parts on a backlit panel) under a synthetic
camera motion (drift, slow turn and zoom) with mild noise; memory: the part cut from the photo
(Otsu, the component of median area) and 16 of the paper memory; its truth affines are approximate
(from the parts' moments), their centres are the parts' centroids. The Hu-moments baseline's affine
comes from moments too, so its affine error there says how alike the two are, not how right.
Frames are numbered from 1.
"""

METHODS_TEXT = """\
Every method gets the same prototypes (the suite's `prototypes/` folder) and the same frames, one
core each (OpenCV threads off), and reports labels with a prototype->image affine per frame:
- **AMCR**: `config/amcr.yaml` as committed (60 V-particles, a budget of 1000 M-particles each shared by the prototypes, the proposal index, KLD-sampling),
  one recognizer per sequence, reset between sequences; what it reports (score >= the decision
  threshold) is taken as it is.
- **LINE-2D** (Hinterstoisser et al.; OpenCV contrib's `cv::linemod`, `getDefaultLINE()`: quantised
  gradient orientations over two pyramid levels, T = 5 and 8 px, 63 features): one template per
  prototype, size, rotation and stretch, each the prototype printed dark on light (orientations
  count modulo 180 degrees, so either print polarity matches) with its mask dilated 2 px: sizes over
  the suite's range in steps of at most 1.12x, rotations every 5 degrees, and the identity and 6
  stretches (area kept, along 6 axes over 180 degrees) at 2/3 of the suite's largest anisotropy in
  the logarithm (1.7 for the `paper` suites and `real-camera-cube`, 3.1 for `oblique` and
  `real-camera`): about 4,500
  templates per prototype, built once per memory (the set-up row). The rotation step, the stretches
  and the gradient threshold were chosen on `paper` seed 1, the threshold on seed 3. Each frame matched on its own at similarity >= 93% (chosen on seed 3 of `paper` and
  `clutter-only`, which no figure here scores), gradient threshold 60, non-maximum suppression
  between matches (centres within half the smaller size), at most 5 reports; the affine is the
  template's, so it carries the sampling steps' error. It runs on every 10th frame of every sequence
  (frames 10, 30, 60 and the last among them), each frame on its own: its figures at those frames are
  what it does on any frame.
- **Shape contexts** (Belongie, Malik and Puzicha, the paper's comparison;
  `cv::ShapeContextDistanceExtractor`): candidates are the closed contours of the frame binarised as
  for Hu moments, opened and closed with a 7 px disc (cuts crossing lines off), following Canny edges
  for 60% of their points, one per outline, the 12 largest in the suite's size range; each resampled
  to 50 points and compared with every prototype's outline from 8 starting turns (OpenCV's rotation
  invariant mode is not invariant), affine alignment, 3 iterations; a candidate goes to its nearest
  prototype, reported at a distance <= 0.1 (set on drawn scenes), the affine fitted (RANSAC, 3 px) to
  the extractor's last point matches, which are its correspondences. At 1.9 ms per comparison it
  takes seconds per frame, so it runs on every 60th frame (60 and the last) of every sequence.
- **ORB+RANSAC** (find_object_2d's method): prototypes rescaled to 200 px, described in both print
  polarities (400 ORB features each), all in one FLANN LSH index; 1500 ORB features per frame,
  ratio test 0.8 over the whole memory, RANSAC homography (5 px) per prototype, reported with at
  least 10 inliers; the affine is the least-squares fit of the homography at the prototype's corners
  and centre; the inliers are its correspondences. Stateless: each frame on its own.
- **Hu moments**: Otsu and adaptive (51 px, C 10) thresholds in both polarities, contours of
  800 px^2 to 40% of the frame, `cv::matchShapes` (I1) against each prototype's outer contour,
  reported when the distance is below 0.05 (each contour to its best prototype only); the affine
  from the moments (centroids, principal axes scaled by their spread, signs by third-order skew).
- **GHT Guil** (`cv::GeneralizedHoughGuil`): prototypes rescaled to 160 px, one detector per
  prototype and print polarity, full circle in 2-degree steps, scale 0.5-2.0 in steps of 0.05,
  vote thresholds 0.2/0.04/0.02 of the template's edge points (angle/scale/position, set by hand
  on clean rotated copies and one cluttered frame: lower ones take tens of seconds per prototype on
  clutter), reported with position votes of at least 0.03 of the edge points, ranked by votes per
  edge point; a similarity only (no shear, no anisotropic scale). It is slow on clutter, from
  0.3 s to minutes per prototype and polarity (one `paper` frame took 3 to 16 minutes with 17
  prototypes), so the full run gives it the last frame of every `similar` sequence (3 prototypes)
  and of one `paper` sequence only (the "frames run" row), and none of the other suites. It keeps
  no state from frame to frame, so a frame says what it does on any frame, but the sample is small:
  read its figures as indicative.
"""
