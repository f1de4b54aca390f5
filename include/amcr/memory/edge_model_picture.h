// A prototype's model as a picture: what a user checks a grey template with
// (`amcr_offline --write-models`), and the edge points the score checks.
#pragma once

#include <opencv2/core.hpp>

#include "amcr/memory/prototype.h"

namespace amcr
{
/// The edge model of `prototype` as a picture in table px, `scale` times
/// larger: its scan image dimmed, the region where M-particles are seeded
/// outlined, and every edge point of the score with a short tick along its
/// normal (towards rising grey for a template, outwards for a silhouette).
cv::Mat drawEdgeModel(const Prototype& prototype, int scale = 3);
}  // namespace amcr
