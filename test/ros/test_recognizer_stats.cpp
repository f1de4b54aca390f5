// The nodelet's /diagnostics status (src/ros/recognizer_stats.cpp): each
// filter figure under its own name, and a warning when objects were found
// but not reported because max_objects tracks were kept.
#include <string>

#include <gtest/gtest.h>

#include "recognizer_stats.h"

namespace
{
/// The value of the status entry `key`, or "(missing)".
std::string valueOf(const diagnostic_updater::DiagnosticStatusWrapper& status, const std::string& key)
{
  for (const auto& entry : status.values)
    if (entry.key == key)
      return entry.value;
  return "(missing)";
}

amcr_ros::RecognizerStats::FilterState state(int over_limit)
{
  amcr_ros::RecognizerStats::FilterState s;
  s.converged_v_particles = 7;
  s.num_v_particles = 60;
  s.flow_failures = 2;
  s.mean_m_particles = 123.0;
  s.budget_ms = 40.0;
  s.objects_over_limit = over_limit;
  s.max_objects = 16;
  return s;
}

/// Stats with one image received and processed, its filter in `s`.
void process(amcr_ros::RecognizerStats& stats, const amcr_ros::RecognizerStats::FilterState& s, std::uint32_t seq)
{
  stats.received(seq);
  amcr::Recognitions out;
  out.processing_ms = 12.0;
  stats.processed(out, s);
}

TEST(RecognizerStats, EachFilterFigureUnderItsName)
{
  amcr_ros::RecognizerStats stats;
  stats.setPrototypes(3, "");
  process(stats, state(0), 1);
  diagnostic_updater::DiagnosticStatusWrapper status;
  stats.report(status);
  EXPECT_EQ(status.level, diagnostic_msgs::DiagnosticStatus::OK) << status.message;
  EXPECT_EQ(valueOf(status, "M-particles per V-particle (mean)"), "123");
  EXPECT_DOUBLE_EQ(std::stod(valueOf(status, "frame budget (ms)")), 40.0);
  EXPECT_EQ(valueOf(status, "converged V-particles"), "7 of 60");
  EXPECT_EQ(valueOf(status, "V-particles re-seeded by failed flows"), "2");
  EXPECT_EQ(valueOf(status, "objects not reported over max_objects"), "0");
}

TEST(RecognizerStats, ObjectsOverMaxObjectsWarnUntilNoneMoreAreFound)
{
  amcr_ros::RecognizerStats stats;
  stats.setPrototypes(3, "");
  process(stats, state(4), 1);
  diagnostic_updater::DiagnosticStatusWrapper first;
  stats.report(first);
  EXPECT_EQ(first.level, diagnostic_msgs::DiagnosticStatus::WARN);
  EXPECT_NE(first.message.find("max_objects (16)"), std::string::npos) << first.message;
  EXPECT_EQ(valueOf(first, "objects not reported over max_objects"), "4");

  // None more since the last report: the status is OK again, the count stays.
  process(stats, state(0), 2);
  diagnostic_updater::DiagnosticStatusWrapper second;
  stats.report(second);
  EXPECT_EQ(second.level, diagnostic_msgs::DiagnosticStatus::OK) << second.message;
  EXPECT_EQ(valueOf(second, "objects not reported over max_objects"), "4");
}
}  // namespace
