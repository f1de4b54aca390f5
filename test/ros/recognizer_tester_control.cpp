// The generic rostest tester (recognizer_tester.cpp): ~reset, dynamic_reconfigure, and bad inputs
// that leave the nodelet answering.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <dynamic_reconfigure/Reconfigure.h>
#include <opencv2/imgproc.hpp>
#include <std_srvs/Trigger.h>

#include "reconfigure_request.h"

#include "recognizer_test.h"

namespace recognizer_tester
{
// ~reset restarts the filter: the next frame is iteration 1.
TEST_F(RecognizerTest, ResetRestartsTheFilter)
{
  ensurePrototypes();
  ASSERT_TRUE(waitForNodeletSubscription());
  auto before = publishAndWait(frame(sceneFrame(), enc::MONO8, nextStamp()));
  ASSERT_TRUE(before);
  ASSERT_GT(before->iteration, 1);
  std_srvs::Trigger trigger;
  ASSERT_TRUE(ros::service::call(node_ + "/reset", trigger));
  EXPECT_TRUE(trigger.response.success);
  EXPECT_NE(trigger.response.message.find("reset"), std::string::npos) << trigger.response.message;
  auto after = publishAndWait(frame(sceneFrame(), enc::MONO8, nextStamp()));
  ASSERT_TRUE(after);
  EXPECT_EQ(after->iteration, 1);
}

// dynamic_reconfigure: a new particle count rebuilds the filter (iteration 1,
// the new count in /diagnostics); a new table size rebuilds the prototype
// tables; the subscription stays and recognitions keep coming.
TEST_F(RecognizerTest, ReconfigureRebuildsTheFilter)
{
  ensurePrototypes();
  ASSERT_TRUE(waitForNodeletSubscription());
  ASSERT_TRUE(ros::service::waitForService(node_ + "/set_parameters", ros::Duration(timeout_)));
  dynamic_reconfigure::Reconfigure srv = amcr_test::intParameterRequest("num_v_particles", 40);
  ASSERT_TRUE(ros::service::call(node_ + "/set_parameters", srv));
  bool echoed = false;
  for (const auto& p : srv.response.config.ints)
    echoed = echoed || (p.name == "num_v_particles" && p.value == 40);
  EXPECT_TRUE(echoed) << "the answer does not carry num_v_particles = 40";

  auto first = publishAndWait(frame(sceneFrame(), enc::MONO8, nextStamp()));
  ASSERT_TRUE(first) << "no recognitions after reconfiguring";
  EXPECT_EQ(first->iteration, 1);
  diagnostics_.clear();
  auto report = diagnostics_.waitFor(
      [](const diagnostic_msgs::DiagnosticArray& a) {
        const std::string* v = diagnosticValue(a, "converged V-particles");
        return v && v->find("of 40") != std::string::npos;
      },
      timeout_);
  EXPECT_TRUE(report) << "/diagnostics does not show 40 V-particles";

  dynamic_reconfigure::Reconfigure tables = amcr_test::intParameterRequest("prototype_size", 96);
  ASSERT_TRUE(ros::service::call(node_ + "/set_parameters", tables));
  EXPECT_TRUE(waitForLog(rosgraph_msgs::Log::INFO, "prototype tables and filter rebuilt"));
  auto after = publishAndWait(frame(sceneFrame(), enc::MONO8, nextStamp()));
  ASSERT_TRUE(after) << "no recognitions after rebuilding the tables";
  EXPECT_EQ(after->iteration, 1);
}

// Every bad input: the convertible ones are recognized, the others are
// refused with an error naming the problem; the nodelet keeps answering.
TEST_F(RecognizerTest, BadInputsLeaveTheNodeletAnswering)
{
  ensurePrototypes();
  ASSERT_TRUE(waitForNodeletSubscription());
  const cv::Mat grey = sceneFrame();
  cv::Mat bgr, bgra, yuv;
  cv::cvtColor(grey, bgr, cv::COLOR_GRAY2BGR);
  cv::cvtColor(grey, bgra, cv::COLOR_GRAY2BGRA);
  cv::Mat mono16;
  grey.convertTo(mono16, CV_16U, 257.0);
  // yuv422 (UYVY): U Y0 V Y1 per two pixels; grey: U = V = 128.
  yuv.create(grey.rows, grey.cols, CV_8UC2);
  for (int y = 0; y < grey.rows; ++y)
    for (int x = 0; x < grey.cols; ++x)
      yuv.at<cv::Vec2b>(y, x) = cv::Vec2b(128, grey.at<std::uint8_t>(y, x));

  // Converted: each gives recognitions.
  const std::vector<std::pair<std::string, cv::Mat>> converted = {
      {enc::MONO16, mono16}, {enc::BGRA8, bgra}, {enc::RGB8, bgr}, {enc::BAYER_RGGB8, grey}, {enc::YUV422, yuv}};
  for (const auto& c : converted)
    EXPECT_TRUE(publishAndWait(frame(c.second, c.first, nextStamp()))) << "no recognitions for a " << c.first
                                                                          << " image";

  // Refused: an error naming the problem, no crash.
  cv::Mat depth;
  grey.convertTo(depth, CV_32F, 1.0 / 255.0);
  image_pub_.publish(frame(depth, enc::TYPE_32FC1, nextStamp()));
  EXPECT_TRUE(waitForLog(rosgraph_msgs::Log::ERROR, "32FC1")) << "no error naming 32FC1";

  auto zero = boost::make_shared<sensor_msgs::Image>();
  zero->header.stamp = nextStamp();
  zero->encoding = enc::MONO8;
  image_pub_.publish(zero);
  EXPECT_TRUE(waitForLog(rosgraph_msgs::Log::ERROR, "zero-size")) << "no error about a zero-size image";

  auto short_data = frame(grey, enc::MONO8, nextStamp());
  short_data->data.resize(short_data->data.size() / 2);
  image_pub_.publish(short_data);
  EXPECT_TRUE(waitForLog(rosgraph_msgs::Log::ERROR, "inconsistent image")) << "no error about truncated data";

  // The resolution changes mid-stream: recognized at the new size, and back.
  cv::Mat small;
  cv::resize(grey, small, cv::Size(320, 240), 0, 0, cv::INTER_AREA);
  EXPECT_TRUE(publishAndWait(frame(small, enc::MONO8, nextStamp()))) << "no recognitions after a size change";
  EXPECT_TRUE(publishAndWait(frame(grey, enc::MONO8, nextStamp()))) << "no recognitions after the size came back";

  // Time goes backwards (a looped bag): reset and say so.
  auto back = publishAndWait(frame(grey, enc::MONO8, ros::Time(500.0)));
  ASSERT_TRUE(back) << "no recognitions after time went backwards";
  EXPECT_EQ(back->iteration, 1);
  EXPECT_TRUE(waitForLog(rosgraph_msgs::Log::WARN, "time went backwards"));

  // Still answering.
  std_srvs::Trigger trigger;
  EXPECT_TRUE(ros::service::call(node_ + "/reset", trigger));
  EXPECT_TRUE(publishAndWait(frame(grey, enc::MONO8, nextStamp())));
}
}  // namespace recognizer_tester
