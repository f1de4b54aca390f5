#include "sequence_truth.h"

#include <fstream>
#include <map>
#include <stdexcept>

#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

namespace amcr_bench
{
namespace
{
using nlohmann::json;

cv::Matx33d matrixOf(const json& rows, int row_count)
{
  if (!rows.is_array() || static_cast<int>(rows.size()) != row_count)
    throw std::runtime_error("a map is not " + std::to_string(row_count) + " rows");
  cv::Matx33d m = cv::Matx33d::eye();
  for (int r = 0; r < row_count; ++r)
  {
    if (!rows[r].is_array() || rows[r].size() != 3)
      throw std::runtime_error("a map's row is not 3 numbers");
    for (int c = 0; c < 3; ++c)
      m(r, c) = rows[r][c].get<double>();
  }
  return m;
}

/// The prototype's self-maps under which the shape looks the same, the identity first: the truth's
/// `symmetries` (permutations of its 4 `score_points`) or `half_turn_symmetric`.
std::vector<cv::Matx33d> symmetriesOf(const json& truth, const cv::Size& size)
{
  std::vector<cv::Matx33d> maps = {cv::Matx33d::eye()};
  if (truth.value("half_turn_symmetric", false))
    maps.push_back(cv::Matx33d(-1, 0, size.width - 1.0, 0, -1, size.height - 1.0, 0, 0, 1));
  if (truth.contains("symmetries") && truth.contains("score_points"))
  {
    std::vector<cv::Point2f> points;
    for (const json& p : truth["score_points"])
      points.emplace_back(p[0].get<float>(), p[1].get<float>());
    if (points.size() != 4)
      throw std::runtime_error("score_points is not 4 points");
    for (const json& permutation : truth["symmetries"])
    {
      std::vector<cv::Point2f> moved;
      for (const json& i : permutation)
        moved.push_back(points.at(i.get<std::size_t>()));
      if (moved == points)
        continue;  // the identity, already there
      // S(points[i]) = points[perm[i]]: the truth composed with S maps point i where the truth
      // maps point perm[i], the same look.
      maps.push_back(cv::Matx33d(cv::Mat(cv::getPerspectiveTransform(points, moved))));
    }
  }
  return maps;
}
}  // namespace

std::vector<TruthFrame> readSequenceTruth(const std::string& path)
{
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error("cannot read " + path);
  try
  {
    const json truth = json::parse(in);
    std::map<std::string, std::string> sources;  // label -> the image the shown shape was drawn from
    for (const json& t : truth.value("targets", json::array()))
      sources[t.at("label").get<std::string>()] = t.value("source", std::string());
    std::vector<TruthFrame> frames;
    for (const json& f : truth.at("frames"))
    {
      TruthFrame frame;
      frame.known = !f.value("unknown", false);
      for (const json& o : f.at("objects"))
      {
        TruthObject object;
        object.label = o.at("label").get<std::string>();
        const auto source = sources.find(object.label);
        object.source = source == sources.end() ? std::string() : source->second;
        const json& size = truth.at("prototype_sizes").at(object.label);
        object.prototype_size = cv::Size(size.at(0).get<int>(), size.at(1).get<int>());
        if (frame.known)
        {
          const cv::Matx33d map = o.contains("homography") ? matrixOf(o["homography"], 3)
                                                           : matrixOf(o.at("prototype_to_image"), 2);
          for (const cv::Matx33d& symmetry : symmetriesOf(truth, object.prototype_size))
            object.prototype_to_image.push_back(map * symmetry);
        }
        frame.objects.push_back(std::move(object));
      }
      if (f.at("frame").get<std::size_t>() != frames.size())
        throw std::runtime_error("frame " + std::to_string(frames.size()) + " is not in order");
      frames.push_back(std::move(frame));
    }
    return frames;
  }
  catch (const std::exception& e)
  {
    throw std::runtime_error(path + ": " + e.what());
  }
}
}  // namespace amcr_bench
