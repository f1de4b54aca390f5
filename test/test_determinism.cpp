// Determinism: the recognizer's seeded generators (one stream per V-particle)
// are its only source of randomness, so one seed and one input give one
// output, bit for bit, whatever the number of threads.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/memory/prototype_memory.h"
#include "amcr/recognizer.h"
#include "scene_drawing.h"

namespace
{
using amcr_test::ShapeId;

amcr::Params params(std::uint64_t seed)
{
  amcr::Params p;  // the paper's counts: 30 V x 60 M per prototype
  p.seed = seed;
  return p;
}

// Built once (immutable; the tables take a while to build).
std::shared_ptr<const amcr::PrototypeMemory> threePrototypes()
{
  static const std::shared_ptr<const amcr::PrototypeMemory> memory = [] {
    auto built = std::make_shared<amcr::PrototypeMemory>();
    for (ShapeId id : {ShapeId::kArrow, ShapeId::kCrescent, ShapeId::kStar})
      built->add(amcr_test::shapeName(id), amcr_test::drawPrototype(id), amcr::Params());
    return built;
  }();
  return memory;
}

// 25 frames (V-resampling happens at 10 and 20) of the crescent over clutter.
std::vector<cv::Mat> sequence()
{
  amcr_test::Scene scene;
  scene.objects.push_back({ShapeId::kCrescent, amcr_test::makeAffine(amcr_test::prototypeCentre(), {300, 250}, -0.6,
                                                                     0.9, 0.8, 0.2)});
  scene.clutter.silhouettes = {ShapeId::kEll, ShapeId::kFlag};
  scene.clutter.seed = 21;
  return amcr_test::renderSequence(scene, 25);
}

template <typename T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b)
{
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

bool sameBits(const amcr::Affine& a, const amcr::Affine& b) { return std::memcmp(a.val, b.val, sizeof(a.val)) == 0; }

// Every field of the V-particles and M-particles, bitwise.
void expectSameState(const amcr::Recognizer& a, const amcr::Recognizer& b, int frame)
{
  const auto& va = a.vParticles();
  const auto& vb = b.vParticles();
  ASSERT_EQ(va.size(), vb.size()) << "frame " << frame;
  for (std::size_t i = 0; i < va.size(); ++i)
  {
    EXPECT_EQ(std::memcmp(&va[i].x, &vb[i].x, sizeof(float)), 0) << "frame " << frame << " V " << i;
    EXPECT_EQ(std::memcmp(&va[i].y, &vb[i].y, sizeof(float)), 0) << "frame " << frame << " V " << i;
    EXPECT_EQ(std::memcmp(&va[i].theta, &vb[i].theta, sizeof(float)), 0) << "frame " << frame << " V " << i;
    EXPECT_EQ(std::memcmp(&va[i].log_evidence_sum, &vb[i].log_evidence_sum, sizeof(double)), 0)
        << "frame " << frame << " V " << i;
    EXPECT_EQ(va[i].evidence_count, vb[i].evidence_count);
    EXPECT_EQ(va[i].age, vb[i].age);
  }
  const amcr::MParticleSet& ma = a.mParticles();
  const amcr::MParticleSet& mb = b.mParticles();
  EXPECT_TRUE(sameBits(ma.x, mb.x)) << "frame " << frame;
  EXPECT_TRUE(sameBits(ma.y, mb.y)) << "frame " << frame;
  EXPECT_TRUE(sameBits(ma.theta, mb.theta)) << "frame " << frame;
  EXPECT_TRUE(sameBits(ma.prototype, mb.prototype)) << "frame " << frame;
  EXPECT_TRUE(sameBits(ma.affine_valid, mb.affine_valid)) << "frame " << frame;
  EXPECT_TRUE(sameBits(ma.log_likelihood, mb.log_likelihood)) << "frame " << frame;
  for (int k = 0; k < 6; ++k)
    EXPECT_TRUE(sameBits(ma.affine[k], mb.affine[k])) << "frame " << frame << " affine " << k;
  for (int k = 0; k < 3; ++k)
    EXPECT_TRUE(sameBits(ma.shape[k], mb.shape[k])) << "frame " << frame << " shape " << k;
}

/// The two results agree bitwise; track ids too, unless `track_offset` is
/// given: then b's ids are a's plus one offset throughout (a recognizer
/// never reuses a track id, not even after a reset), set by the first object.
void expectSameResult(const amcr::RecognitionResult& a, const amcr::RecognitionResult& b, int frame,
                      int* track_offset = nullptr)
{
  EXPECT_EQ(a.iteration, b.iteration);
  EXPECT_EQ(a.converged_v_particles, b.converged_v_particles) << "frame " << frame;
  ASSERT_EQ(a.objects.size(), b.objects.size()) << "frame " << frame;
  for (std::size_t i = 0; i < a.objects.size(); ++i)
  {
    const amcr::RecognizedObject& oa = a.objects[i];
    const amcr::RecognizedObject& ob = b.objects[i];
    EXPECT_EQ(oa.label, ob.label) << "frame " << frame;
    EXPECT_EQ(oa.prototype_id, ob.prototype_id);
    if (!track_offset)
      EXPECT_EQ(oa.track_id, ob.track_id);
    else if (*track_offset < 0)
      *track_offset = ob.track_id - oa.track_id;
    else
      EXPECT_EQ(ob.track_id - oa.track_id, *track_offset) << "frame " << frame;
    EXPECT_EQ(oa.support, ob.support);
    EXPECT_EQ(std::memcmp(&oa.score, &ob.score, sizeof(double)), 0) << "frame " << frame;
    EXPECT_TRUE(sameBits(oa.prototype_to_image, ob.prototype_to_image)) << "frame " << frame;
    EXPECT_TRUE(sameBits(oa.image_to_prototype, ob.image_to_prototype)) << "frame " << frame;
    ASSERT_EQ(oa.correspondences.size(), ob.correspondences.size());
    for (std::size_t j = 0; j < oa.correspondences.size(); ++j)
    {
      EXPECT_EQ(oa.correspondences[j].image, ob.correspondences[j].image);
      EXPECT_EQ(oa.correspondences[j].prototype, ob.correspondences[j].prototype);
    }
  }
}

TEST(Determinism, SameSeedSameResults)
{
  const auto memory = threePrototypes();
  const std::vector<cv::Mat> frames = sequence();
  amcr::Recognizer a(params(17), memory), b(params(17), memory);
  for (std::size_t k = 0; k < frames.size(); ++k)
  {
    // b gets its own copy of the frame: nothing may depend on the buffer's address.
    const amcr::RecognitionResult ra = a.step(frames[k]);
    const amcr::RecognitionResult rb = b.step(frames[k].clone());
    expectSameResult(ra, rb, static_cast<int>(k));
    expectSameState(a, b, static_cast<int>(k));
    if (::testing::Test::HasFailure())
      FAIL() << "diverged at frame " << k;
  }
}

TEST(Determinism, ResetReplaysTheRun)
{
  const auto memory = threePrototypes();
  const std::vector<cv::Mat> frames = sequence();
  amcr::Recognizer fresh(params(5), memory), reused(params(5), memory);
  // `reused` first sees other frames, then forgets them.
  for (int k = 0; k < 7; ++k)
    reused.step(frames[(k * 3) % frames.size()]);
  reused.reset();
  EXPECT_EQ(reused.iteration(), 0);
  int track_offset = -1;
  for (std::size_t k = 0; k < 12; ++k)
  {
    const amcr::RecognitionResult ra = fresh.step(frames[k]);
    const amcr::RecognitionResult rb = reused.step(frames[k]);
    expectSameResult(ra, rb, static_cast<int>(k), &track_offset);
    expectSameState(fresh, reused, static_cast<int>(k));
    if (::testing::Test::HasFailure())
      FAIL() << "diverged at frame " << k;
  }
}

/// Three crescents sliding to the right over clutter: the flow moves the
/// V-particles, the copies are confirmed and held, V-resampling keeps a few
/// on each.
std::vector<cv::Mat> movingCopies(int frames)
{
  const auto placements = [](int k) {
    const cv::Point2d centres[3] = {{140, 160}, {330, 330}, {470, 140}};
    std::vector<amcr_test::Placement> copies;
    for (int i = 0; i < 3; ++i)
      copies.push_back({ShapeId::kCrescent,
                        amcr_test::makeAffine(amcr_test::prototypeCentre(), centres[i] + cv::Point2d(2.0 * k, 0.5 * k),
                                              (40.0 + 100.0 * i) * M_PI / 180.0, 0.55, 0.5, 0.05)});
    return copies;
  };
  amcr_test::Scene scene;
  scene.objects = placements(0);
  scene.clutter.silhouettes = {ShapeId::kEll, ShapeId::kFlag};
  scene.clutter.seed = 5;
  return amcr_test::renderMovingSequence(scene, frames, placements);
}

/// Runs `frames` through recognizers of 1, 2 and 4 threads and expects the
/// same results and particles, bit for bit, after every frame. Returns the
/// most objects held at once.
std::size_t expectSameForAnyThreadCount(const std::vector<cv::Mat>& frames, std::uint64_t seed)
{
  std::vector<std::unique_ptr<amcr::Recognizer>> recognizers;
  for (int threads : {1, 2, 4})
  {
    amcr::Params p = params(seed);
    p.num_threads = threads;
    recognizers.push_back(std::make_unique<amcr::Recognizer>(p, threePrototypes()));
  }
  std::size_t most_held = 0;
  for (std::size_t k = 0; k < frames.size(); ++k)
  {
    const amcr::RecognitionResult one = recognizers[0]->step(frames[k]);
    std::size_t held = 0;
    for (const amcr::RecognizedObject& object : one.objects)
      held += object.state == amcr::ObjectState::kHeld;
    most_held = std::max(most_held, held);
    for (std::size_t r = 1; r < recognizers.size(); ++r)
    {
      SCOPED_TRACE(r == 1 ? "2 threads" : "4 threads");
      expectSameResult(one, recognizers[r]->step(frames[k]), static_cast<int>(k));
      expectSameState(*recognizers[0], *recognizers[r], static_cast<int>(k));
    }
    if (::testing::Test::HasFailure())
    {
      ADD_FAILURE() << "diverged at frame " << k;
      break;
    }
  }
  return most_held;
}

TEST(Determinism, SameResultsOnAnyNumberOfThreads)
{
  expectSameForAnyThreadCount(sequence(), 17);
}

TEST(Determinism, SameResultsOnAnyNumberOfThreadsWithHeldObjects)
{
  const std::size_t most_held = expectSameForAnyThreadCount(movingCopies(40), 3);
  EXPECT_GE(most_held, 1u) << "no copy was held: the held objects' attention was not exercised";
}

TEST(Determinism, DifferentSeedDifferentParticles)
{
  const auto memory = threePrototypes();
  const std::vector<cv::Mat> frames = sequence();
  amcr::Recognizer a(params(17), memory), b(params(18), memory);
  a.step(frames[0]);
  b.step(frames[0]);
  ASSERT_EQ(a.vParticles().size(), b.vParticles().size());
  int same_v = 0;
  for (std::size_t i = 0; i < a.vParticles().size(); ++i)
    same_v += a.vParticles()[i].x == b.vParticles()[i].x && a.vParticles()[i].y == b.vParticles()[i].y;
  EXPECT_EQ(same_v, 0) << "V-particles at the same place with different seeds";
  EXPECT_FALSE(sameBits(a.mParticles().x, b.mParticles().x));
  EXPECT_FALSE(sameBits(a.mParticles().theta, b.mParticles().theta));
}
}  // namespace
