#include "template_drawing.h"

#include <opencv2/imgproc.hpp>

namespace amcr_test
{
namespace
{
constexpr double kBoard = 150, kBody = 45, kDisc = 215, kBar = 185;

/// The body's inner structure drawn into `image` (template px).
void drawInside(cv::Mat& image, double body, double disc, double bar)
{
  image(kTemplateBody).setTo(body);
  cv::circle(image, cv::Point(58, 58), 22, cv::Scalar(disc), cv::FILLED, cv::LINE_AA);
  cv::rectangle(image, cv::Rect(40, 104, 80, 16), cv::Scalar(bar), cv::FILLED);
}
}  // namespace

cv::Mat drawGreyTemplate()
{
  cv::Mat image(kTemplateSide, kTemplateSide, CV_8UC1, cv::Scalar(kBoard));
  drawInside(image, kBody, kDisc, kBar);
  return image;
}

cv::Mat drawTemplateOutline()
{
  cv::Mat image = cv::Mat::zeros(kTemplateSide, kTemplateSide, CV_8UC1);
  image(kTemplateBody).setTo(255);
  return image;
}

std::vector<cv::Mat> templateOverClutter(TemplateView view, const amcr::Affine& truth, const Clutter& clutter,
                                         int frames)
{
  Scene scene;
  scene.clutter = clutter;
  scene.objects = {{ShapeId::kCrescent, truth}};  // only to keep the distractors off the part's place
  const cv::Mat background = renderBackground(scene);

  cv::Mat part(kTemplateSide, kTemplateSide, CV_8UC1, cv::Scalar(0));
  if (view == TemplateView::kPlain)
    part(kTemplateBody).setTo(kBody);
  else
    drawInside(part, kBody, kDisc, kBar);
  const cv::Mat body_mask = drawTemplateOutline();

  cv::Mat warped_part, warped_mask;
  cv::warpAffine(part, warped_part, cv::Mat(truth), background.size(), cv::INTER_LINEAR);
  cv::warpAffine(body_mask, warped_mask, cv::Mat(truth), background.size(), cv::INTER_LINEAR);
  // The body over the background, blended at its antialiased edge.
  cv::Mat clean(background.size(), CV_8UC1);
  for (int y = 0; y < clean.rows; ++y)
    for (int x = 0; x < clean.cols; ++x)
    {
      const double a = warped_mask.at<std::uint8_t>(y, x) / 255.0;
      const double inside = a > 0 ? warped_part.at<std::uint8_t>(y, x) / a : 0.0;  // undo the blend with 0
      clean.at<std::uint8_t>(y, x) =
          cv::saturate_cast<std::uint8_t>(a * inside + (1 - a) * background.at<std::uint8_t>(y, x));
    }
  if (view == TemplateView::kReversed)
    cv::bitwise_not(clean, clean);
  std::vector<cv::Mat> out;
  for (int k = 0; k < frames; ++k)
    out.push_back(addNoise(clean, clutter.noise_sigma, clutter.seed * 1000 + static_cast<std::uint64_t>(k)));
  return out;
}
amcr::Affine templatePlacement(double turn_deg, const cv::Point2d& centre, double scale)
{
  const cv::Point2d template_centre(0.5 * (kTemplateSide - 1), 0.5 * (kTemplateSide - 1));
  return makeAffine(template_centre, centre, turn_deg * CV_PI / 180.0, scale, scale, 0.0);
}

cv::Mat templateFrame(TemplateView view, const amcr::Affine& truth, std::uint64_t clutter_seed)
{
  Clutter clutter;
  clutter.random_shapes = 7;
  clutter.silhouettes = {ShapeId::kEll, ShapeId::kFlag};
  clutter.seed = clutter_seed;
  return templateOverClutter(view, truth, clutter, 1)[0];
}
}  // namespace amcr_test
