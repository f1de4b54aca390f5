// The generic rostest tester (recognizer_tester.cpp): a shape taught from a frame through ~teach,
// recognized, and removed through ~remove_prototype.
#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <amcr/RemovePrototype.h>
#include <amcr/TeachPrototype.h>

#include "recognizer_test.h"

namespace recognizer_tester
{
// ~teach: a flag (not in the memory) cut from a frame is added to the running
// filter and recognized in the next frames under another pose; bad requests
// are refused with the reason and change nothing; ~remove_prototype undoes it
// (the file saved on request stays).
TEST_F(RecognizerTest, TeachAShapeFromTheImageAndRemoveIt)
{
  if (!check_teach_)
    return;
  ensurePrototypes();
  ASSERT_TRUE(waitForNodeletSubscription());
  ASSERT_TRUE(ros::service::waitForService(node_ + "/teach", ros::Duration(timeout_)));
  auto current = prototypes_.waitFor([](const amcr::PrototypeTable& t) { return t.prototypes.size() == 3; }, timeout_);
  ASSERT_TRUE(current);
  const std::uint32_t version = current->version;

  // The flag alone over clutter (no lines: a line across it would join its outline to the region's border).
  amcr_test::Scene scene;
  scene.size = scene_.size;
  const amcr::Affine taught_at =
      amcr_test::makeAffine(amcr_test::prototypeCentre(), {300.0, 240.0}, 0.2, 1.0, 1.0, 0.0);
  scene.objects = {{ShapeId::kFlag, taught_at, 35.0}};
  scene.clutter.lines = 0;
  scene.clutter.seed = 21;
  ASSERT_TRUE(publishAndWait(frame(amcr_test::addNoise(amcr_test::renderClean(scene), 6.0, 2100), enc::MONO8,
                                   nextStamp())));
  std::vector<cv::Point2f> outline;
  for (const cv::Point2d& p : amcr_test::transformPoints(taught_at, amcr_test::shapePolygon(ShapeId::kFlag)))
    outline.emplace_back(p);
  const cv::Rect box = cv::boundingRect(outline);

  auto call = [](amcr::TeachPrototype& srv) { return ros::service::call(node_ + "/teach", srv); };
  auto request = [&](const std::string& label, int x, int y, int w, int h) {
    amcr::TeachPrototype srv;
    srv.request.label = label;
    srv.request.rectangle.x_offset = static_cast<std::uint32_t>(x);
    srv.request.rectangle.y_offset = static_cast<std::uint32_t>(y);
    srv.request.rectangle.width = static_cast<std::uint32_t>(w);
    srv.request.rectangle.height = static_cast<std::uint32_t>(h);
    return srv;
  };
  const int x = box.x - 12, y = box.y - 12, w = box.width + 24, h = box.height + 24;

  // Refused, nothing changes.
  const std::vector<std::pair<amcr::TeachPrototype, std::string>> bad = {
      {request("flag", 0, 0, 0, 0), "empty"},
      {request("flag", 5000, 5000, 40, 40), "outside"},
      {request(label_, x, y, w, h), "taken"},
      {request("bad/label", x, y, w, h), "character"},
  };
  for (auto b : bad)
  {
    ASSERT_TRUE(call(b.first));
    EXPECT_FALSE(b.first.response.success) << "'" << b.first.request.label << "' was taught";
    EXPECT_NE(b.first.response.message.find(b.second), std::string::npos)
        << "the answer does not say '" << b.second << "': " << b.first.response.message;
    EXPECT_EQ(b.first.response.table_version, version);
  }

  // Taught and saved.
  prototypes_.clear();
  amcr::TeachPrototype good = request("flag", x, y, w, h);
  good.request.save = true;
  ASSERT_TRUE(call(good));
  ASSERT_TRUE(good.response.success) << good.response.message;
  EXPECT_EQ(good.response.table_version, version + 1);
  EXPECT_EQ(good.response.prototype_id, 3);
  EXPECT_EQ(good.response.saved_path, dir_->file("flag.png"));
  EXPECT_FALSE(cv::imread(dir_->file("flag.png"), cv::IMREAD_GRAYSCALE).empty()) << "no saved silhouette";
  auto table = prototypes_.waitFor([&](const amcr::PrototypeTable& t) { return t.version == version + 1; }, timeout_);
  ASSERT_TRUE(table) << "no label table of version " << version + 1;
  ASSERT_EQ(table->prototypes.size(), 4u);
  EXPECT_EQ(table->prototypes[3].label, "flag");

  // Recognized under another pose, in the running filter (no restart).
  const amcr::Affine moved = amcr_test::makeAffine(amcr_test::prototypeCentre(), {360.0, 250.0}, -0.4, 0.85, 0.8, 0.1);
  scene.objects = {{ShapeId::kFlag, moved, 35.0}};
  const cv::Mat moved_clean = amcr_test::renderClean(scene);
  std::vector<cv::Point2f> truth;
  for (const cv::Point2d& p : amcr_test::transformPoints(moved, amcr_test::shapePolygon(ShapeId::kFlag)))
    truth.emplace_back(p);
  const cv::Rect2f truth_box = cv::boundingRect(truth);
  const cv::Point2f truth_centre(truth_box.x + 0.5f * truth_box.width, truth_box.y + 0.5f * truth_box.height);
  long first_iteration = -1;
  int frames = 0;
  double centre_error = -1.0;
  for (; frames < max_frames_; ++frames)
  {
    auto r = publishAndWait(frame(amcr_test::addNoise(moved_clean, 6.0, 2200 + frames), enc::MONO8, nextStamp()));
    ASSERT_TRUE(r);
    if (first_iteration < 0)
      first_iteration = r->iteration;
    EXPECT_EQ(r->prototype_table_version, version + 1);
    bool found = false;
    for (const auto& o : r->objects)
    {
      if (o.label != "flag" || o.outline.points.empty())
        continue;
      std::vector<cv::Point2f> points;
      for (const auto& p : o.outline.points)
        points.emplace_back(p.x, p.y);
      const cv::Rect2f b = cv::boundingRect(points);
      centre_error = cv::norm(cv::Point2f(b.x + 0.5f * b.width, b.y + 0.5f * b.height) - truth_centre);
      found = centre_error < corner_tolerance_ && std::abs(b.width / truth_box.width - 1.0) < 0.15 &&
              std::abs(b.height / truth_box.height - 1.0) < 0.15;
    }
    if (found)
      break;
  }
  EXPECT_GT(first_iteration, 1) << "teaching restarted the filter";
  ASSERT_LT(frames, max_frames_) << "the taught flag was not recognized within " << max_frames_
                                 << " frames (last centre error " << centre_error << " px)";
  ROS_INFO("taught flag recognized %d frames later, centre error %.2f px", frames + 1, centre_error);

  // Removed: the table goes back to 3, the file stays; teaching it again with save is refused.
  amcr::RemovePrototype remove;
  remove.request.label = "flag";
  ASSERT_TRUE(ros::service::call(node_ + "/remove_prototype", remove));
  EXPECT_TRUE(remove.response.success) << remove.response.message;
  EXPECT_EQ(remove.response.num_removed, 1);
  EXPECT_EQ(remove.response.table_version, version + 2);
  EXPECT_TRUE(prototypes_.waitFor([&](const amcr::PrototypeTable& t) { return t.version == version + 2 && t.prototypes.size() == 3; },
                                  timeout_));
  ASSERT_TRUE(ros::service::call(node_ + "/remove_prototype", remove));
  EXPECT_FALSE(remove.response.success);
  EXPECT_NE(remove.response.message.find("no label"), std::string::npos) << remove.response.message;
  EXPECT_EQ(remove.response.table_version, version + 2);
  ASSERT_TRUE(call(good));
  EXPECT_FALSE(good.response.success);
  EXPECT_NE(good.response.message.find("exists"), std::string::npos) << good.response.message;
  EXPECT_EQ(good.response.table_version, version + 2);
  std::remove(dir_->file("flag.png").c_str());
}
}  // namespace recognizer_tester
