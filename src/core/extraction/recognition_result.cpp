#include "amcr/extraction/recognition_result.h"

#include "amcr/extraction/viewing_angle.h"

namespace amcr
{
std::string toString(ObjectState state)
{
  switch (state)
  {
    case ObjectState::kTentative:
      return "tentative";
    case ObjectState::kConfirmed:
      return "confirmed";
    case ObjectState::kHeld:
      return "held";
    case ObjectState::kLost:
      return "lost";
  }
  return "unknown";
}

void mapImageSide(RecognizedObject& object, const Affine& image_map)
{
  Affine inverse = identityAffine();
  invertAffine(image_map, inverse);
  for (cv::Point2d& p : object.outline)
    p = applyAffine(image_map, p);
  for (Correspondence& c : object.correspondences)
    c.image = applyAffine(image_map, c.image);
  object.prototype_to_image = composeAffine(object.prototype_to_image, image_map);
  object.image_to_prototype = composeAffine(inverse, object.image_to_prototype);
  // A fitted homography is composed (the map's last row is 0 0 1: h22 stays
  // 1); otherwise it is the affine's lift, as RecognizedObject promises.
  object.homography = object.homography_valid ? composeHomography(object.homography, liftAffine(image_map))
                                              : liftAffine(object.prototype_to_image);
  object.anisotropy = affineAnisotropy(object.prototype_to_image);
  object.viewing_angle_deg = viewingAngleDegrees(object.anisotropy);
}
}  // namespace amcr
