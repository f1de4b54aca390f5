// The generic rostest tester (recognizer_tester.cpp): ~overlay while someone subscribes, and
// /diagnostics.
#include <string>

#include "recognizer_test.h"

namespace recognizer_tester
{
// ~overlay is drawn while someone subscribes: bgr8, the input's header, and
// wider than the input (the prototype column).
TEST_F(RecognizerTest, OverlayWhileSubscribed)
{
  ensurePrototypes();
  ASSERT_TRUE(waitForNodeletSubscription());
  Inbox<sensor_msgs::Image> overlay;
  overlay.subscribe(*nh_, node_ + "/overlay", 5);
  ASSERT_TRUE(waitUntil([&] { return overlay.publishers() > 0; }, timeout_));
  // The nodelet learns of the subscriber a moment after we learn of it: a few frames at most.
  sensor_msgs::ImageConstPtr got;
  for (int i = 0; i < 50 && !got; ++i)
  {
    const ros::Time stamp = nextStamp();
    ASSERT_TRUE(publishAndWait(frame(sceneFrame(), enc::MONO8, stamp)));
    got = overlay.waitFor([stamp](const sensor_msgs::Image& m) { return m.header.stamp == stamp; }, 0.5);
  }
  ASSERT_TRUE(got) << "no overlay while subscribed";
  EXPECT_EQ(got->encoding, enc::BGR8);
  EXPECT_GT(static_cast<int>(got->width), scene_.size.width);
  EXPECT_GE(static_cast<int>(got->height), scene_.size.height);
  EXPECT_EQ(got->header.frame_id, "camera");
  overlay.shutdown();
}

// /diagnostics reports the stream and the filter; overlays are drawn only
// while someone subscribes to ~overlay (the counter stands still without).
TEST_F(RecognizerTest, DiagnosticsAndNoOverlayWithoutSubscribers)
{
  ensurePrototypes();
  ASSERT_TRUE(waitForNodeletSubscription());
  ASSERT_TRUE(publishAndWait(frame(sceneFrame(), enc::MONO8, nextStamp())));
  diagnostics_.clear();
  auto idle = diagnostics_.waitFor(
      [](const diagnostic_msgs::DiagnosticArray& a) {
        return diagnosticNumber(a, "overlay subscribers") == 0 && diagnosticNumber(a, "frames processed") > 0;
      },
      timeout_);
  ASSERT_TRUE(idle) << "no diagnostics of the recognizer without overlay subscribers";
  const long processed = diagnosticNumber(*idle, "frames processed");
  const long overlays = diagnosticNumber(*idle, "overlays drawn");
  EXPECT_GT(overlays, 0) << "OverlayWhileSubscribed (run before) drew none";
  EXPECT_EQ(diagnosticNumber(*idle, "prototypes"), 3);
  EXPECT_TRUE(diagnosticValue(*idle, "Actual frequency (Hz)", "input images"))
      << "no FrequencyStatus of the input images";
  bool delay = false;  // TimeStampStatus's keys ("Earliest timestamp delay", ...) end in ':' in some releases
  for (const auto& status : idle->status)
    if (status.name.find("input images") != std::string::npos)
      for (const auto& kv : status.values)
        delay = delay || kv.key.find("timestamp delay") != std::string::npos;
  EXPECT_TRUE(delay) << "no TimeStampStatus of the input images";
  EXPECT_TRUE(diagnosticValue(*idle, "processing time, mean (ms)"));
  EXPECT_TRUE(diagnosticValue(*idle, "converged V-particles"));
  EXPECT_TRUE(diagnosticValue(*idle, "leading hypotheses"));

  constexpr int kFrames = 5;
  for (int i = 0; i < kFrames; ++i)
    ASSERT_TRUE(publishAndWait(frame(sceneFrame(), enc::MONO8, nextStamp())));
  auto later = diagnostics_.waitFor(
      [&](const diagnostic_msgs::DiagnosticArray& a) { return diagnosticNumber(a, "frames processed") >= processed + kFrames; },
      timeout_);
  ASSERT_TRUE(later) << "frames processed did not grow in /diagnostics";
  EXPECT_EQ(diagnosticNumber(*later, "overlays drawn"), overlays) << "overlays drawn while nobody subscribed";
}
}  // namespace recognizer_tester
