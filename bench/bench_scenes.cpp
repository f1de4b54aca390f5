#include "bench_scenes.h"

#include <cmath>
#include <string>

#include "scene_drawing.h"

namespace amcr_bench
{
namespace
{
using amcr_test::ShapeId;

std::shared_ptr<const amcr::PrototypeMemory> memoryOf(int count)
{
  auto memory = std::make_shared<amcr::PrototypeMemory>();
  const std::vector<ShapeId>& shapes = amcr_test::allShapes();
  for (int i = 0; i < count; ++i)
  {
    const ShapeId id = shapes[i % shapes.size()];
    memory->add(amcr_test::shapeName(id) + "_" + std::to_string(i), amcr_test::drawPrototype(id), amcr::Params());
  }
  return memory;
}

amcr::Affine movingPose(int frame)
{
  const double t = 2.0 * M_PI * frame / 200.0;
  return amcr_test::makeAffine(amcr_test::prototypeCentre(),
                               {320.0 + 110.0 * std::sin(t), 240.0 + 55.0 * std::sin(2.0 * t)},
                               (20.0 + 2.5 * frame) * M_PI / 180.0, 0.6, 0.52, 0.15);
}
}  // namespace

std::shared_ptr<const amcr::PrototypeMemory> cachedMemory(int count)
{
  static std::vector<std::shared_ptr<const amcr::PrototypeMemory>> memories(128);
  if (!memories[count])
    memories[count] = memoryOf(count);
  return memories[count];
}

const std::vector<cv::Mat>& staticFrames()
{
  static const std::vector<cv::Mat> sequence = [] {
    amcr_test::Scene scene;
    scene.objects.push_back({ShapeId::kArrow, amcr_test::makeAffine(amcr_test::prototypeCentre(), {320, 240},
                                                                     0.6, 0.9, 0.8, 0.2)});
    scene.clutter.silhouettes = {ShapeId::kEll, ShapeId::kFlag};
    return amcr_test::renderSequence(scene, 16);
  }();
  return sequence;
}

const std::vector<cv::Mat>& movingFrames()
{
  static const std::vector<cv::Mat> frames = [] {
    amcr_test::Scene scene;
    scene.objects.push_back({ShapeId::kArrow, movingPose(0)});
    scene.clutter.silhouettes = {ShapeId::kEll, ShapeId::kFlag};
    scene.clutter.seed = 301;
    return amcr_test::renderMovingSequence(scene, 200, [](int k) {
      return std::vector<amcr_test::Placement>{{ShapeId::kArrow, movingPose(k)}};
    });
  }();
  return frames;
}
}  // namespace amcr_bench
