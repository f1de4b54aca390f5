#include "amcr/filter/particles.h"

#include <algorithm>
#include <cmath>

namespace amcr
{
void scanFeatureRays(const RadialScanner& scanner, float x, float y, float theta, RayHit hits[kFeatureRays])
{
  for (int k = 0; k < kFeatureRays; ++k)
    hits[k] = scanner.scanAngle(x, y, theta + k * kFeatureBinStep * kBinAngle);
}

RaySignature raySignature(const RayHit hits[kFeatureRays])
{
  RaySignature rays;
  for (int k = 0; k < kFeatureRays; ++k)
    rays.distance[k] = hits[k].valid ? std::max(hits[k].distance, 1e-3f) : 0.f;
  return rays;
}

RaySignature unsquashedFeatureRays(const RadialScanner& scanner, float x, float y, float theta, const float shape[3])
{
  const float a = shape[0], b = shape[1], c = shape[2];  // P; its inverse is (c, -b; -b, a) (det 1)
  const float hx = std::cos(theta), hy = std::sin(theta);
  const float u0 = std::atan2(b * hx + c * hy, a * hx + b * hy);
  RaySignature rays;
  for (int k = 0; k < kFeatureRays; ++k)
  {
    const float angle = u0 + static_cast<float>(k * kFeatureBinStep * kBinAngle);
    const float ux = std::cos(angle), uy = std::sin(angle);
    const float dx = c * ux - b * uy, dy = -b * ux + a * uy;  // P^-1 u_k
    const float length = std::hypot(dx, dy);
    const RayHit hit = scanner.scanAngle(x, y, std::atan2(dy, dx));
    rays.distance[k] = hit.valid ? std::max(hit.distance / length, 1e-3f) : 0.f;
  }
  return rays;
}

int RaySignature::valid_rays() const
{
  int n = 0;
  for (float d : distance)
    n += d > 0.f ? 1 : 0;
  return n;
}

void MParticleSet::resize(std::size_t n)
{
  x.resize(n);
  y.resize(n);
  theta.resize(n);
  prototype.resize(n);
  for (auto& a : affine)
    a.resize(n);
  affine_valid.resize(n);
  for (auto& s : shape)
    s.resize(n, 0.f);
  log_likelihood.resize(n);
  log_proposal.resize(n, 0.f);
}

void MParticleSet::copy(std::size_t from, std::size_t to) { copyFrom(*this, from, to); }

void MParticleSet::copyFrom(const MParticleSet& source, std::size_t from, std::size_t to)
{
  x[to] = source.x[from];
  y[to] = source.y[from];
  theta[to] = source.theta[from];
  prototype[to] = source.prototype[from];
  for (int k = 0; k < 6; ++k)
    affine[k][to] = source.affine[k][from];
  affine_valid[to] = source.affine_valid[from];
  for (int k = 0; k < 3; ++k)
    shape[k][to] = source.shape[k][from];
  log_likelihood[to] = source.log_likelihood[from];
  log_proposal[to] = source.log_proposal[from];
}
void MParticleSet::copyRange(const MParticleSet& source, std::size_t begin, std::size_t end)
{
  const auto range = [&](const auto& from, auto& to) {
    std::copy(from.begin() + begin, from.begin() + end, to.begin() + begin);
  };
  range(source.x, x);
  range(source.y, y);
  range(source.theta, theta);
  range(source.prototype, prototype);
  for (int k = 0; k < 6; ++k)
    range(source.affine[k], affine[k]);
  range(source.affine_valid, affine_valid);
  for (int k = 0; k < 3; ++k)
    range(source.shape[k], shape[k]);
  range(source.log_likelihood, log_likelihood);
  range(source.log_proposal, log_proposal);
}
}  // namespace amcr
