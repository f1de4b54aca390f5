// main() of every gtest binary: catkin_add_gtest links gtest but, depending
// on the catkin release, not always gtest_main.
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  // A ROS_HOME of this run's own, removed at the end: the table cache's
  // default place ($ROS_HOME/amcr/tables, table_cache.h) is never the
  // user's home, and no run reads the tables of another.
  std::string pattern = (std::filesystem::temp_directory_path() / "amcr_ros_home_XXXXXX").string();
  std::vector<char> buffer(pattern.begin(), pattern.end());
  buffer.push_back('\0');
  const bool own_home = mkdtemp(buffer.data()) != nullptr;
  if (own_home)
    setenv("ROS_HOME", buffer.data(), 1);
  const int result = RUN_ALL_TESTS();
  if (own_home)
  {
    std::error_code ignored;
    std::filesystem::remove_all(buffer.data(), ignored);
  }
  return result;
}
