// A read-only picture of the particle filter after a step, for overlays and
// diagnostics: what the paper's figures show (V-particles in the input,
// M-particles in the prototypes), by value, with nothing that reaches into
// the recognizer. Recognizer::view() makes it.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

namespace amcr
{
/// Where the optical flow of the last step took a V-particle from.
struct FlowTrail
{
  bool valid = false;  ///< false: no flow moved it (no flow, seeded afresh, or lost)
  cv::Point2f from;    ///< input px in the previous frame
};

/// One of the clusters a V-particle is deciding between (discriminative_attention.h).
struct CompetingView
{
  int prototype = -1;
  cv::Matx23d table_to_input;  ///< its affine, prototype table px -> input px
  float share = 0.f;           ///< of the V-particle's M-particles
};

struct VParticleView
{
  cv::Point2f position;  ///< input px
  float theta = 0.f;     ///< heading, rad
  /// The prototype of its dominant M-cluster when that cluster is converged
  /// (VParticleCluster::converged, as the result extraction decides), else -1.
  int dominant_prototype = -1;
  FlowTrail trail;
  /// Whether its last move was chosen to decide between `competing` (else
  /// the exploration policy chose it); `competing` is empty when fewer than
  /// two clusters compete.
  bool discriminating = false;
  std::vector<CompetingView> competing;
};

/// An M-particle as drawn in its prototype's panel.
struct MParticleDot
{
  cv::Point2f table;  ///< table px of its prototype
  int v = -1;         ///< index of its V-particle in FilterView::v
};

struct FilterView
{
  std::vector<VParticleView> v;
  /// The M-particles of each prototype (index = prototype), V-particle by V-particle.
  std::vector<std::vector<MParticleDot>> m_by_prototype;
};
}  // namespace amcr
