// The generic rostest tester of amcr/RecognizerNodelet (style point 9): one
// program, parameterised by the launch file, with every input drawn in code
// (test/scene_drawing.h). The nodelet under test starts with a prototype
// directory that does not exist; the tester writes the prototypes and loads
// them through ~load_prototypes, then publishes frames of the expected
// prototype under a known affine over clutter, one at a time, each waited for
// on ~recognitions (no sleeps: every wait is on a condition with a timeout).
//
// Private parameters:
//   ~node              namespace of the nodelet under test (default /amcr)
//   ~image             topic the nodelet subscribes to (default /camera/image)
//   ~label             the expected label: one of arrow, crescent, star (default arrow)
//   ~rotation, ~scale_x, ~scale_y, ~shear   the true prototype->image affine (rad, ratios)
//   ~clutter_seed      seed of the drawn clutter (default 1)
//   ~max_frames        frames within which the label must be recognized (default 100)
//   ~corner_tolerance  mean corner error of prototype_to_image, px (default 6)
//   ~timeout           seconds to wait for any one answer (default 20)
//   ~check_pose        publish camera_info (~camera_info topic, fx = fy = ~focal px, centre of the
//                      image) and check the pose and tf frame (default false: then pose_valid must be
//                      false). Needs a similarity (scale_x = scale_y, shear = 0): the scene is then the
//                      exact image of a plane parallel to the image plane, at z = focal * m/px / scale.
//   ~metres_per_pixel  the value the nodelet was given (default 0.001)
//   ~translation_tolerance  of the pose and the tf frame, m (default 0.02)
//   ~rectified         the frames are rectified images: camera_info's P has the focal ~focal, while
//                      K (12 % longer) and D (barrel distortion) are the raw camera's; the nodelet
//                      must use P (default false: K = P, D = 0)
//   ~frame_prefix      the nodelet's tf prefix (default amcr/)
//   ~check_markers     check ~markers: an outline and a label for the recognized object, deleted once
//                      it leaves the image (default false; needs ~check_pose)
//   ~check_teach       teach a drawn flag from a frame through ~teach, recognize it under another
//                      pose, refuse bad regions, remove it (default false)
//
// The tests are in recognizer_tester_*.cpp, by what they check; the fixture is recognizer_test.h.
// gtest runs the tests in the order they register; across files that is the order of static
// initialisation, which the GNU and LLVM toolchains make the link order (the sources' order in
// CMakeLists.txt): StartsWithoutPrototypesAndLoadsThemAtRuntime, which sees the nodelet before any
// memory, must come first, and recognizer_tester_recognition.cpp is the first of them.
#include <cstdint>
#include <memory>
#include <string>

#include <gtest/gtest.h>
#include <ros/ros.h>

#include "recognizer_test.h"

namespace recognizer_tester
{
std::string RecognizerTest::node_, RecognizerTest::image_topic_, RecognizerTest::label_, RecognizerTest::info_topic_,
    RecognizerTest::frame_prefix_;
bool RecognizerTest::check_pose_ = false, RecognizerTest::similarity_ = false, RecognizerTest::rectified_ = false,
     RecognizerTest::check_markers_ = false, RecognizerTest::check_teach_ = false;
double RecognizerTest::focal_ = 500.0, RecognizerTest::metres_per_pixel_ = 0.001,
       RecognizerTest::translation_tolerance_ = 0.02, RecognizerTest::scale_ = 1.0;
ros::Publisher RecognizerTest::info_pub_;
std::unique_ptr<tf2_ros::Buffer> RecognizerTest::tf_buffer_;
std::unique_ptr<tf2_ros::TransformListener> RecognizerTest::tf_listener_;
int RecognizerTest::max_frames_ = 100;
double RecognizerTest::corner_tolerance_ = 6.0, RecognizerTest::timeout_ = 20.0;
amcr::Affine RecognizerTest::truth_;
amcr_test::Scene RecognizerTest::scene_;
cv::Mat RecognizerTest::clean_;
std::unique_ptr<amcr_test::TempDir> RecognizerTest::dir_;
std::unique_ptr<ros::NodeHandle> RecognizerTest::nh_;
ros::Publisher RecognizerTest::image_pub_;
Inbox<amcr::Recognitions> RecognizerTest::recognitions_;
Inbox<amcr::PrototypeTable> RecognizerTest::prototypes_;
Inbox<rosgraph_msgs::Log> RecognizerTest::log_;
Inbox<diagnostic_msgs::DiagnosticArray> RecognizerTest::diagnostics_;
bool RecognizerTest::loaded_ = false;
ros::Time RecognizerTest::stamp_(1000.0);
std::uint64_t RecognizerTest::noise_index_ = 0;
}  // namespace recognizer_tester

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "recognizer_tester");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const int result = RUN_ALL_TESTS();
  spinner.stop();
  ros::shutdown();
  return result;
}
