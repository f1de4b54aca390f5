#include "amcr/extraction/optical_flow.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/video/tracking.hpp>

#include "amcr/base/errors.h"

namespace amcr
{
namespace
{
constexpr int kMaxLkIterations = 20;
constexpr double kLkEpsilon = 0.03;          // px: LK stops when an update is smaller
constexpr double kRansacThreshold = 2.0;     // px: a flow agrees with the patch motion within this
}  // namespace

PyramidFlow::PyramidFlow(int window, int levels, double max_error)
  : window_(window, window), levels_(levels), max_error_(max_error)
{
  if (window < 3 || levels < 0 || !(max_error > 0.0))
    throw ParameterError("optical flow: window must be at least 3 px, levels at least 0, max_error above 0");
}

void PyramidFlow::push(const cv::Mat& gray8)
{
  if (gray8.empty() || gray8.type() != CV_8UC1)
    throw InputError("optical flow: a frame must be a non-empty 8-bit grey image");
  if (gray8.size() != frame_size_)
    current_.clear();
  frame_size_ = gray8.size();
  std::swap(previous_, current_);
  current_.clear();
  cv::buildOpticalFlowPyramid(gray8, current_, window_, levels_);
}

std::vector<FlowVector> PyramidFlow::track(const std::vector<cv::Point2f>& from) const
{
  std::vector<FlowVector> flow(from.size());
  if (!ready() || from.empty())
    return flow;
  std::vector<cv::Point2f> to = from;
  std::vector<uchar> status;
  std::vector<float> error;
  cv::calcOpticalFlowPyrLK(previous_, current_, from, to, status, error, window_, levels_,
                           cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, kMaxLkIterations,
                                            kLkEpsilon),
                           cv::OPTFLOW_USE_INITIAL_FLOW);
  const float max_x = static_cast<float>(frame_size_.width - 1), max_y = static_cast<float>(frame_size_.height - 1);
  for (std::size_t i = 0; i < from.size(); ++i)
  {
    flow[i].to = to[i];
    flow[i].found = status[i] != 0;
    flow[i].ok = status[i] && error[i] <= max_error_ && to[i].x >= 0.f && to[i].y >= 0.f && to[i].x <= max_x &&
                 to[i].y <= max_y;
  }
  return flow;
}

void PyramidFlow::reset()
{
  previous_.clear();
  current_.clear();
  frame_size_ = cv::Size();
}

bool estimatePatchMotion(const std::vector<cv::Point2f>& from, const std::vector<FlowVector>& flow,
                         int min_inliers, cv::Matx23d& motion)
{
  std::vector<cv::Point2f> a, b;
  for (std::size_t i = 0; i < from.size() && i < flow.size(); ++i)
    if (flow[i].ok)
    {
      a.push_back(from[i]);
      b.push_back(flow[i].to);
    }
  if (static_cast<int>(a.size()) < std::max(min_inliers, 2))
    return false;
  std::vector<uchar> inliers;
  const cv::Mat m = cv::estimateAffinePartial2D(a, b, inliers, cv::RANSAC, kRansacThreshold);
  if (m.empty() || cv::countNonZero(inliers) < min_inliers)
    return false;
  motion = cv::Matx23d(m.ptr<double>());  // estimateAffinePartial2D returns CV_64F
  return true;
}
}  // namespace amcr
