#include "generalized_hough.h"

#include <algorithm>
#include <cmath>

namespace amcr_bench
{
GeneralizedHough::GeneralizedHough(const std::vector<PrototypeImage>& prototypes, const HoughConfig& config)
  : config_(config)
{
  for (const PrototypeImage& p : prototypes)
  {
    Model model;
    model.label = p.label;
    const cv::Mat mask = normalisedPrototype(p.mask, config.template_side, 4, model.template_to_original);
    model.centre = {static_cast<double>(mask.cols / 2), static_cast<double>(mask.rows / 2)};
    for (bool inverted : {false, true})
    {
      cv::Mat view;
      mask.convertTo(view, CV_8U, inverted ? 160.0 / 255 : -160.0 / 255, inverted ? 40 : 200);
      cv::GaussianBlur(view, view, cv::Size(), 1.0);
      cv::Mat edges;
      cv::Canny(view, edges, config.canny_low, config.canny_high);
      const int n = std::max(1, cv::countNonZero(edges));
      model.edge_points = n;
      cv::Ptr<cv::GeneralizedHoughGuil> d = cv::createGeneralizedHoughGuil();
      d->setMinDist(100);
      d->setLevels(360);
      d->setDp(2);
      d->setMaxBufferSize(1000);
      d->setMinAngle(0);
      d->setMaxAngle(360);
      d->setAngleStep(config.angle_step);
      d->setAngleThresh(std::max(1, static_cast<int>(config.angle_votes * n)));
      d->setMinScale(config.min_scale);
      d->setMaxScale(config.max_scale);
      d->setScaleStep(config.scale_step);
      d->setScaleThresh(std::max(1, static_cast<int>(config.scale_votes * n)));
      d->setPosThresh(std::max(1, static_cast<int>(config.position_votes * n)));
      d->setCannyLowThresh(config.canny_low);
      d->setCannyHighThresh(config.canny_high);
      d->setTemplate(view, cv::Point(mask.cols / 2, mask.rows / 2));
      model.detectors.push_back(d);
    }
    models_.push_back(std::move(model));
  }
}

std::vector<Detection> GeneralizedHough::detect(const cv::Mat& grey)
{
  cv::Mat frame;
  cv::GaussianBlur(grey, frame, cv::Size(), 1.0);
  std::vector<Detection> found;
  for (Model& model : models_)
  {
    cv::Vec4f best_position;
    int best_votes = -1;
    for (auto& detector : model.detectors)
    {
      std::vector<cv::Vec4f> positions;
      std::vector<cv::Vec3i> votes;
      try
      {
        detector->detect(frame, positions, votes);
      }
      catch (const cv::Exception&)
      {
        continue;
      }
      for (std::size_t i = 0; i < positions.size(); ++i)
        if (votes[i][0] > best_votes)
        {
          best_votes = votes[i][0];
          best_position = positions[i];
        }
    }
    if (best_votes < config_.report_votes * model.edge_points)
      continue;
    const double s = best_position[2], a = best_position[3] * CV_PI / 180.0;
    // template px -> frame px: rotate and scale about the template centre.
    const double c = s * std::cos(a), sn = s * std::sin(a);
    const cv::Matx33d t2f(c, -sn, best_position[0] - (c * model.centre.x - sn * model.centre.y),  //
                          sn, c, best_position[1] - (sn * model.centre.x + c * model.centre.y),   //
                          0, 0, 1);
    const cv::Matx23d& o = model.template_to_original;
    const cv::Matx33d t2o(o(0, 0), o(0, 1), o(0, 2), o(1, 0), o(1, 1), o(1, 2), 0, 0, 1);
    Detection d;
    d.label = model.label;
    d.score = static_cast<double>(best_votes) / model.edge_points;
    d.prototype_to_image = (t2f * t2o.inv()).get_minor<2, 3>(0, 0);
    found.push_back(std::move(d));
  }
  std::sort(found.begin(), found.end(), [](const Detection& a, const Detection& b) { return a.score > b.score; });
  return found;
}
}  // namespace amcr_bench
