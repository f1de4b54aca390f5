// main() of every gtest binary: catkin_add_gtest links gtest but, depending
// on the catkin release, not always gtest_main.
#include <gtest/gtest.h>

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
