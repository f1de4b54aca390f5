// Throttling per distinct problem: a stream of bad images reports each kind of
// problem (an encoding, a zero-size image, ...) at most once per period,
// without one kind hiding another as a per-call-site throttle would.
#pragma once

#include <map>
#include <string>

#include <ros/time.h>

namespace amcr_ros
{
class ReportThrottle
{
public:
  explicit ReportThrottle(double period_s) : period_(period_s) {}

  /// True when `key` was not reported within the period (and records it now).
  bool shouldReport(const std::string& key)
  {
    const ros::WallTime now = ros::WallTime::now();
    auto it = last_.find(key);
    if (it != last_.end() && (now - it->second).toSec() < period_)
      return false;
    if (last_.size() > 256)  // unbounded keys (sizes in the text) must not grow memory
      last_.clear();
    last_[key] = now;
    return true;
  }

private:
  double period_;
  std::map<std::string, ros::WallTime> last_;
};
}  // namespace amcr_ros
