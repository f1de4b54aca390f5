// The inputs, the runs and the checks of offline_runner_test.h.
#include "offline_runner_test.h"

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <utility>

#include <opencv2/imgproc.hpp>

namespace offline_runner_test
{
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

void writePrototype(const fs::path& path, const std::vector<cv::Point2d>& shape)
{
  cv::Mat image(160, 160, CV_8UC1, cv::Scalar(255));
  cv::fillPoly(image, std::vector<std::vector<cv::Point>>{transformed(shape, cv::Matx23d(1, 0, 80, 0, 1, 80))},
               cv::Scalar(0), cv::LINE_AA);
  ASSERT_TRUE(cv::imwrite(path.string(), image));
}

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

void checkObject(const json& object, const std::string& line)
{
  for (const char* key :
       {"label", "track_id", "score", "visible_share", "support", "image_to_prototype", "prototype_to_image", "homography",
        "homography_valid", "anisotropy", "viewing_angle_deg", "correspondences"})
    EXPECT_TRUE(member(object, key) != nullptr) << key << " missing in " << line;
  const json* label = member(object, "label");
  EXPECT_TRUE(label && label->is_string()) << line;
  const json* score = member(object, "score");
  EXPECT_TRUE(score && score->is_number() && score->get<double>() >= 0.0 && score->get<double>() <= 1.0) << line;
  const json* visible = member(object, "visible_share");
  EXPECT_TRUE(visible && visible->is_number() && visible->get<double>() >= 0.0 && visible->get<double>() <= 1.0)
      << line;
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

double numberOf(const json& object, const std::string& key)
{
  const json* value = member(object, key);
  return value && value->is_number() ? value->get<double>() : std::nan("");
}

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

fs::path OfflineRunner::root_;

std::string withoutTimes(const std::string& text)
{
  return std::regex_replace(text, std::regex("\"time_ms\": [0-9.]+"), "\"time_ms\": T");
}
}  // namespace offline_runner_test
