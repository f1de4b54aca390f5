#pragma once

#include <map>
#include <memory>

#include "amcr/base/params.h"
#include "amcr/memory/prototype.h"
#include "scene_drawing.h"

namespace amcr_test
{
// Prototypes at the default size (128 px) and edge threshold, built once
// per test program: a table takes about half a second to build.
inline const amcr::Prototype& cachedPrototype(ShapeId shape)
{
  static std::map<ShapeId, std::unique_ptr<amcr::Prototype>> cache;
  std::unique_ptr<amcr::Prototype>& p = cache[shape];
  if (!p)
  {
    const amcr::Params defaults;
    p = std::make_unique<amcr::Prototype>(amcr_test::shapeName(shape), amcr_test::drawPrototype(shape),
                                          defaults.prototype_size, defaults.edge_threshold);
  }
  return *p;
}
}  // namespace amcr_test
