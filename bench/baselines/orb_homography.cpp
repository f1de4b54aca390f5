#include "orb_homography.h"

#include <algorithm>

#include <opencv2/calib3d.hpp>
#include <opencv2/flann.hpp>
#include <opencv2/imgproc.hpp>

#include "amcr/base/affine.h"

namespace amcr_bench
{
OrbHomography::OrbHomography(const std::vector<PrototypeImage>& prototypes, const OrbConfig& config)
  : config_(config)
  , frame_orb_(cv::ORB::create(config.frame_features))
  , matcher_(cv::makePtr<cv::flann::LshIndexParams>(12, 20, 2), cv::makePtr<cv::flann::SearchParams>(50))
{
  cv::Ptr<cv::ORB> orb = cv::ORB::create(config.prototype_features);
  cv::Mat all;
  for (const PrototypeImage& p : prototypes)
  {
    models_.push_back({p.label, p.mask.size()});
    cv::Matx23d to_original;
    const cv::Mat mask = normalisedPrototype(p.mask, config.prototype_side, config.prototype_side / 5, to_original);
    // The print is dark on light or inverted: describe both, as two views of one object.
    for (bool inverted : {false, true})
    {
      cv::Mat view;
      mask.convertTo(view, CV_8U, inverted ? 160.0 / 255 : -160.0 / 255, inverted ? 40 : 200);
      cv::GaussianBlur(view, view, cv::Size(), 1.0);
      std::vector<cv::KeyPoint> keypoints;
      cv::Mat descriptors;
      orb->detectAndCompute(view, cv::noArray(), keypoints, descriptors);
      for (const cv::KeyPoint& k : keypoints)
      {
        points_.push_back({to_original(0, 0) * k.pt.x + to_original(0, 2), to_original(1, 1) * k.pt.y + to_original(1, 2)});
        owner_.push_back(static_cast<int>(models_.size()) - 1);
      }
      all.push_back(descriptors);
    }
  }
  matcher_.add(std::vector<cv::Mat>{all});
  matcher_.train();
}

std::vector<Detection> OrbHomography::detect(const cv::Mat& grey)
{
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  frame_orb_->detectAndCompute(grey, cv::noArray(), keypoints, descriptors);
  std::vector<Detection> found;
  if (keypoints.size() < 2 || points_.empty())
    return found;
  std::vector<std::vector<cv::DMatch>> knn;
  matcher_.knnMatch(descriptors, knn, 2);
  // Matches that pass the ratio test, grouped by prototype: (prototype point, frame point).
  std::vector<std::vector<cv::Point2f>> from(models_.size()), to(models_.size());
  for (const auto& m : knn)
    if (m.size() == 2 && m[0].distance < config_.ratio * m[1].distance)
    {
      const int owner = owner_[m[0].trainIdx];
      from[owner].push_back(cv::Point2f(points_[m[0].trainIdx]));
      to[owner].push_back(keypoints[m[0].queryIdx].pt);
    }
  for (std::size_t i = 0; i < models_.size(); ++i)
  {
    if (static_cast<int>(from[i].size()) < config_.min_inliers)
      continue;
    std::vector<unsigned char> inlier;
    const cv::Mat h = cv::findHomography(from[i], to[i], cv::RANSAC, config_.ransac_px, inlier);
    if (h.empty())
      continue;
    Detection d;
    for (std::size_t k = 0; k < from[i].size(); ++k)
      if (inlier[k])
        d.correspondences.push_back({cv::Point2d(to[i][k]), cv::Point2d(from[i][k])});
    if (static_cast<int>(d.correspondences.size()) < config_.min_inliers)
      continue;
    // The reported affine: the least-squares affine through the homography's images of the
    // prototype's corners and centre.
    const float w = models_[i].size.width - 1, hh = models_[i].size.height - 1;
    const std::vector<cv::Point2f> corners = {{0, 0}, {w, 0}, {w, hh}, {0, hh}, {w / 2, hh / 2}};
    std::vector<cv::Point2f> mapped;
    cv::perspectiveTransform(corners, mapped, h);
    const std::vector<cv::Point2d> a(corners.begin(), corners.end()), b(mapped.begin(), mapped.end());
    if (!amcr::fitAffine(a, b, d.prototype_to_image))
      continue;
    d.label = models_[i].label;
    d.score = static_cast<double>(d.correspondences.size());
    found.push_back(std::move(d));
  }
  std::sort(found.begin(), found.end(), [](const Detection& a, const Detection& b) { return a.score > b.score; });
  return found;
}
}  // namespace amcr_bench
