// The inner parts of a prototype's outline (the outlines of its holes: a
// printed target's disc and dots) fitted on the image each on its own: a
// user who draws a prototype from a target measured with a ruler gets its
// holes' places and sizes a few percent off, and the affine of the whole
// outline cannot put them on their edges. Each part may move and scale about
// its centre by a bounded amount before the score counts its points.
#pragma once

#include <vector>

#include "amcr/extraction/outline_edges.h"
#include "amcr/scan/radial_scan.h"

namespace amcr
{
/// The runs of `mapped` that are closed contours of the prototype: each
/// [begin, end) of consecutive points whose table positions lie within
/// 2.5 outline spacings of each other (the outline is stored contour by
/// contour).
std::vector<std::pair<std::size_t, std::size_t>> outlineParts(const std::vector<MappedPoint>& mapped);

/// Moves each inner part of `mapped` (every contour but the one with the
/// most points) onto the image's edges, in place: the translation and the scale
/// about the part's centre that put its points on the nearest edges of the
/// outline's majority polarity (least squares along the normals, 3 passes
/// with the search shrinking from `max_shift` + `tolerance` to `tolerance`),
/// no point moved by more than `max_shift` px. A part with fewer than 6
/// points, or with fewer than half of them on edges, stays where it is.
/// `max_shift` <= 0 leaves `mapped` unchanged.
void fitPartsOnEdges(const RadialScanner& scanner, std::vector<MappedPoint>& mapped, double max_shift,
                     double tolerance);

/// The largest distance a part may move for an object of the mapped
/// outline: `share` of the longer side of its image bounding box.
double partShiftLimit(const std::vector<MappedPoint>& mapped, double share);

/// fitPartsOnEdges with the bound `share` of the object's size
/// (partShiftLimit): what the score and the rival check count. A grey
/// template's edges stay where the photo has them (a template is cut from
/// the object itself, not drawn from measures): `mapped` is left unchanged.
inline void fitPartsWithinShare(const Prototype& prototype, const RadialScanner& scanner,
                                std::vector<MappedPoint>& mapped, double share, double tolerance)
{
  if (!prototype.isTemplate())
    fitPartsOnEdges(scanner, mapped, partShiftLimit(mapped, share), tolerance);
}
}  // namespace amcr
