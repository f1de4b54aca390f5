// A proposal for the heading of a newly seeded M-particle. The paper seeds
// M-particles uniformly; here, at the seeded pixel, the heading is the
// direction bin whose 8 table scans best match the V-particle's own scans up
// to a common scale (log distances), so a seed starts aligned with what its
// V-particle sees. It is an importance-sampling proposal: the weights that
// follow are still the likelihood of paper eq. 6.
#pragma once

#include "amcr/particles.h"
#include "amcr/prototype.h"

namespace amcr
{
/// The direction bin at table pixel (x, y) of `prototype` whose feature rays
/// best match `signature` up to scale; -1 when the signature has fewer than
/// 3 valid rays (nothing to match: choose at random).
int bestHeadingBin(const Prototype& prototype, int x, int y, const RaySignature& signature);
}  // namespace amcr
