// A point of a prototype's model with its unit normal, in table
// coordinates: of a silhouette's outline (normal outwards) or of a grey
// template's edges (normal towards rising grey, edge_model.h).
#pragma once

#include <opencv2/core.hpp>

namespace amcr
{
/// A point of the prototype's outline with its outward unit normal, in
/// table coordinates.
struct OutlinePoint
{
  cv::Point2f position;
  cv::Point2f normal;
};
}  // namespace amcr
