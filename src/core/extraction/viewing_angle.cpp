#include "amcr/extraction/viewing_angle.h"

#include <cmath>
#include <limits>
#include <sstream>

#include "amcr/base/errors.h"

namespace amcr
{
double affineAnisotropy(const Affine& a)
{
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(a(r, c)))
        throw InputError("affineAnisotropy: the affine has a non-finite entry");
  double smallest = 0.0, largest = 0.0;
  affineScales(a, smallest, largest);
  if (!(smallest > 0.0))
    return std::numeric_limits<double>::infinity();
  return largest / smallest;
}

double viewingAngleDegrees(double anisotropy)
{
  if (std::isnan(anisotropy) || anisotropy < 1.0)
  {
    std::ostringstream out;
    out << "viewingAngleDegrees: the anisotropy must be >= 1, got " << anisotropy;
    throw InputError(out.str());
  }
  return std::acos(1.0 / anisotropy) * 180.0 / M_PI;
}
}  // namespace amcr
