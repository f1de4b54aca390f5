// The fixture of the tests of amcr_offline run as a program (test_offline_runner.cpp,
// test_offline_runner_errors.cpp): the inputs drawn in code (three prototypes, a moving star over
// clutter), a run of the program with its output and error captured, and the checks of its JSON
// lines and of a one-line error.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "strict_json.h"

#ifndef AMCR_OFFLINE_BINARY
#error "AMCR_OFFLINE_BINARY must name the amcr_offline executable"
#endif

namespace offline_runner_test
{
namespace fs = std::filesystem;
using amcr_test::member;
using amcr_test::parseStrictJson;
using nlohmann::json;

const cv::Size kFrameSize(320, 240);
constexpr int kSceneFrames = 5;

struct RunResult
{
  int exit_code = -1;
  std::string out;
  std::string err;
};

std::string quote(const std::string& text);
std::string readFile(const fs::path& path);
void writeFile(const fs::path& path, const std::string& text);
std::vector<std::string> splitLines(const std::string& text);
std::vector<cv::Point2d> starShape();
std::vector<cv::Point2d> arrowShape();
std::vector<cv::Point2d> lShape();

/// A prototype file: a dark silhouette centred on a white image.
void writePrototype(const fs::path& path, const std::vector<cv::Point2d>& shape);

/// Frame `k` of a scene: the star rotated, scaled and sheared, moving right
/// over a noisy gradient with a distractor line and a disc.
cv::Mat drawScene(int k);

/// Asserts that a failed run wrote nothing and exactly one readable error
/// line that names `expected`.
void expectOneErrorLine(const RunResult& run, int exit_code, const std::string& expected);

/// Checks the documented fields of one recognized object.
void checkObject(const json& object, const std::string& line);

/// A number member's value, or NaN when it is missing or no number.
double numberOf(const json& object, const std::string& key);

/// Parses JSON lines and checks the documented fields of each frame.
std::vector<json> parseFrames(const std::string& text);

class OfflineRunner : public ::testing::Test
{
protected:
  static void SetUpTestSuite()
  {
    std::string pattern = (fs::temp_directory_path() / "amcr_offline_test_XXXXXX").string();
    ASSERT_NE(mkdtemp(&pattern[0]), nullptr);
    root_ = pattern;
    fs::create_directories(root_ / "prototypes");
    writePrototype(root_ / "prototypes" / "star.png", starShape());
    writePrototype(root_ / "prototypes" / "arrow.png", arrowShape());
    writePrototype(root_ / "prototypes" / "l-shape.png", lShape());
    fs::create_directories(root_ / "frames");
    for (int k = 0; k < kSceneFrames; ++k)
    {
      char name[32];
      std::snprintf(name, sizeof(name), "frame_%03d.png", k);
      ASSERT_TRUE(cv::imwrite((root_ / "frames" / name).string(), drawScene(k)));
    }
    // Small particle counts and tables keep every run short.
    writeFile(root_ / "fast.yaml",
              "%YAML:1.0\n---\nnum_v_particles: 12\nm_particles_per_prototype: 12\nprototype_size: 64\nseed: 3\n");
  }

  static void TearDownTestSuite()
  {
    std::error_code ignored;
    fs::remove_all(root_, ignored);
  }

  /// Runs amcr_offline with `args`; its standard output and error are captured.
  static RunResult run(const std::vector<std::string>& args, const std::string& prefix = "")
  {
    std::string command = prefix + quote(AMCR_OFFLINE_BINARY);
    for (const std::string& a : args)
      command += " " + quote(a);
    const fs::path out = root_ / "stdout.txt";
    const fs::path err = root_ / "stderr.txt";
    command += " >" + quote(out.string()) + " 2>" + quote(err.string()) + " </dev/null";
    const int status = std::system(command.c_str());
    RunResult result;
    result.exit_code = (status != -1 && WIFEXITED(status)) ? WEXITSTATUS(status) : -1;
    result.out = readFile(out);
    result.err = readFile(err);
    return result;
  }

  /// The usual arguments with a fast config; `input` and extras appended.
  static std::vector<std::string> fastArgs(const fs::path& input, std::vector<std::string> extra = {})
  {
    std::vector<std::string> args = {"--prototypes", (root_ / "prototypes").string(), "--config",
                                     (root_ / "fast.yaml").string(), "--input", input.string()};
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
  }

  /// A prefix for run() under which file permissions apply: root (as in a container) reads every file
  /// unless it drops CAP_DAC_OVERRIDE. Empty when not root; null when root cannot drop it.
  static const char* withFilePermissions()
  {
    if (geteuid() != 0)
      return "";
    if (std::system("setpriv --bounding-set -dac_override,-dac_read_search -- true >/dev/null 2>&1") == 0)
      return "setpriv --bounding-set -dac_override,-dac_read_search -- ";
    return nullptr;
  }

  /// An MJPG .avi of `frames` frames of the scene, written by cv::VideoWriter; its bytes.
  static std::string writeVideo(const fs::path& path, int frames)
  {
    {
      cv::VideoWriter writer(path.string(), cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 15.0, kFrameSize, true);
      EXPECT_TRUE(writer.isOpened());
      for (int k = 0; k < frames; ++k)
        writer.write(drawScene(k % kSceneFrames));
    }
    return readFile(path);
  }

  static fs::path root_;
};

std::string withoutTimes(const std::string& text);
}  // namespace offline_runner_test
