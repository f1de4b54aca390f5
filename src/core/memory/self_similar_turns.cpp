#include "amcr/memory/self_similar_turns.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace amcr
{
bool modelTurn(const Prototype& prototype, double degrees, Affine& turn)
{
  // About the model points' centre: a template's region may hold more than
  // the object (a crop's background), its edges are the object.
  const std::vector<OutlinePoint>& model = prototype.outline();
  if (model.size() < 3)
    return false;
  cv::Point2d centre(0, 0);
  for (const OutlinePoint& o : model)
    centre += cv::Point2d(o.position);
  centre *= 1.0 / model.size();
  const double a = degrees * M_PI / 180.0;
  const double c = std::cos(a), s = std::sin(a);
  turn = Affine(c, -s, centre.x - c * centre.x + s * centre.y, s, c, centre.y - s * centre.x - c * centre.y);
  return true;
}

namespace
{
/// Distance (table px) from every table pixel to the nearest model point.
cv::Mat modelDistance(const Prototype& prototype)
{
  cv::Mat free(prototype.mask().size(), CV_8UC1, cv::Scalar(255));
  for (const OutlinePoint& o : prototype.outline())
  {
    const int x = cvRound(o.position.x), y = cvRound(o.position.y);
    if (x >= 0 && y >= 0 && x < free.cols && y < free.rows)
      free.at<std::uint8_t>(y, x) = 0;
  }
  cv::Mat distance;
  cv::distanceTransform(free, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  return distance;
}

double repeatShare(const Prototype& prototype, const cv::Mat& distance, const Affine& turn, double tolerance)
{
  const std::vector<OutlinePoint>& model = prototype.outline();
  if (model.empty())
    return 0.0;
  std::size_t repeated = 0;
  for (const OutlinePoint& o : model)
  {
    const cv::Point2d q = applyAffine(turn, cv::Point2d(o.position));
    const int x = cvRound(q.x), y = cvRound(q.y);
    if (x >= 0 && y >= 0 && x < distance.cols && y < distance.rows && distance.at<float>(y, x) <= tolerance)
      ++repeated;
  }
  return static_cast<double>(repeated) / model.size();
}
}  // namespace

double modelRepeatShare(const Prototype& prototype, const Affine& turn, double tolerance)
{
  return repeatShare(prototype, modelDistance(prototype), turn, tolerance);
}

std::vector<Affine> selfSimilarTurns(const Prototype& prototype, double tolerance_share, double min_share)
{
  std::vector<Affine> turns;
  std::vector<cv::Point2f> points;
  for (const OutlinePoint& o : prototype.outline())
    points.push_back(o.position);
  const cv::Rect box = cv::boundingRect(points);
  const double tolerance = tolerance_share * std::max(box.width, box.height);
  const cv::Mat distance = modelDistance(prototype);
  for (const int degrees : kTurnDegrees)
  {
    Affine turn;
    if (modelTurn(prototype, degrees, turn) && repeatShare(prototype, distance, turn, tolerance) >= min_share)
      turns.push_back(turn);
  }
  return turns;
}
}  // namespace amcr
