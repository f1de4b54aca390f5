#include "amcr/base/resource_bounds.h"

#include <cstdio>

#include "amcr/base/errors.h"

namespace amcr
{
namespace
{
/// Whether a * b > bound for a, b >= 0, without computing a * b (which can
/// overflow: a PNG header may claim 2^32 - 1 pixels a side).
bool productExceeds(std::int64_t a, std::int64_t b, std::int64_t bound) { return a > 0 && b > bound / a; }
}  // namespace

void checkParticleBound(std::int64_t v_particles, std::int64_t m_per_v, const std::string& what)
{
  if (!productExceeds(v_particles, m_per_v, kMaxMParticles))
    return;
  const double total = static_cast<double>(v_particles) * static_cast<double>(m_per_v);
  throw ParameterError(std::to_string(v_particles) + " V-particles x " + std::to_string(m_per_v) +
                       " M-particles each (" + what + ") = " + formatCount(total) + " M-particles, " +
                       formatBytes(total * kBytesPerMParticle) + ": above the bound of " +
                       std::to_string(kMaxMParticles) + " M-particles (" +
                       formatBytes(kMaxMParticles * kBytesPerMParticle) + ")");
}

void checkImageBound(std::int64_t width, std::int64_t height, const std::string& what)
{
  if (width < 0 || height < 0)
    throw InputError(what + " has a negative size (" + std::to_string(width) + " x " + std::to_string(height) + ")");
  if (!productExceeds(width, height, kMaxImagePixels))
    return;
  throw InputError(what + " is " + std::to_string(width) + " x " + std::to_string(height) + " = " +
                   formatCount(static_cast<double>(width) * static_cast<double>(height)) +
                   " pixels: above the bound of " + std::to_string(kMaxImagePixels) + " pixels (7680 x 4320)");
}

std::string formatCount(double count)
{
  char text[64];
  std::snprintf(text, sizeof(text), "%.0f", count);
  return text;
}

std::string formatBytes(double bytes)
{
  char text[64];
  if (bytes >= 1'000'000'000)
    std::snprintf(text, sizeof(text), "%.2f GB", bytes / 1e9);
  else
    std::snprintf(text, sizeof(text), "%.1f MB", bytes / 1e6);
  return text;
}
}  // namespace amcr
