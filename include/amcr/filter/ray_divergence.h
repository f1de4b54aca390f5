// How much an observation tells two hypotheses apart (eqs. 5-6): the
// divergence of one ray's distance, or of a V-particle's eight feature rays,
// from what a hypothesis predicts. Read by discriminative attention (where to
// look next, discriminative_attention.h) and by the memory's look-alike places
// (discriminative_places.h).
#pragma once

#include "amcr/filter/observation_model.h"
#include "amcr/filter/particles.h"

namespace amcr
{
/// The log-likelihood (nats, >= 0) one ray loses against the hypothesis
/// that predicts distance `b` (px; 0: no edge) when the image shows `a`:
/// log p(0) - log p(a - b) under eq. 5 when both have an edge, log p(0) -
/// log p_invalid (eq. 6) when only one has, 0 when neither has.
double rayDivergence(float a, float b, const ObservationModel& observation);

/// The expected log-likelihood ratio (nats, >= 0) of an observation `a`
/// against the hypothesis that predicts `b`: rayDivergence summed over the
/// rays.
double scanDivergence(const RaySignature& a, const RaySignature& b, const ObservationModel& observation);
}  // namespace amcr
