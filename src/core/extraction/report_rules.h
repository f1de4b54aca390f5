// The rules a report keeps from frame to frame, shared by the extraction
// (object_extractor.cpp) and the tracks (track_registry.cpp): the hysteresis
// of a tracked object and when two outlines are one object.
#pragma once

namespace amcr
{
namespace extraction_steps
{
constexpr double kKeepTrackRatio = 0.65;  // a tracked object stays at this share of the decision threshold
constexpr int kRivalGraceFrames = 10;      // reports in a row a track may fail the rival check's hysteresis
constexpr double kLeadingScoreRatio = 0.5;  // a leading hypothesis scores at least this share of the threshold
// Outlines overlapping more are one object: the better is kept. Below a half
// (an elongated part found twice, slid along its axis, overlaps itself by a
// third); touching copies overlap by next to nothing.
constexpr double kSameObjectOverlap = 0.3;
}  // namespace extraction_steps
}  // namespace amcr
