// amcr_offline run as a program (the fixture: offline_runner_test.h): what it does with bad
// input, damaged files and wrong options, i.e. a warning and a skipped line, or one error line.
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/videoio.hpp>

#include "offline_runner_test.h"

namespace offline_runner_test
{
TEST_F(OfflineRunner, AnUnreadableFrameIsAWarningAndASkippedLine)
{
  const fs::path dir = root_ / "frames_with_bad_one";
  fs::create_directories(dir);
  for (int k = 0; k < 3; ++k)
    fs::copy_file(root_ / "frames" / ("frame_00" + std::to_string(k) + ".png"),
                  dir / ("frame_00" + std::to_string(k) + ".png"), fs::copy_options::overwrite_existing);
  writeFile(dir / "frame_001b.png", "not a png");
  writeFile(dir / "notes.txt", "ignored: not an image file name");
  const RunResult r = run(fastArgs(dir));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<json> frames = parseFrames(r.out);
  ASSERT_EQ(frames.size(), 4u);
  const json* skipped = member(frames[2], "skipped");
  ASSERT_TRUE(skipped && skipped->is_string());
  EXPECT_NE(skipped->get<std::string>().find("frame_001b.png"), std::string::npos);
  const json* objects = member(frames[2], "objects");
  EXPECT_TRUE(objects && objects->is_array() && objects->empty());
  EXPECT_EQ(numberOf(frames[2], "iteration"), numberOf(frames[1], "iteration"));
  EXPECT_EQ(member(frames[1], "skipped"), nullptr);
  const std::vector<std::string> warnings = splitLines(r.err);
  ASSERT_EQ(warnings.size(), 1u) << r.err;
  EXPECT_EQ(warnings[0].rfind("amcr_offline: warning: ", 0), 0u) << warnings[0];
  EXPECT_NE(warnings[0].find("frame_001b.png"), std::string::npos) << warnings[0];
}

TEST_F(OfflineRunner, AnUnusablePrototypeFileIsAWarning)
{
  const fs::path dir = root_ / "prototypes_with_bad_one";
  fs::create_directories(dir);
  fs::copy_file(root_ / "prototypes" / "star.png", dir / "star.png", fs::copy_options::overwrite_existing);
  writeFile(dir / "broken.png", "not a png");
  const RunResult r = run({"--prototypes", dir.string(), "--config", (root_ / "fast.yaml").string(), "--input",
                           (root_ / "frames").string(), "--frames", "1"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(parseFrames(r.out).size(), 1u);
  const std::vector<std::string> warnings = splitLines(r.err);
  ASSERT_EQ(warnings.size(), 1u) << r.err;
  EXPECT_EQ(warnings[0].rfind("amcr_offline: warning: ", 0), 0u) << warnings[0];
  EXPECT_NE(warnings[0].find("broken.png"), std::string::npos) << warnings[0];
}

TEST_F(OfflineRunner, HelpExitsZero)
{
  const RunResult r = run({"--help"});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("--prototypes DIR"), std::string::npos);
  EXPECT_NE(r.out.find("skipped"), std::string::npos);
  EXPECT_NE(r.out.find("3  the input ended early"), std::string::npos) << "the exit codes are not documented";
  EXPECT_TRUE(r.err.empty());
}

TEST_F(OfflineRunner, MissingPrototypeDirectoryIsOneErrorLine)
{
  const fs::path missing = root_ / "no_such_prototypes";
  expectOneErrorLine(
      run({"--prototypes", missing.string(), "--input", (root_ / "frames").string(), "--frames", "1"}), 1,
      "no_such_prototypes");
}

TEST_F(OfflineRunner, EmptyPrototypeDirectoryIsOneErrorLine)
{
  const fs::path empty = root_ / "empty_prototypes";
  fs::create_directories(empty);
  expectOneErrorLine(run({"--prototypes", empty.string(), "--input", (root_ / "frames").string(), "--frames", "1"}),
                     1, "empty_prototypes");
}

TEST_F(OfflineRunner, MissingInputIsOneErrorLine)
{
  expectOneErrorLine(run(fastArgs(root_ / "no_such_input.avi")), 1, "no_such_input.avi");
  const fs::path no_images = root_ / "no_images";
  fs::create_directories(no_images);
  writeFile(no_images / "readme.txt", "x");
  expectOneErrorLine(run(fastArgs(no_images)), 1, "no_images");
  writeFile(root_ / "garbage.bin", "neither an image nor a video");
  expectOneErrorLine(run(fastArgs(root_ / "garbage.bin")), 1, "garbage.bin");
}

TEST_F(OfflineRunner, BadOptionsAreOneErrorLine)
{
  expectOneErrorLine(run(fastArgs(root_ / "frames", {"--seed", "abc"})), 2, "--seed");
  expectOneErrorLine(run(fastArgs(root_ / "frames", {"--seed", "-4"})), 2, "--seed");
  expectOneErrorLine(run(fastArgs(root_ / "frames", {"--frames", "0"})), 2, "--frames");
  expectOneErrorLine(run(fastArgs(root_ / "frames", {"--colour", "red"})), 2, "--colour");
  expectOneErrorLine(run(fastArgs(root_ / "frames", {"--overlay", "x.gif"})), 2, "--overlay");
  expectOneErrorLine(run({"--input", (root_ / "frames").string()}), 2, "--prototypes");
}

TEST_F(OfflineRunner, ParameterOutOfRangeInTheConfigIsOneErrorLine)
{
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"p_outlier: 1.5", "p_outlier"}, {"num_v_particles: -3", "num_v_particles"}, {"sigma_w: 0", "sigma_w"}};
  for (const auto& c : cases)
  {
    const fs::path config = root_ / "bad.yaml";
    writeFile(config, "%YAML:1.0\n---\n" + c.first + "\n");
    expectOneErrorLine(run({"--prototypes", (root_ / "prototypes").string(), "--config", config.string(), "--input",
                            (root_ / "frames").string()}),
                       1, c.second);
  }
  expectOneErrorLine(run({"--prototypes", (root_ / "prototypes").string(), "--config",
                          (root_ / "no_such_config.yaml").string(), "--input", (root_ / "frames").string()}),
                     1, "no_such_config.yaml");
}

TEST_F(OfflineRunner, UnwritableOutputIsOneErrorLine)
{
  const fs::path output = root_ / "no_such_dir" / "out.jsonl";
  expectOneErrorLine(run(fastArgs(root_ / "frames", {"--output", output.string()})), 1, "out.jsonl");
}

// A video cut short or damaged used to end early with exit 0 and no word (6 of 10 frames): the frames read
// are kept, one line says how many of how many, and the exit code is 3.
TEST_F(OfflineRunner, ATruncatedOrCorruptVideoKeepsItsFramesAndSaysHowFarItWasRead)
{
  const std::string whole = writeVideo(root_ / "ten.avi", 10);
  ASSERT_GT(whole.size(), 1000u);
  std::string corrupt = whole;
  for (std::size_t i = whole.size() / 2; i < whole.size() * 55 / 100; ++i)
    corrupt[i] = '\0';
  const std::vector<std::pair<std::string, std::string>> videos = {
      {"truncated.avi", whole.substr(0, whole.size() * 6 / 10)}, {"corrupt.avi", corrupt}};
  for (const auto& video : videos)
  {
    writeFile(root_ / video.first, video.second);
    const RunResult r = run(fastArgs(root_ / video.first));
    EXPECT_EQ(r.exit_code, 3) << video.first << ": " << r.err;
    const std::vector<json> frames = parseFrames(r.out);
    EXPECT_GE(frames.size(), 1u) << video.first;
    EXPECT_LT(frames.size(), 10u) << video.first;
    const std::vector<std::string> lines = splitLines(r.err);
    ASSERT_EQ(lines.size(), 1u) << r.err;
    EXPECT_EQ(lines[0].rfind("amcr_offline: error: ", 0), 0u) << lines[0];
    const std::string figures = "ended after " + std::to_string(frames.size()) + " frames of the 10";
    for (const std::string& part : {video.first, figures})
      EXPECT_NE(lines[0].find(part), std::string::npos) << "'" << part << "' not in: " << lines[0];
  }
  // Read whole, or capped by --frames: no complaint.
  const RunResult whole_run = run(fastArgs(root_ / "ten.avi"));
  EXPECT_EQ(whole_run.exit_code, 0) << whole_run.err;
  EXPECT_EQ(parseFrames(whole_run.out).size(), 10u);
  const RunResult capped = run(fastArgs(root_ / "truncated.avi", {"--frames", "2"}));
  EXPECT_EQ(capped.exit_code, 0) << capped.err;
  EXPECT_TRUE(capped.err.empty()) << capped.err;
}

// cv::CAP_ANY offered a garbage file to the camera backends too (gphoto2 leaked, V4L2 opened it): only the
// file backends see it now. OpenCV says which backends it tries when OPENCV_VIDEOIO_DEBUG is set.
TEST_F(OfflineRunner, AGarbageFileIsOfferedToFileBackendsOnly)
{
  writeFile(root_ / "garbage.bin", "neither an image nor a video");
  expectOneErrorLine(run(fastArgs(root_ / "garbage.bin")), 1, "as an image or a video");
  const RunResult r =
      run(fastArgs(root_ / "garbage.bin"), "env OPENCV_VIDEOIO_DEBUG=1 OPENCV_LOG_LEVEL=WARNING ");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  const std::regex tried(R"(VIDEOIO\(([A-Z0-9_]+)\): trying capture)");
  int backends = 0;
  for (const std::string& line : splitLines(r.err))
  {
    std::smatch m;
    if (!std::regex_search(line, m, tried))
      continue;
    ++backends;
    EXPECT_TRUE(m[1] == "FFMPEG" || m[1] == "CV_MJPEG") << m[1] << " was offered a file: " << line;
  }
  EXPECT_GE(backends, 1) << "OpenCV did not say which backends it tried:\n" << r.err;
}

// A symbolic link loop said "does not exist"; an unreadable file said nothing about permissions.
TEST_F(OfflineRunner, ASymlinkLoopAndAnUnreadableFileSayWhatIsWrong)
{
  const fs::path loop_a = root_ / "loop_a.avi", loop_b = root_ / "loop_b.avi";
  std::error_code ignored;
  fs::remove(loop_a, ignored);
  fs::remove(loop_b, ignored);
  fs::create_symlink(loop_b, loop_a);
  fs::create_symlink(loop_a, loop_b);
  expectOneErrorLine(run(fastArgs(loop_a)), 1, "loop_a.avi' is a symbolic link loop");

  const char* prefix = withFilePermissions();
  if (!prefix)
    GTEST_SKIP() << "running as root without setpriv: every file is readable, permissions cannot be tested";
  writeVideo(root_ / "locked.avi", 2);
  fs::permissions(root_ / "locked.avi", fs::perms::none);
  expectOneErrorLine(run(fastArgs(root_ / "locked.avi"), prefix), 1, "locked.avi': Permission denied");

  const fs::path dir = root_ / "frames_with_locked_one";
  fs::create_directories(dir);
  fs::copy_file(root_ / "frames" / "frame_000.png", dir / "a.png", fs::copy_options::overwrite_existing);
  fs::copy_file(root_ / "frames" / "frame_001.png", dir / "b.png", fs::copy_options::overwrite_existing);
  fs::permissions(dir / "b.png", fs::perms::none);
  const RunResult r = run(fastArgs(dir), prefix);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(parseFrames(r.out).size(), 2u);
  const std::vector<std::string> warnings = splitLines(r.err);
  ASSERT_EQ(warnings.size(), 1u) << r.err;
  EXPECT_NE(warnings[0].find("b.png': Permission denied"), std::string::npos) << warnings[0];
}
}  // namespace offline_runner_test
