// The warnings a loader, an index or a recognizer reports through its
// sink, collected for the tests.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace amcr_test
{
struct WarningLines
{
  std::vector<std::string> lines;

  std::function<void(const std::string&)> sink()
  {
    return [this](const std::string& line) { lines.push_back(line); };
  }

  /// Whether one line holds `a` and `b` ("" matches any line).
  bool mention(const std::string& a, const std::string& b = "") const
  {
    for (const auto& l : lines)
      if (l.find(a) != std::string::npos && l.find(b) != std::string::npos)
        return true;
    return false;
  }

  /// Every line, for a failure message.
  std::string all() const
  {
    std::string s;
    for (const auto& l : lines)
      s += "\n  " + l;
    return s.empty() ? " (none)" : s;
  }
};
}  // namespace amcr_test
