// The turns of a prototype onto itself: the affine maps of its table under
// which its model (a silhouette's outline, a template's edges) nearly
// repeats. A square face with a ring of dots shifted a little off its centre
// is one: turned by a quarter, its outline is the same and its dots lie
// within a dot's radius of where they were. The filter's likelihood can
// hardly tell such poses apart, and a fit that starts at the wrong one stays
// there (its outline is on edges, its inner edges just off them, scoring a
// little below the decision threshold or a little above it), so the result
// extraction tries them on the fit of every new object that comes near the
// decision, and keeps the turn that verifies best (candidate_fit.cpp).
//
// A turn is taken about the model points' centre (a template's region may
// hold a crop's background, its edges are the object) in the table, where
// the prototype is seen frontally.
#pragma once

#include <vector>

#include "amcr/base/affine.h"
#include "amcr/memory/prototype.h"

namespace amcr
{
/// The turns tried: multiples of 60 and 90 degrees about the model's centre
/// (the symmetries of triangles, squares and hexagons).
constexpr int kTurnDegrees[] = {60, 90, 120, 180, 240, 270, 300};

/// Table -> table affine of `prototype` turned by `degrees` about its model
/// points' centre; false for a model of fewer than 3 points.
bool modelTurn(const Prototype& prototype, double degrees, Affine& turn);

/// The share of the prototype's model points that `turn` maps within
/// `tolerance` table px of a model point.
double modelRepeatShare(const Prototype& prototype, const Affine& turn, double tolerance);

/// The turns of kTurnDegrees under which at least `min_share` of the model
/// repeats within `tolerance_share` of the model's longer side (table ->
/// table affines, in kTurnDegrees' order).
std::vector<Affine> selfSimilarTurns(const Prototype& prototype, double tolerance_share = 0.03,
                                     double min_share = 0.45);
}  // namespace amcr
