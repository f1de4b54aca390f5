// amcr_offline run as a program on inputs drawn in code (the fixture: offline_runner_test.h): its
// JSON lines and its overlay video. No roscore. Its warnings and errors: test_offline_runner_errors.cpp.
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "amcr/overlay.h"
#include "offline_runner_test.h"
#include "template_drawing.h"

namespace offline_runner_test
{
TEST_F(OfflineRunner, OneWellFormedJsonLinePerFrameOfADirectory)
{
  const fs::path output = root_ / "directory.jsonl";
  const RunResult r = run(fastArgs(root_ / "frames", {"--output", output.string()}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.out.empty()) << "JSON goes to --output only";
  EXPECT_TRUE(r.err.empty()) << r.err;
  const std::string text = readFile(output);
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n');
  const std::vector<json> frames = parseFrames(text);
  ASSERT_EQ(frames.size(), static_cast<std::size_t>(kSceneFrames));
  for (std::size_t i = 1; i < frames.size(); ++i)
    EXPECT_GT(numberOf(frames[i], "iteration"), numberOf(frames[i - 1], "iteration"));
}

TEST_F(OfflineRunner, FramesCapsADirectoryAndJsonGoesToStandardOutput)
{
  const RunResult r = run(fastArgs(root_ / "frames", {"--frames", "3"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(parseFrames(r.out).size(), 3u);
}

TEST_F(OfflineRunner, ASingleImageIsRepeatedFramesTimes)
{
  const RunResult r = run(fastArgs(root_ / "frames" / "frame_000.png", {"--frames", "4"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(parseFrames(r.out).size(), 4u);
}

TEST_F(OfflineRunner, SameSeedSameOutput)
{
  const RunResult a = run(fastArgs(root_ / "frames", {"--seed", "11"}));
  const RunResult b = run(fastArgs(root_ / "frames", {"--seed", "11"}));
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  ASSERT_EQ(parseFrames(a.out).size(), static_cast<std::size_t>(kSceneFrames));
  EXPECT_EQ(withoutTimes(a.out), withoutTimes(b.out));
}

// The V-particles' updates on 1, 2 and 4 threads: the same JSON, byte for
// byte (the times aside), over 20 frames of the drawn scene with the default
// counts.
TEST_F(OfflineRunner, SameOutputOnOneTwoAndFourThreads)
{
  std::vector<std::string> outputs;
  for (int threads : {1, 2, 4})
  {
    const fs::path config = root_ / ("threads" + std::to_string(threads) + ".yaml");
    writeFile(config, "%YAML:1.0\n---\nnum_threads: " + std::to_string(threads) + "\nprototype_size: 64\nseed: 5\n");
    const RunResult r = run({"--prototypes", (root_ / "prototypes").string(), "--config", config.string(), "--input",
                             (root_ / "frames" / "frame_000.png").string(), "--frames", "20"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    ASSERT_EQ(parseFrames(r.out).size(), 20u);
    outputs.push_back(withoutTimes(r.out));
  }
  EXPECT_EQ(outputs[1], outputs[0]) << "2 threads differ from 1";
  EXPECT_EQ(outputs[2], outputs[0]) << "4 threads differ from 1";
  EXPECT_NE(outputs[0].find("\"label\""), std::string::npos) << "nothing recognized: the comparison says little";
}

TEST_F(OfflineRunner, VideoInputAndOverlayVideoOfFixedSize)
{
  const fs::path video = root_ / "scene.avi";
  {
    cv::VideoWriter writer(video.string(), cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 15.0, kFrameSize, true);
    ASSERT_TRUE(writer.isOpened());
    for (int k = 0; k < 6; ++k)
      writer.write(drawScene(k));
  }
  const fs::path overlay = root_ / "overlay.avi";
  const RunResult r = run(fastArgs(video, {"--overlay", overlay.string()}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(parseFrames(r.out).size(), 6u);

  cv::VideoCapture capture(overlay.string());
  ASSERT_TRUE(capture.isOpened());
  const cv::Size expected = amcr::overlayLayout(kFrameSize, 3).size;
  int count = 0;
  for (cv::Mat frame; capture.read(frame); ++count)
    EXPECT_EQ(frame.size(), expected);
  EXPECT_EQ(count, 6);

  // --frames caps a video too.
  const RunResult capped = run(fastArgs(video, {"--frames", "2"}));
  ASSERT_EQ(capped.exit_code, 0) << capped.err;
  EXPECT_EQ(parseFrames(capped.out).size(), 2u);
}
}  // namespace offline_runner_test

namespace offline_runner_test
{
// --write-models alone: one picture per prototype, the grey template among
// them read as one (its model holds points inside its body, on the disc).
TEST_F(OfflineRunner, WriteModelsDrawsEveryPrototypesModel)
{
  const fs::path prototypes = root_ / "with_template";
  fs::create_directories(prototypes);
  for (const char* name : {"star.png", "arrow.png"})
    fs::copy_file(root_ / "prototypes" / name, prototypes / name, fs::copy_options::overwrite_existing);
  ASSERT_TRUE(cv::imwrite((prototypes / "part.png").string(), amcr_test::drawGreyTemplate()));
  const fs::path models = root_ / "models" / "new";
  const RunResult r =
      run({"--prototypes", prototypes.string(), "--config", (root_ / "fast.yaml").string(), "--write-models",
           models.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("(1 grey templates, 2 silhouettes)"), std::string::npos) << r.err;
  for (const char* name : {"star.model.png", "arrow.model.png", "part.model.png"})
  {
    const cv::Mat picture = cv::imread((models / name).string());
    ASSERT_FALSE(picture.empty()) << name;
    EXPECT_GT(picture.cols, 64) << name;
  }
  EXPECT_TRUE(r.out.empty()) << "no frame was asked for";

  // Without --input and --write-models, --input is missing.
  const RunResult missing = run({"--prototypes", prototypes.string()});
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("missing --input PATH"), std::string::npos) << missing.err;
}
}  // namespace offline_runner_test
