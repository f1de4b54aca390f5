// amcr_index_rank SUITE [FRAME_STEP]: how well each index proposes the true
// place, recognizer-free. At points on each target (every 8th table px of
// its prototype, mapped by the truth) of every FRAME_STEP-th frame (default
// 20) of a benchmark suite (bench/make_sequences), a V-particle's scan with a
// random heading is put to the 8-ray index (proposal_index.h) and to the
// radial-profile index (profile_index.h); printed: the share of points each
// can read at all, and the share whose true place (8 table px, 2 bins) is the
// first candidate, among the first 8, among the first 64 (the profile
// index's ranked by alignment). Parameters are the defaults.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "amcr/scan/edge_thresholds.h"
#include "amcr/base/errors.h"
#include "amcr/base/params.h"
#include "amcr/filter/profile_index.h"
#include "amcr/filter/proposal_index.h"
#include "amcr/memory/prototype_memory.h"
#include "sequence_truth.h"

namespace
{
constexpr int kCandidates = 64;
constexpr int kPointStride = 8;     // table px between the points tried on a target
constexpr double kPlaceRadius = 8;  // table px
constexpr int kBins = 2;

struct Tally
{
  long readable = 0;
  long within[3] = {0, 0, 0};  // first, first 8, first 64
  void add(const std::vector<amcr::ProposalCandidate>& candidates, int p, const cv::Point& at, int bin)
  {
    ++readable;
    for (std::size_t r = 0; r < candidates.size(); ++r)
    {
      const amcr::ProposalCandidate& c = candidates[r];
      const int d = std::abs(c.bin - bin) % amcr::kDirectionBins;
      if (c.prototype == p && std::abs(c.x - at.x) <= kPlaceRadius && std::abs(c.y - at.y) <= kPlaceRadius &&
          std::min(d, amcr::kDirectionBins - d) <= kBins)
      {
        within[0] += r < 1;
        within[1] += r < 8;
        within[2] += 1;
        return;
      }
    }
  }
  void print(const char* name, long points) const
  {
    std::printf("  %-13s readable %5.1f%%; true place first %5.1f%%, in the first 8 %5.1f%%, in the first 64 %5.1f%%\n",
                name, 100.0 * readable / points, 100.0 * within[0] / points, 100.0 * within[1] / points,
                100.0 * within[2] / points);
  }
};
}  // namespace

int main(int argc, char** argv)
{
  if (argc < 2 || argc > 3)
  {
    std::cerr << "usage: amcr_index_rank SUITE_DIRECTORY [FRAME_STEP]\n";
    return 2;
  }
  const std::string suite = argv[1];
  const int frame_step = argc == 3 ? std::atoi(argv[2]) : 20;
  if (frame_step < 1)
  {
    std::cerr << "amcr_index_rank: FRAME_STEP must be a whole number of at least 1, got '" << argv[2] << "'\n";
    return 2;
  }
  try
  {
    const amcr::Params params;
    const amcr::PrototypeMemory memory = amcr::PrototypeMemory::loadDirectory(suite + "/prototypes", params);
    const amcr::ProposalIndex rays8(memory, params.index_stride);
    const amcr::ProfileIndex profiles(memory, std::max(1, params.index_stride / 2));
    std::mt19937 rng(5);
    long points = 0;
    Tally by_rays, by_profile;
    std::vector<std::filesystem::path> sequences;
    for (const auto& entry : std::filesystem::directory_iterator(suite))
      if (entry.path().filename().string().rfind("seq_", 0) == 0)
        sequences.push_back(entry.path());
    std::sort(sequences.begin(), sequences.end());
    for (const auto& sequence : sequences)
    {
      const std::vector<amcr_bench::TruthFrame> truth = amcr_bench::readSequenceTruth((sequence / "truth.json").string());
      for (std::size_t f = 0; f < truth.size(); f += frame_step)
      {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%04zu.png", f);
        const cv::Mat image = cv::imread((sequence / "frames" / name).string(), cv::IMREAD_GRAYSCALE);
        if (image.empty() || !truth[f].known)
          continue;
        const cv::Mat scan = amcr::prepareScanImage(image, params.blur_sigma);
        const amcr::RadialScanner scanner(
            scan, amcr::EdgeThresholds(scan, params.edge_threshold, params.edge_full_strength), params.max_ray_length);
        for (const amcr_bench::TruthObject& object : truth[f].objects)
        {
          const int p = memory.find(object.label);
          if (p < 0 || object.prototype_to_image.empty())
            continue;
          const amcr::Prototype& prototype = memory[p];
          const cv::Matx23d& t2o = prototype.tableToOriginal();
          const cv::Matx33d table_to_image =
              object.prototype_to_image[0] *
              cv::Matx33d(t2o(0, 0), t2o(0, 1), t2o(0, 2), t2o(1, 0), t2o(1, 1), t2o(1, 2), 0, 0, 1);
          const cv::Matx22d linear(table_to_image(0, 0), table_to_image(0, 1), table_to_image(1, 0),
                                   table_to_image(1, 1));
          const cv::Matx22d image_to_table = linear.inv();
          for (const cv::Point& at : prototype.interior())
          {
            if (at.x % kPointStride || at.y % kPointStride)
              continue;
            const cv::Vec3d q = table_to_image * cv::Vec3d(at.x, at.y, 1.0);
            const float x = static_cast<float>(q[0] / q[2]), y = static_cast<float>(q[1] / q[2]);
            if (!scanner.contains(x, y))
              continue;
            ++points;
            const float heading = std::uniform_real_distribution<float>(0.f, 2.f * static_cast<float>(M_PI))(rng);
            const cv::Vec2d direction = image_to_table * cv::Vec2d(std::cos(heading), std::sin(heading));
            const int bin = amcr::angleToBin(std::atan2(direction[1], direction[0]));
            amcr::RayHit hits[amcr::kFeatureRays];
            amcr::scanFeatureRays(scanner, x, y, heading, hits);
            const std::vector<amcr::ProposalCandidate> found8 = rays8.query(amcr::raySignature(hits), kCandidates);
            if (!found8.empty())
              by_rays.add(found8, p, at, bin);
            amcr::RadialProfile profile;
            if (amcr::scanProfile(scanner, x, y, heading, profile))
              by_profile.add(profiles.query(memory, profile, kCandidates, kCandidates), p, at, bin);
          }
        }
      }
    }
    if (points == 0)
    {
      std::cerr << "amcr_index_rank: no point of a target in memory was found in '" << suite << "'\n";
      return 1;
    }
    std::printf("%s: %ld points on targets (every %d table px, every %d frames)\n", suite.c_str(), points,
                kPointStride, frame_step);
    by_rays.print("8-ray index", points);
    by_profile.print("profile index", points);
    return 0;
  }
  catch (const std::exception& e)
  {
    std::cerr << "amcr_index_rank: " << e.what() << "\n";
    return 1;
  }
}
