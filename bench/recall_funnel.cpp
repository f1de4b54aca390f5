#include "recall_funnel.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

#include "amcr/extraction/object_extraction.h"
#include "amcr/extraction/object_extractor.h"
#include "amcr/filter/proposal_index.h"

namespace amcr_bench
{
namespace
{
constexpr double kRadToDeg = 180.0 / M_PI;

cv::Point2d project(const cv::Matx33d& h, const cv::Point2d& p)
{
  const cv::Vec3d q = h * cv::Vec3d(p.x, p.y, 1.0);
  return {q[0] / q[2], q[1] / q[2]};
}

double headingDifferenceDeg(double a, double b)
{
  return std::abs(amcr::wrapAngle(a - b)) * kRadToDeg;
}

/// Where a point of the input lies in one prototype's table under one truth map, and the table
/// heading of an input heading there.
struct TruePlace
{
  int prototype = -1;
  cv::Matx33d input_to_table;
  cv::Point2d at(const cv::Point2d& input) const { return project(input_to_table, input); }
  /// The table direction of the input direction `theta` at `input` (the map's local linear part).
  double heading(const cv::Point2d& input, double theta) const
  {
    const cv::Point2d a = at(input);
    const cv::Point2d b = at(input + cv::Point2d(std::cos(theta), std::sin(theta)));
    return std::atan2(b.y - a.y, b.x - a.x);
  }
};

/// Whether prototype `p` is the very shape shown: of the object's label and image size, and,
/// where the memory holds several instances of the label (a label directory), the instance drawn
/// from the truth's source image (the shown instance may be held out of the memory).
/// `label_instances`: how many prototypes of the label the memory holds.
bool isShownShape(const amcr::Prototype& prototype, int label_instances, const TruthObject& object)
{
  if (prototype.label() != object.label || prototype.originalSize() != object.prototype_size)
    return false;
  if (label_instances == 1)
    return true;
  const std::string& instance = prototype.instance();
  const std::string file = instance.substr(instance.find_last_of('/') + 1);
  return !object.source.empty() && file == object.source;
}

/// Every (prototype, truth map) pair under which the object's true place is judged.
std::vector<TruePlace> truePlaces(const amcr::PrototypeMemory& memory, const TruthObject& object)
{
  int label_instances = 0;
  for (std::size_t p = 0; p < memory.size(); ++p)
    label_instances += memory[p].label() == object.label ? 1 : 0;
  std::vector<TruePlace> places;
  for (std::size_t p = 0; p < memory.size(); ++p)
  {
    if (!isShownShape(memory[p], label_instances, object))
      continue;
    const cv::Matx23d& o2t = memory[p].originalToTable();
    const cv::Matx33d original_to_table(o2t(0, 0), o2t(0, 1), o2t(0, 2), o2t(1, 0), o2t(1, 1), o2t(1, 2), 0, 0, 1);
    for (const cv::Matx33d& map : object.prototype_to_image)
      places.push_back({static_cast<int>(p), original_to_table * map.inv()});
  }
  return places;
}

bool insideSilhouette(const amcr::Prototype& p, const cv::Point2d& table)
{
  const int x = static_cast<int>(std::lround(table.x)), y = static_cast<int>(std::lround(table.y));
  return x >= 0 && y >= 0 && x < p.width() && y < p.height() && p.mask().at<std::uint8_t>(y, x) != 0;
}

/// Whether `object` (a report or a verified candidate) lies at the object's place: every corner of
/// the prototype within corner_share of the object's image diagonal, under any of the truth maps.
bool atRightPlace(const amcr::RecognizedObject& object, const TruthObject& truth, const FunnelTolerance& tolerance)
{
  if (object.label != truth.label)
    return false;
  const double w = truth.prototype_size.width - 1.0, h = truth.prototype_size.height - 1.0;
  const cv::Point2d corners[4] = {{0, 0}, {w, 0}, {w, h}, {0, h}};
  for (const cv::Matx33d& map : truth.prototype_to_image)
  {
    cv::Point2d truth_corners[4];
    for (int c = 0; c < 4; ++c)
      truth_corners[c] = project(map, corners[c]);
    const double diagonal =
        0.5 * (cv::norm(truth_corners[2] - truth_corners[0]) + cv::norm(truth_corners[3] - truth_corners[1]));
    double worst = 0.0;
    for (int c = 0; c < 4; ++c)
      worst = std::max(worst, cv::norm(project(object.homography, corners[c]) - truth_corners[c]));
    if (worst <= tolerance.corner_share * diagonal)
      return true;
  }
  return false;
}

/// The stages of the filter (on object ... cluster) for one object.
void measureParticles(const amcr::Recognizer& recognizer, const std::vector<TruePlace>& places,
                      const std::vector<amcr::VParticleCluster>& clusters, const FunnelTolerance& tolerance,
                      ObjectFunnel& funnel)
{
  const amcr::ParticleFilter& filter = recognizer.filter();
  const amcr::PrototypeMemory& memory = filter.memory();
  const amcr::MParticleSet& m = filter.mParticles();
  const std::vector<amcr::VParticle>& v = filter.vParticles();
  const amcr::Affine to_input = recognizer.workingScale().toInput();
  const amcr::ProposalIndex* index = filter.proposalIndex();
  // Where a V-particle lies in the prototype under one truth map: its true place and heading.
  struct OnPlace
  {
    int prototype;
    cv::Point2d table;
    double heading;
    /// Whether a hypothesis at (x, y) with heading `theta` is near it.
    bool near(double x, double y, double theta, const FunnelTolerance& tolerance) const
    {
      return std::hypot(x - table.x, y - table.y) <= tolerance.table_px &&
             headingDifferenceDeg(theta, heading) <= tolerance.heading_deg;
    }
  };
  for (std::size_t i = 0; i < v.size(); ++i)
  {
    const cv::Point2d input = amcr::applyAffine(to_input, cv::Point2d(v[i].x, v[i].y));
    // The truth maps under which this V-particle lies on the object, with its true place there.
    std::vector<OnPlace> on;
    for (const TruePlace& place : places)
    {
      const cv::Point2d table = place.at(input);
      if (insideSilhouette(memory[place.prototype], table))
        on.push_back({place.prototype, table, place.heading(input, v[i].theta)});
    }
    if (on.empty())
      continue;
    ++funnel.v_on;
    amcr::RayDescriptor descriptor;
    if (amcr::describeRays(v[i].rays, descriptor))
    {
      ++funnel.v_indexable;
      if (index != nullptr)
      {
        const std::vector<amcr::ProposalCandidate> candidates =
            index->query(v[i].rays, filter.params().index_candidates);
        for (std::size_t rank = 0; rank < candidates.size(); ++rank)
        {
          const amcr::ProposalCandidate& c = candidates[rank];
          const bool hit = std::any_of(on.begin(), on.end(), [&](const OnPlace& place) {
            return place.prototype == c.prototype && place.near(c.x, c.y, amcr::binToAngle(c.bin), tolerance);
          });
          if (hit)
          {
            ++funnel.v_proposed;
            if (funnel.best_rank < 0 || static_cast<int>(rank) < funnel.best_rank)
              funnel.best_rank = static_cast<int>(rank);
            break;
          }
        }
      }
    }
    // Near M-particles: fresh ones (seeded at this iteration's resampling, not measured yet)
    // were proposed; measured ones (a fitted affine) survived a resampling.
    int near_measured = 0;
    bool near_fresh = false;
    float best_near_likelihood = -std::numeric_limits<float>::infinity();
    const amcr::MRange range = filter.mRange(static_cast<int>(i));
    for (std::size_t k = range.begin; k < range.end; ++k)
    {
      bool near_here = false;
      for (const OnPlace& place : on)
      {
        if (m.prototype[k] != place.prototype)
          continue;
        const double distance = std::hypot(m.x[k] - place.table.x, m.y[k] - place.table.y);
        if (funnel.best_table_px < 0 || distance < funnel.best_table_px)
        {
          funnel.best_table_px = distance;
          funnel.best_heading_deg = headingDifferenceDeg(m.theta[k], place.heading);
        }
        near_here = near_here || place.near(m.x[k], m.y[k], m.theta[k], tolerance);
      }
      if (!near_here)
        continue;
      if (m.affine_valid[k] != amcr::kFittedAffine)
      {
        near_fresh = true;
        continue;
      }
      ++near_measured;
      best_near_likelihood = std::max(best_near_likelihood, m.log_likelihood[k]);
    }
    funnel.v_fresh += near_fresh ? 1 : 0;
    funnel.v_alive += near_measured > 0 ? 1 : 0;
    if (near_measured > 0)
    {
      funnel.best_share = std::max(funnel.best_share, static_cast<double>(near_measured) / range.size());
      // How the likelihood of the last update ranks the best near hypothesis among all of the
      // V-particle's: 0 when none is more likely.
      int above = 0;
      for (std::size_t k = range.begin; k < range.end; ++k)
        above += m.log_likelihood[k] > best_near_likelihood ? 1 : 0;
      const double quantile = static_cast<double>(above) / range.size();
      funnel.best_likelihood_quantile =
          funnel.best_likelihood_quantile < 0 ? quantile : std::min(funnel.best_likelihood_quantile, quantile);
    }
    const amcr::VParticleCluster& c = clusters[i];
    const bool cluster = c.converged &&
                         std::any_of(on.begin(), on.end(), [&](const OnPlace& place) {
                           return place.prototype == c.prototype &&
                                  std::hypot(c.mean.x - place.table.x, c.mean.y - place.table.y) <= tolerance.table_px;
                         });
    funnel.v_cluster += cluster ? 1 : 0;
  }
}

/// Two decimals are what the report reads.
double rounded(double v) { return std::round(v * 100.0) / 100.0; }
}  // namespace

const char* stageName(FunnelStage stage)
{
  switch (stage)
  {
    case FunnelStage::kOnObject: return "on_object";
    case FunnelStage::kProposed: return "proposed";
    case FunnelStage::kAlive: return "alive";
    case FunnelStage::kCluster: return "cluster";
    case FunnelStage::kVerified: return "verified";
    case FunnelStage::kPassed: return "passed";
    case FunnelStage::kReported: return "reported";
  }
  return "?";
}

bool ObjectFunnel::reached(FunnelStage stage) const
{
  switch (stage)
  {
    case FunnelStage::kOnObject: return v_on > 0;
    case FunnelStage::kProposed: return v_proposed > 0 || v_fresh > 0 || v_alive > 0;
    case FunnelStage::kAlive: return v_alive > 0;
    case FunnelStage::kCluster: return v_cluster > 0;
    case FunnelStage::kVerified: return candidate_score >= 0.0;
    case FunnelStage::kPassed: return passed;
    case FunnelStage::kReported: return reported;
  }
  return false;
}

std::vector<ObjectFunnel> measureFunnel(const amcr::Recognizer& recognizer, const amcr::RecognitionResult& result,
                                        const TruthFrame& truth, const FunnelTolerance& tolerance)
{
  std::vector<ObjectFunnel> funnels;
  if (!truth.known)
    return funnels;
  const std::vector<amcr::VParticleCluster> clusters = amcr::filterClusters(recognizer.filter());
  for (const TruthObject& object : truth.objects)
  {
    ObjectFunnel funnel;
    funnel.label = object.label;
    const std::vector<TruePlace> places = truePlaces(recognizer.memory(), object);
    funnel.in_memory = !places.empty();
    if (funnel.in_memory)
      measureParticles(recognizer, places, clusters, tolerance, funnel);
    for (const amcr::RecognizedObject& r : result.objects)
      funnel.reported = funnel.reported || (funnel.in_memory ? atRightPlace(r, object, tolerance) : r.label == object.label);
    for (const amcr::RecognizedObject& c : recognizer.verifiedCandidates())
      if (funnel.in_memory ? atRightPlace(c, object, tolerance) : c.label == object.label)
        funnel.candidate_score = std::max(funnel.candidate_score, c.score);
    funnel.passed = funnel.reported || funnel.candidate_score >= recognizer.params().decision_threshold;
    funnels.push_back(std::move(funnel));
  }
  return funnels;
}

void FunnelRecorder::add(int frame, const std::vector<ObjectFunnel>& objects)
{
  if (summaries_.size() < objects.size())
    summaries_.resize(objects.size());
  for (std::size_t k = 0; k < objects.size(); ++k)
  {
    FunnelSummary& s = summaries_[k];
    s.label = objects[k].label;
    ++s.frames;
    for (int stage = 0; stage < kFunnelStages; ++stage)
      if (objects[k].reached(static_cast<FunnelStage>(stage)))
      {
        ++s.reached[stage];
        if (s.first_frame[stage] == 0)
          s.first_frame[stage] = frame + 1;
      }
    s.first_missing = -1;
    for (int stage = 0; stage < kFunnelStages && s.first_missing < 0; ++stage)
      if (s.reached[stage] == 0)
        s.first_missing = stage;
  }
}

std::string funnelJson(int frame, const std::vector<ObjectFunnel>& objects)
{
  nlohmann::json line = {{"frame", frame}, {"objects", nlohmann::json::array()}};
  for (const ObjectFunnel& o : objects)
  {
    nlohmann::json stages = nlohmann::json::array();
    for (int stage = 0; stage < kFunnelStages; ++stage)
      stages.push_back(o.reached(static_cast<FunnelStage>(stage)) ? 1 : 0);
    line["objects"].push_back({{"label", o.label},
                               {"in_memory", o.in_memory},
                               {"v_on", o.v_on},
                               {"v_indexable", o.v_indexable},
                               {"v_proposed", o.v_proposed},
                               {"best_rank", o.best_rank},
                               {"v_fresh", o.v_fresh},
                               {"v_alive", o.v_alive},
                               {"v_cluster", o.v_cluster},
                               {"best_table_px", rounded(o.best_table_px)},
                               {"best_heading_deg", rounded(o.best_heading_deg)},
                               {"best_share", rounded(o.best_share)},
                               {"best_likelihood_quantile", rounded(o.best_likelihood_quantile)},
                               {"candidate_score", rounded(o.candidate_score)},
                               {"passed", o.passed},
                               {"reported", o.reported},
                               {"stages", stages}});
  }
  return line.dump();
}

std::string funnelSummaryJson(const std::vector<FunnelSummary>& summaries)
{
  nlohmann::json list = nlohmann::json::array();
  for (const FunnelSummary& f : summaries)
  {
    nlohmann::json reached, first;
    for (int stage = 0; stage < kFunnelStages; ++stage)
    {
      reached[stageName(static_cast<FunnelStage>(stage))] = f.reached[stage];
      first[stageName(static_cast<FunnelStage>(stage))] = f.first_frame[stage];
    }
    const nlohmann::json first_missing =
        f.first_missing < 0 ? nlohmann::json(nullptr)
                            : nlohmann::json(stageName(static_cast<FunnelStage>(f.first_missing)));
    list.push_back({{"label", f.label},
                    {"frames", f.frames},
                    {"reached", reached},
                    {"first_frame", first},
                    {"first_missing", first_missing}});
  }
  return nlohmann::json{{"summary", list}}.dump();
}
}  // namespace amcr_bench
