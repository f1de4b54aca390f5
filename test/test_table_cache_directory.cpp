// Where the table cache lives: under ROS_HOME, else HOME, by default; an absolute path or "none"
// from the parameter file; a relative path is a parameter error.
#include <cstdlib>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "amcr/base/errors.h"
#include "amcr/base/params.h"
#include "amcr/io/params_file.h"
#include "amcr/memory/table_cache.h"
#include "scene_drawing.h"

namespace
{
/// Sets an environment variable for one scope, then restores it.
class ScopedVariable
{
public:
  ScopedVariable(const char* name, const char* value) : name_(name)
  {
    const char* old = std::getenv(name);
    had_ = old != nullptr;
    old_ = old ? old : "";
    if (value)
      ::setenv(name, value, 1);
    else
      ::unsetenv(name);
  }
  ~ScopedVariable()
  {
    if (had_)
      ::setenv(name_, old_.c_str(), 1);
    else
      ::unsetenv(name_);
  }

private:
  const char* name_;
  bool had_;
  std::string old_;
};

TEST(TableCacheDirectory, DefaultFollowsRosHomeThenHome)
{
  ScopedVariable home("HOME", "/home/someone");
  {
    ScopedVariable ros_home("ROS_HOME", "/var/ros");
    EXPECT_EQ(amcr::tableCacheDirectory(""), "/var/ros/amcr/tables");
  }
  {
    ScopedVariable ros_home("ROS_HOME", nullptr);
    EXPECT_EQ(amcr::tableCacheDirectory(""), "/home/someone/.ros/amcr/tables");
    EXPECT_EQ(amcr::tableCacheDirectory("~/tables"), "/home/someone/tables");
    EXPECT_EQ(amcr::tableCacheDirectory("/data/tables"), "/data/tables");
    EXPECT_EQ(amcr::tableCacheDirectory("none"), "");
    ScopedVariable no_home("HOME", nullptr);
    std::string why;
    EXPECT_EQ(amcr::tableCacheDirectory("", &why), "");
    EXPECT_NE(why.find("ROS_HOME"), std::string::npos) << why;
  }
}

TEST(TableCacheDirectory, ReadFromTheParameterFile)
{
  amcr_test::TempDir dir;
  std::ofstream(dir.file("p.yaml")) << "%YAML:1.0\n---\ntable_cache_dir: \"none\"\n";
  EXPECT_EQ(amcr::loadParams(dir.file("p.yaml")).table_cache_dir, "none");
  std::ofstream(dir.file("q.yaml")) << "%YAML:1.0\n---\ntable_cache_dir: \"tables\"\n";
  EXPECT_THROW(amcr::loadParams(dir.file("q.yaml")), amcr::ParameterError);
  EXPECT_EQ(amcr::loadParams(AMCR_SOURCE_DIR "/config/amcr.yaml").table_cache_dir, "");
}

TEST(TableCacheDirectory, RelativePathIsAParameterError)
{
  amcr::Params p;
  EXPECT_THROW(amcr::setParameter(p, "table_cache_dir", "tables"), amcr::ParameterError);
  p.table_cache_dir = "cache/tables";
  EXPECT_THROW(p.validate(), amcr::ParameterError);
  amcr::setParameter(p, "table_cache_dir", "none");
  EXPECT_EQ(p.table_cache_dir, "none");
  EXPECT_NO_THROW(p.validate());
}
}  // namespace
