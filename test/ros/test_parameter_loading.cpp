// Parameters from the ROS parameter server (amcr_ros::loadParams) against the
// rostest master: ~seed as a string carries every 64-bit seed, which an
// XML-RPC integer cannot; malformed seeds and a number where a word is
// expected are refused naming the parameter; a reconfiguration keeps a
// 64-bit seed whole.
#include <cstdint>
#include <limits>
#include <string>

#include <gtest/gtest.h>
#include <ros/ros.h>

#include "amcr/base/errors.h"
#include "parameter_loading.h"
#include "reconfigure.h"

namespace
{
/// A private namespace of its own per test, emptied afterwards.
class ParameterLoadingTest : public ::testing::Test
{
protected:
  void TearDown() override { nh_.deleteParam(""); }

  std::string errorOf() const
  {
    try
    {
      amcr_ros::loadParams(nh_);
    }
    catch (const amcr::ParameterError& e)
    {
      return e.what();
    }
    return "";
  }

  ros::NodeHandle nh_{"~" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name())};
};

TEST_F(ParameterLoadingTest, ASeedAsAStringIsReadWhole)
{
  nh_.setParam("seed", std::string("18446744073709551615"));
  EXPECT_EQ(amcr_ros::loadParams(nh_).seed, std::numeric_limits<std::uint64_t>::max());
  nh_.setParam("seed", std::string("9007199254740993"));  // 2^53 + 1: no double holds it
  EXPECT_EQ(amcr_ros::loadParams(nh_).seed, 9007199254740993ULL);
  nh_.setParam("seed", 42);
  EXPECT_EQ(amcr_ros::loadParams(nh_).seed, 42u);
}

TEST_F(ParameterLoadingTest, AMalformedSeedIsRefusedNamingIt)
{
  for (const std::string text : {"12a", "-1", "", " 7", "18446744073709551616", "1e9"})
  {
    nh_.setParam("seed", text);
    const std::string error = errorOf();
    EXPECT_NE(error.find("~seed '" + text + "' must be a whole number in [0, 18446744073709551615]"), std::string::npos)
        << "'" << text << "': " << error;
  }
  nh_.setParam("seed", true);
  EXPECT_EQ(amcr_ros::loadParams(nh_).seed, 1u) << "a bool is read as 0 or 1, as for every number";
}

TEST_F(ParameterLoadingTest, ANumberWhereAWordIsExpectedIsRefused)
{
  nh_.setParam("likelihood_form", 5);
  EXPECT_NE(errorOf().find("~likelihood_form must be a string"), std::string::npos) << errorOf();
}

TEST_F(ParameterLoadingTest, AReconfigurationKeepsA64BitSeedWhole)
{
  nh_.setParam("seed", std::string("12345678901234567890"));
  const amcr::Params params = amcr_ros::loadParams(nh_);
  amcr::AMCRConfig config = amcr_ros::toConfig(params);
  EXPECT_EQ(config.seed, std::numeric_limits<int>::max());
  config.num_v_particles = 40;  // another parameter changes
  const amcr::Params changed = amcr_ros::fromConfig(config, params);
  EXPECT_EQ(changed.seed, 12345678901234567890ULL);
  EXPECT_EQ(changed.num_v_particles, 40);
  config.seed = 5;  // the seed itself changes
  EXPECT_EQ(amcr_ros::fromConfig(config, params).seed, 5u);
}
}  // namespace

int main(int argc, char** argv)
{
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "parameter_loading_tester");
  return RUN_ALL_TESTS();
}
