#include "amcr/resource_bounds.h"

#include <cstdio>

#include "amcr/errors.h"
#include "amcr/prototype.h"
#include "amcr/ray_directions.h"

namespace amcr
{
std::int64_t maxTableBytesPerPrototype(int prototype_size)
{
  const std::int64_t side = prototype_size + 2LL * Prototype::tableMargin(prototype_size);
  return side * side * kDirectionBins;
}

void checkParticleBound(std::int64_t v_particles, std::int64_t m_per_v, const std::string& what)
{
  const std::int64_t total = v_particles * m_per_v;
  if (total <= kMaxMParticles)
    return;
  throw ParameterError(std::to_string(v_particles) + " V-particles x " + std::to_string(m_per_v) +
                       " M-particles each (" + what + ") = " + std::to_string(total) + " M-particles, " +
                       formatBytes(total * kBytesPerMParticle) + ": above the bound of " +
                       std::to_string(kMaxMParticles) + " M-particles (" +
                       formatBytes(kMaxMParticles * kBytesPerMParticle) + ")");
}

void checkImageBound(std::int64_t width, std::int64_t height, const std::string& what)
{
  if (width * height <= kMaxImagePixels)
    return;
  throw InputError(what + " is " + std::to_string(width) + " x " + std::to_string(height) + " = " +
                   std::to_string(width * height) + " pixels: above the bound of " + std::to_string(kMaxImagePixels) +
                   " pixels (7680 x 4320)");
}

std::string formatBytes(std::int64_t bytes)
{
  char text[64];
  if (bytes >= 1'000'000'000)
    std::snprintf(text, sizeof(text), "%.2f GB", bytes / 1e9);
  else
    std::snprintf(text, sizeof(text), "%.1f MB", bytes / 1e6);
  return text;
}
}  // namespace amcr
