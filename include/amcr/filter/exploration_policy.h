// The feedback policy F (paper 4.3): how a V-particle moves on its own.
#pragma once

#include "amcr/base/random.h"
#include "amcr/filter/motion_model.h"
#include "amcr/filter/particles.h"
#include "amcr/scan/radial_scan.h"

namespace amcr
{
/// Chooses the control of one V-particle from what it sees. decide() is
/// called for several V-particles at once, from num_threads threads (each
/// with the V-particle's own random stream): a policy that keeps state must
/// make it safe to share.
class ExplorationPolicy
{
public:
  virtual ~ExplorationPolicy() = default;
  virtual Control decide(const VParticle& v, const RadialScanner& scanner, Rng& rng) const = 0;
};

/// The paper's baseline: move forward, reflect at edges (and at the image
/// border), so the V-particle explores the region it is in.
class ReflectAtEdgesPolicy : public ExplorationPolicy
{
public:
  /// `step`: forward step, px; `jitter`: largest random turn added at a reflection, rad.
  ReflectAtEdgesPolicy(double step, double jitter);
  Control decide(const VParticle& v, const RadialScanner& scanner, Rng& rng) const override;

private:
  double step_;
  double jitter_;
};
}  // namespace amcr
