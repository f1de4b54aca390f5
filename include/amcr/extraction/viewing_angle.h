// How obliquely a planar prototype is seen, reported with each object: the
// anisotropy of the prototype -> image affine and the viewing angle it
// implies under weak-perspective projection.
#pragma once

#include "amcr/base/affine.h"

namespace amcr
{
/// Ratio of the larger to the smaller singular value of the linear part of
/// `a`, >= 1 (1: no squash, as in a frontal view); +infinity when the linear
/// part is singular. Throws InputError when an entry is not finite.
double affineAnisotropy(const Affine& a);

/// The angle, degrees in [0, 90], between a planar target's normal and the
/// viewing direction that a squash of `anisotropy` implies under weak
/// perspective (a plane tilted by theta shrinks by cos(theta) across the tilt
/// axis): acos(1 / anisotropy); 90 for +infinity. An anisotropy of 2 is
/// 60 degrees, 3 is 70.5. Throws InputError below 1 or when NaN.
double viewingAngleDegrees(double anisotropy);
}  // namespace amcr
