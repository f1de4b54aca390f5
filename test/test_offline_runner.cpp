// amcr_offline run as a program on inputs drawn in code: its JSON lines, its
// overlay video, and its one-line errors. No roscore.
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "amcr/overlay.h"
#include "strict_json.h"

#ifndef AMCR_OFFLINE_BINARY
#error "AMCR_OFFLINE_BINARY must name the amcr_offline executable"
#endif

namespace fs = std::filesystem;
using amcr_test::member;
using amcr_test::parseStrictJson;
using nlohmann::json;

namespace
{
const cv::Size kFrameSize(320, 240);
constexpr int kSceneFrames = 5;

struct RunResult
{
  int exit_code = -1;
  std::string out;
  std::string err;
};

std::string quote(const std::string& text)
{
  std::string quoted = "'";
  for (const char c : text)
    quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

std::string readFile(const fs::path& path)
{
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void writeFile(const fs::path& path, const std::string& text)
{
  std::ofstream out(path, std::ios::binary);
  out << text;
}

std::vector<std::string> splitLines(const std::string& text)
{
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    lines.push_back(line);
  return lines;
}

std::vector<cv::Point> transformed(const std::vector<cv::Point2d>& shape, const cv::Matx23d& a)
{
  std::vector<cv::Point> out;
  for (const cv::Point2d& p : shape)
    out.emplace_back(cvRound(a(0, 0) * p.x + a(0, 1) * p.y + a(0, 2)), cvRound(a(1, 0) * p.x + a(1, 1) * p.y + a(1, 2)));
  return out;
}

std::vector<cv::Point2d> starShape()
{
  std::vector<cv::Point2d> star;
  for (int k = 0; k < 10; ++k)
  {
    const double r = k % 2 == 0 ? 60.0 : 25.0;
    const double angle = -CV_PI / 2 + k * CV_PI / 5;
    star.emplace_back(r * std::cos(angle), r * std::sin(angle));
  }
  return star;
}

std::vector<cv::Point2d> arrowShape()
{
  return {{-60, -15}, {10, -15}, {10, -40}, {60, 0}, {10, 40}, {10, 15}, {-60, 15}};
}

std::vector<cv::Point2d> lShape() { return {{-40, -50}, {-10, -50}, {-10, 20}, {40, 20}, {40, 50}, {-40, 50}}; }

/// A prototype file: a dark silhouette centred on a white image.
void writePrototype(const fs::path& path, const std::vector<cv::Point2d>& shape)
{
  cv::Mat image(160, 160, CV_8UC1, cv::Scalar(255));
  cv::fillPoly(image, std::vector<std::vector<cv::Point>>{transformed(shape, cv::Matx23d(1, 0, 80, 0, 1, 80))},
               cv::Scalar(0), cv::LINE_AA);
  ASSERT_TRUE(cv::imwrite(path.string(), image));
}

/// Frame `k` of a scene: the star rotated, scaled and sheared, moving right
/// over a noisy gradient with a distractor line and a disc.
cv::Mat drawScene(int k)
{
  cv::Mat image(kFrameSize, CV_8UC3);
  for (int y = 0; y < image.rows; ++y)
    image.row(y).setTo(cv::Scalar(150 + y / 6, 160 + y / 8, 170));
  cv::line(image, cv::Point(10, 200), cv::Point(300, 170), cv::Scalar(40, 40, 40), 3, cv::LINE_AA);
  cv::circle(image, cv::Point(270, 60), 25, cv::Scalar(60, 80, 60), cv::FILLED, cv::LINE_AA);
  const double angle = 0.3, scale = 0.8, shear = 0.15;
  const cv::Matx23d pose(scale * std::cos(angle), scale * (-std::sin(angle) + shear), 120 + 3 * k,
                         scale * std::sin(angle), scale * std::cos(angle), 115);
  cv::fillPoly(image, std::vector<std::vector<cv::Point>>{transformed(starShape(), pose)}, cv::Scalar(30, 30, 30),
               cv::LINE_AA);
  cv::Mat noise(image.size(), CV_16SC3);
  cv::RNG rng(1000 + k);
  rng.fill(noise, cv::RNG::NORMAL, 0, 6);
  cv::Mat noisy;
  cv::add(image, noise, noisy, cv::noArray(), CV_8U);
  return noisy;
}

/// Asserts that a failed run wrote nothing and exactly one readable error
/// line that names `expected`.
void expectOneErrorLine(const RunResult& run, int exit_code, const std::string& expected)
{
  EXPECT_EQ(run.exit_code, exit_code) << run.err;
  EXPECT_TRUE(run.out.empty()) << run.out;
  ASSERT_FALSE(run.err.empty());
  EXPECT_EQ(run.err.back(), '\n');
  const std::vector<std::string> lines = splitLines(run.err);
  ASSERT_EQ(lines.size(), 1u) << run.err;
  EXPECT_EQ(lines[0].rfind("amcr_offline: error: ", 0), 0u) << lines[0];
  EXPECT_NE(lines[0].find(expected), std::string::npos) << "'" << expected << "' not in: " << lines[0];
}

/// Checks the documented fields of one recognized object.
void checkObject(const json& object, const std::string& line)
{
  for (const char* key :
       {"label", "track_id", "score", "support", "image_to_prototype", "prototype_to_image", "homography",
        "homography_valid", "anisotropy", "viewing_angle_deg", "correspondences"})
    EXPECT_TRUE(member(object, key) != nullptr) << key << " missing in " << line;
  const json* label = member(object, "label");
  EXPECT_TRUE(label && label->is_string()) << line;
  const json* score = member(object, "score");
  EXPECT_TRUE(score && score->is_number() && score->get<double>() >= 0.0 && score->get<double>() <= 1.0) << line;
  for (const char* key : {"image_to_prototype", "prototype_to_image"})
  {
    const json* a = member(object, key);
    ASSERT_TRUE(a && a->is_array() && a->size() == 2u) << key << " in " << line;
    for (const json& row : *a)
    {
      ASSERT_TRUE(row.is_array() && row.size() == 3u) << key << " in " << line;
      for (const json& v : row)
        EXPECT_TRUE(v.is_number()) << key << " in " << line;
    }
  }
  const json* h = member(object, "homography");
  ASSERT_TRUE(h && h->is_array() && h->size() == 3u) << line;
  for (const json& row : *h)
  {
    ASSERT_TRUE(row.is_array() && row.size() == 3u) << line;
    for (const json& v : row)
      EXPECT_TRUE(v.is_number()) << line;
  }
  const json* valid = member(object, "homography_valid");
  ASSERT_TRUE(valid && valid->is_boolean()) << line;
  if (!valid->get<bool>())
  {
    // Not used: the homography is the affine's lift.
    const json& a = *member(object, "prototype_to_image");
    for (int r = 0; r < 2; ++r)
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR((*h)[r][c].get<double>(), a[r][c].get<double>(), 1e-6) << line;
    EXPECT_EQ((*h)[2][0].get<double>(), 0.0) << line;
    EXPECT_EQ((*h)[2][1].get<double>(), 0.0) << line;
  }
  EXPECT_EQ((*h)[2][2].get<double>(), 1.0) << line;
  const json* anisotropy = member(object, "anisotropy");
  const json* angle = member(object, "viewing_angle_deg");
  ASSERT_TRUE(anisotropy && anisotropy->is_number() && angle && angle->is_number()) << line;
  EXPECT_GE(anisotropy->get<double>(), 1.0) << line;
  // viewing_angle_deg = acos(1 / anisotropy), up to the rounding of both.
  EXPECT_NEAR(std::cos(angle->get<double>() * M_PI / 180.0), 1.0 / anisotropy->get<double>(), 2e-4) << line;
  const json* correspondences = member(object, "correspondences");
  ASSERT_TRUE(correspondences && correspondences->is_array()) << line;
  for (const json& c : *correspondences)
  {
    ASSERT_TRUE(c.is_array() && c.size() == 4u) << line;
    for (const json& v : c)
      EXPECT_TRUE(v.is_number()) << line;
  }
}

/// A number member's value, or NaN when it is missing or no number.
double numberOf(const json& object, const std::string& key)
{
  const json* value = member(object, key);
  return value && value->is_number() ? value->get<double>() : std::nan("");
}

/// Parses JSON lines and checks the documented fields of each frame.
std::vector<json> parseFrames(const std::string& text)
{
  std::vector<json> frames;
  const std::vector<std::string> lines = splitLines(text);
  for (std::size_t i = 0; i < lines.size(); ++i)
  {
    json frame;
    std::string error;
    EXPECT_TRUE(parseStrictJson(lines[i], frame, error)) << "line " << i << ": " << error << "\n" << lines[i];
    EXPECT_TRUE(frame.is_object()) << lines[i];
    const json* index = member(frame, "frame");
    const json* time = member(frame, "time_ms");
    const json* iteration = member(frame, "iteration");
    const json* iterations = member(frame, "iterations");
    const json* objects = member(frame, "objects");
    EXPECT_TRUE(index && index->is_number() && index->get<double>() == static_cast<double>(i)) << lines[i];
    EXPECT_TRUE(time && time->is_number() && time->get<double>() >= 0.0) << lines[i];
    EXPECT_TRUE(iteration && iteration->is_number()) << lines[i];
    // Without a frame budget every frame runs one whole iteration (none when skipped).
    EXPECT_TRUE(iterations && iterations->is_number() &&
                iterations->get<double>() == (member(frame, "skipped") ? 0.0 : 1.0)) << lines[i];
    EXPECT_TRUE(objects && objects->is_array()) << lines[i];
    if (objects && objects->is_array())
      for (const json& object : *objects)
        checkObject(object, lines[i]);
    frames.push_back(std::move(frame));
  }
  return frames;
}

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

fs::path OfflineRunner::root_;

std::string withoutTimes(const std::string& text)
{
  return std::regex_replace(text, std::regex("\"time_ms\": [0-9.]+"), "\"time_ms\": T");
}
}  // namespace

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
