#include "amcr/base/params.h"

#include <cmath>
#include <functional>
#include <iomanip>
#include <sstream>
#include <utility>

#include "amcr/base/errors.h"
#include "amcr/base/resource_bounds.h"

namespace amcr
{
namespace
{
/// One numeric parameter: its description and how to read and write it.
struct NumericParameter
{
  ParameterInfo info;
  std::function<double(const Params&)> get;
  std::function<void(Params&, double)> set;
  bool integer;
};

#define AMCR_DOUBLE(field, unit, lo, hi, text)                                                       \
  NumericParameter                                                                                   \
  {                                                                                                  \
    {#field, unit, lo, hi, text}, [](const Params& p) { return static_cast<double>(p.field); },     \
        [](Params& p, double v) { p.field = v; }, false                                              \
  }
#define AMCR_INT(field, unit, lo, hi, text)                                                          \
  NumericParameter                                                                                   \
  {                                                                                                  \
    {#field, unit, lo, hi, text}, [](const Params& p) { return static_cast<double>(p.field); },     \
        [](Params& p, double v) { p.field = static_cast<decltype(p.field)>(std::llround(v)); }, true \
  }

/// `p`, marked as a parameter the prototype memory is built with.
NumericParameter buildsTables(NumericParameter p)
{
  p.info.builds_tables = true;
  return p;
}

const std::vector<NumericParameter>& numericParameters()
{
  static const std::vector<NumericParameter> table = {
      AMCR_INT(num_v_particles, "", 1, 5000, "V-particles in the input image; paper 30"),
      AMCR_INT(m_particles_per_prototype, "", 1, 5000, "M-particles per prototype per V-particle; paper 60"),
      AMCR_INT(m_particles_per_v, "", 0, 100000, "M-particle budget of a V-particle, shared among the prototypes; 0 = m_particles_per_prototype per prototype (paper)"),
      AMCR_INT(min_m_particles_per_v, "", 1, 100000, "fewest M-particles KLD-sampling leaves a V-particle"),
      AMCR_DOUBLE(kld_error, "", 0, 1, "KLD-sampling's bound on the KL divergence between the particles and the posterior (Fox 2003); 0 = a fixed count"),
      AMCR_DOUBLE(kld_z, "", 0, 10, "KLD-sampling's upper standard normal quantile (2.33: 99%)"),
      AMCR_DOUBLE(index_share, "", 0, 1, "share of new M-particles drawn from the proposal index; 0 = none (paper)"),
      AMCR_DOUBLE(proposal_correction, "", 0, 1, "exponent of the importance weight pi/q of a new M-particle under the mixture proposal; 1 = exact importance sampling, 0 = sensor resetting"),
      AMCR_INT(index_stride, "prototype px", 1, 64, "distance between the indexed points of a prototype"),
      AMCR_INT(index_candidates, "", 1, 1000, "places of the memory a V-particle's query returns"),
      AMCR_INT(profile_index, "", 0, 1, "1: the frontal candidates are the best aligned 8 of the index_candidates places nearest in radial-profile key (72 rays); 0: from the 8-ray index"),
      AMCR_INT(index_max_entries, "", 0, 1e9, "most entries of the proposal index; a larger memory is indexed at a larger stride; 0 = no limit"),
      buildsTables(AMCR_INT(prototype_size, "px", 32, 512, "longer side of a prototype in its lookup table")),
      buildsTables(AMCR_INT(table_stride, "table px", 0, 4, "spacing of the lookup table's nodes; 1 = every pixel (exact), s = one per s x s block (s^2 less memory and build time); 0 = the smallest stride whose tables fit table_budget_mb")),
      buildsTables(AMCR_INT(table_budget_mb, "MB", 16, 4096, "most memory the lookup tables may take when table_stride is 0; a given table_stride above it is used with a warning")),
      AMCR_DOUBLE(max_ray_length, "working px", 10, 4000, "longest radial scan in the working image"),
      buildsTables(AMCR_DOUBLE(edge_threshold, "grey levels", 1, 255, "step over 2 px that counts as an edge where the local edge strength reaches edge_full_strength")),
      buildsTables(AMCR_DOUBLE(edge_full_strength, "grey levels", 0, 255, "local edge strength (99th percentile of the 2 px steps within about 50 px) at which edge_threshold applies in full; below it the threshold falls in proportion, down to 5 sigma of the frame's step noise; 0 = edge_threshold everywhere")),
      buildsTables(AMCR_DOUBLE(blur_sigma, "working px", 0, 10, "Gaussian smoothing of the working image before scanning")),
      buildsTables(AMCR_INT(keep_polarity, "", 0, 1, "1: a grey template's edges count only where the grey rises across them as in the template; 0: the polarity most of its points show (a part in reversed contrast is found); silhouettes: no effect")),
      AMCR_INT(working_resolution, "input px", 0, 4000, "longer side of the working image: a larger input is reduced to it (never enlarged) and the results mapped back to input px; every other length in px is of the working image, except min_object_size; 0 = the input's own size"),
      AMCR_DOUBLE(sigma_w, "px", 1e-3, 1000, "std. dev. of a ray's deviation (eq. 5); paper 10"),
      AMCR_DOUBLE(p_outlier, "", 0, 1, "probability that a ray is an outlier (eq. 5); paper 0.1"),
      AMCR_DOUBLE(p_invalid, "", 0, 1, "probability of an invalid ray (eq. 6); paper 0.1"),
      AMCR_DOUBLE(min_triangle_area, "working px^2", 0, 1e6, "smaller affine triangles are degenerate"),
      AMCR_DOUBLE(max_affine_scale, "", 1, 100, "largest accepted scale of A, either way"),
      AMCR_INT(affine_refits, "", 0, 5, "re-estimates of A from the affine-corrected triangle rays (ray_correspondence affine)"),
      AMCR_DOUBLE(max_anisotropy, "", 1, 10, "largest anisotropy (singular value ratio; 3 = 70 deg off the normal) of the view shapes new M-particles get (ray_correspondence affine) and of a new object reported; 1 = frontal only"),
      AMCR_DOUBLE(oblique_share, "", 0, 1, "share of new M-particles given an oblique view shape, and of index candidates read under one; the rest frontal (ray_correspondence affine)"),
      AMCR_DOUBLE(motion_noise_shape, "", 0, 1, "M-particle view-shape noise per iteration, about the change of log anisotropy (ray_correspondence affine)"),
      AMCR_DOUBLE(v_step, "working px", 0, 100, "forward step of a V-particle per iteration"),
      AMCR_DOUBLE(motion_noise_translation, "prototype px", 0, 100, "M-particle translation noise"),
      AMCR_DOUBLE(motion_noise_rotation, "rad", 0, 3.15, "M-particle rotation noise"),
      AMCR_DOUBLE(reflection_jitter, "rad", 0, 3.15, "largest random turn added at a reflection"),
      AMCR_INT(discriminative_moves, "", 0, 1, "1: a V-particle deciding between M-clusters moves where their predicted scans differ most"),
      AMCR_INT(discriminative_places, "", 0, 1, "1: with discriminative_moves, a V-particle heads for the nearest precomputed place where its look-alikes differ"),
      AMCR_DOUBLE(discriminative_min_share, "", 0, 1, "share of a V-particle's M-particles a competing cluster needs"),
      AMCR_DOUBLE(discriminative_min_gain, "nats", 0, 100, "least expected log-likelihood ratio for which a discriminative move is made"),
      AMCR_INT(competing_fits, "", 0, 64, "competing clusters of V-particles, then look-alikes of tracked objects, fitted and verified per frame beside the groups"),
      AMCR_INT(likeliest_fits, "", 0, 64, "modes about the most likely M-particle of V-particles that have not converged, fitted per frame; 0 = off"),
      AMCR_INT(pose_vote_fits, "", 0, 64, "pools of pose votes (the rays of V-particles and of the coverage lattice's places in the proposal index) fitted per frame; 0 = off"),
      AMCR_INT(coverage_frames, "frames", 0, 100, "K: frames in which a lattice of places a third of min_object_size apart covers the image for pose votes; 0 = V-particles only"),
      AMCR_INT(v_resample_interval, "iterations", 1, 1000, "w: V-particles are resampled every w iterations; paper 10"),
      AMCR_DOUBLE(v_reseed_fraction, "", 0, 1, "share of V-particles re-seeded at V-resampling"),
      AMCR_DOUBLE(m_reseed_fraction, "", 0, 1, "share of M-particles re-seeded uniformly per iteration"),
      AMCR_DOUBLE(injection_fraction, "", 0, 1, "share of M-particles placed at leading hypotheses"),
      AMCR_INT(seed_enclosure_rays, "rays", 0, 8, "rays of 8 that must hit an edge where a V-particle is seeded"),
      AMCR_INT(seed_attempts, "", 1, 1000, "tries to find an enclosed place for a new V-particle"),
      AMCR_DOUBLE(cluster_radius, "prototype px", 0.5, 100, "radius of an M-particle cluster"),
      AMCR_DOUBLE(cluster_min_share, "", 0, 1, "share of a V-particle's M-particles its cluster needs"),
      AMCR_DOUBLE(group_tolerance, "working px", 0.5, 200, "V-particles agree on an object within this distance"),
      AMCR_INT(min_support, "V-particles", 1, 5000, "V-particles an object needs"),
      AMCR_INT(refine_iterations, "", 0, 100, "outline-to-edge refinement passes of the affine"),
      AMCR_DOUBLE(refine_search, "working px", 0, 100, "search along the outline normal for an edge"),
      AMCR_INT(fit_homography, "", 0, 1, "1: a homography is fitted after the affine and used when the outline demands it"),
      AMCR_DOUBLE(decision_threshold, "", 0, 1, "smallest score reported"),
      AMCR_DOUBLE(verify_tolerance, "working px", 0.5, 20, "distance along the outline's normal within which an outline point finds its image edge in the score"),
      AMCR_DOUBLE(verify_relative_tolerance, "share of the object's size", 0, 0.1, "the score's tolerance as a share of the longer side of the object's outline box: the smaller of it and verify_tolerance applies, never below 1 px; 0 = verify_tolerance at every size"),
      AMCR_DOUBLE(rival_part_support, "share", 0, 1, "share of the outline points that tell the prototype from its generic rivals (an ellipse, its convex hull, its rectangle, a pair of lines) that must lie on image edges for a report; 0 = off"),
      AMCR_DOUBLE(part_shift, "share of the object's size", 0, 0.2, "how far an inner part of the prototype's outline (a hole's) may move and scale on its own onto its edges before the score counts it; 0 = the outline moves as one"),
      AMCR_DOUBLE(min_visible_share, "share", 0, 1, "smallest share of a new object's outline that must be visible, the rest covered by something in front of it; the score is then the share of the visible outline on edges (a tracked object needs 0.65 of it); 1 = none counts as covered"),
      AMCR_DOUBLE(min_object_size, "input px", 0, 4000, "smallest object reported: longer side of the smallest rectangle around its outline"),
      AMCR_INT(confirm_frames, "frames", 1, 1000, "frames an object is reported in before it is confirmed (tentative until then)"),
      AMCR_INT(lost_frames, "frames", 1, 1000, "frames in a row without a report after which an object's track ends (lost)"),
      AMCR_INT(recall_frames, "frames", 0, 10000, "frames after its end during which a lost track's id is given back to an object of its label found where it was last; 0 = never"),
      AMCR_INT(max_objects, "", 1, 256, "tracks kept at once, coasting ones included; no new object is reported beyond"),
      AMCR_INT(held_v_particles, "V-particles", 0, 5000, "V-particles a held object keeps at V-resampling; the rest look elsewhere"),
      AMCR_DOUBLE(scene_prior_share, "", 0, 1, "share of new M-particles drawn in the prototypes of the held objects (copies of what is in view are likely); 0 = the context prior alone"),
      AMCR_INT(optical_flow, "", 0, 1, "1: V-particles ride the pyramidal Lucas-Kanade flow between frames"),
      AMCR_INT(flow_window, "working px", 5, 101, "side of the Lucas-Kanade window"),
      AMCR_INT(flow_levels, "", 0, 8, "pyramid levels of the optical flow above the frame"),
      AMCR_DOUBLE(flow_max_error, "grey levels", 1, 255, "mean grey-level difference over the window above which a flow fails"),
      AMCR_DOUBLE(frame_budget_ms, "ms", 0, 10000, "time cap per frame; an iteration spans frames when it does not fit; 0 = none"),
      AMCR_INT(num_threads, "", 0, 256, "threads the V-particles' iterations run on; 0 = every core; same output for any count"),
      AMCR_INT(seed, "", 0, 9.007199254740992e15, "seed of the random generator"),
  };
  return table;
}
#undef AMCR_DOUBLE
#undef AMCR_INT

/// The descriptions of a table's entries, in its order.
template <class Entry>
std::vector<decltype(Entry::info)> infosOf(const std::vector<Entry>& table)
{
  std::vector<decltype(Entry::info)> infos;
  for (const Entry& p : table)
    infos.push_back(p.info);
  return infos;
}

/// The entry of `table` named `name`, or nullptr.
template <class Entry>
const Entry* findIn(const std::vector<Entry>& table, const std::string& name)
{
  for (const Entry& p : table)
    if (p.info.name == name)
      return &p;
  return nullptr;
}

/// A prototype_priors entry: a label and a finite weight >= 0.
void checkPrior(const std::string& label, double weight)
{
  if (label.empty())
    throw ParameterError("parameter 'prototype_priors': an entry has no label");
  if (!std::isfinite(weight) || weight < 0.0)
    throw ParameterError("parameter 'prototype_priors': the weight of '" + label + "' must be a finite number >= 0");
}

std::string rangeText(const ParameterInfo& info)
{
  std::ostringstream out;
  out << "[" << formatNumber(info.min) << ", " << formatNumber(info.max) << "]";
  if (!info.unit.empty())
    out << " " << info.unit;
  return out.str();
}
/// table_cache_dir: a relative path would depend on the working directory
/// of whatever loads the memory (a nodelet manager's is not chosen by the user).
void checkTableCacheDir(const std::string& dir)
{
  if (dir.empty() || dir == "none" || dir[0] == '/' || dir.compare(0, 2, "~/") == 0)
    return;
  throw ParameterError("parameter 'table_cache_dir' = '" + dir +
                       "' must be an absolute path, a path starting with '~/', empty (the default place) or 'none'");
}

/// The words of a choice parameter with the value of each, the default's first.
template <class Choice>
using Words = std::vector<std::pair<std::string, Choice>>;

const Words<LikelihoodForm>& likelihoodWords()
{
  static const Words<LikelihoodForm> words = {{"paper", LikelihoodForm::kPaper}, {"mixture", LikelihoodForm::kMixture}};
  return words;
}
const Words<DeviationSpace>& deviationWords()
{
  static const Words<DeviationSpace> words = {{"image", DeviationSpace::kImage}, {"prototype", DeviationSpace::kPrototype}};
  return words;
}
const Words<RayCorrespondence>& correspondenceWords()
{
  static const Words<RayCorrespondence> words = {{"affine", RayCorrespondence::kAffine}, {"paper", RayCorrespondence::kPaper}};
  return words;
}

template <class Choice>
std::string wordOf(const Words<Choice>& words, Choice value)
{
  for (const auto& word : words)
    if (word.second == value)
      return word.first;
  return words.front().first;
}

/// One parameter that is not a number: its description and how to read and write it as text.
struct WordParameter
{
  WordParameterInfo info;
  std::function<std::string(const Params&)> get;
  std::function<void(Params&, const std::string&)> set;
};

/// A choice among `words`, stored in `field` of Params (a member of one of
/// its groups: the pointer converts, it is not deduced).
template <class Choice>
WordParameter choice(const std::string& name, typename Words<Choice>::value_type::second_type Params::*field,
                     const Words<Choice>& words)
{
  WordParameter p;
  p.info.name = name;
  std::string listed, quoted;
  for (const auto& word : words)
  {
    p.info.words.push_back(word.first);
    listed += (listed.empty() ? "" : " or ") + word.first;
    quoted += (quoted.empty() ? "'" : " or '") + word.first + "'";
  }
  p.info.takes = "a word (" + listed + ")";
  p.get = [field, &words](const Params& params) { return wordOf(words, params.*field); };
  p.set = [name, field, &words, quoted](Params& params, const std::string& value) {
    for (const auto& word : words)
      if (word.first == value)
      {
        params.*field = word.second;
        return;
      }
    throw ParameterError("parameter '" + name + "' = '" + value + "' must be " + quoted);
  };
  return p;
}

const std::vector<WordParameter>& wordParameters()
{
  static const std::vector<WordParameter> table = {
      {{"table_cache_dir", "a directory (absolute or ~/...), empty for the default, or none", {}},
       [](const Params& p) { return p.table_cache_dir; },
       [](Params& p, const std::string& value) {
         checkTableCacheDir(value);
         p.table_cache_dir = value;
       }},
      choice("likelihood_form", &Params::likelihood_form, likelihoodWords()),
      choice("deviation_space", &Params::deviation_space, deviationWords()),
      choice("ray_correspondence", &Params::ray_correspondence, correspondenceWords()),
      {{"prototype_priors", "a map of label: weight", {}},
       [](const Params& p) { return formatPriors(p.prototype_priors); },
       [](Params& p, const std::string& value) { p.prototype_priors = parsePriors(value); }},
  };
  return table;
}

/// Pairs of values where one makes the other meaningless.
void checkConsistency(const Params& p)
{
  if (p.min_support > p.num_v_particles)
    throw ParameterError("parameter 'min_support' = " + std::to_string(p.min_support) + " is above 'num_v_particles' = " +
                         std::to_string(p.num_v_particles) + ": no object could ever be reported");
  if (p.injection_fraction + p.m_reseed_fraction >= 1.0)
    throw ParameterError("parameters 'injection_fraction' = " + formatNumber(p.injection_fraction) +
                         " and 'm_reseed_fraction' = " + formatNumber(p.m_reseed_fraction) +
                         " add up to 1 or more: no M-particle would be drawn by its likelihood");
  checkParticleBound(p.num_v_particles, p.m_particles_per_prototype,
                     "m_particles_per_prototype, before the prototypes multiply it");
  checkParticleBound(p.num_v_particles, p.m_particles_per_v, "m_particles_per_v");
  if (p.m_particles_per_v > 0 && p.min_m_particles_per_v > p.m_particles_per_v)
    throw ParameterError("parameter 'min_m_particles_per_v' = " + std::to_string(p.min_m_particles_per_v) +
                         " is above 'm_particles_per_v' = " + std::to_string(p.m_particles_per_v) +
                         ": KLD-sampling could never reach its minimum");
}
}  // namespace

std::string formatNumber(double value)
{
  std::ostringstream out;
  if (std::isfinite(value) && value == std::round(value) && std::abs(value) < 1e16)
    out << static_cast<long long>(value);  // whole numbers as written: 4294967326, not 4.29497e+09
  else
    out << std::setprecision(15) << value;
  return out.str();
}

void Params::validate() const
{
  for (const auto& p : numericParameters())
  {
    // The seed's range is that of a number read exactly (2^53, setParameter);
    // every 64-bit seed set directly (amcr_offline --seed, ~seed as a string) is valid.
    if (p.info.name == "seed")
      continue;
    const double value = p.get(*this);
    if (!std::isfinite(value) || value < p.info.min || value > p.info.max)
    {
      std::ostringstream out;
      out << "parameter '" << p.info.name << "' = " << formatNumber(value) << " is outside its range "
          << rangeText(p.info);
      throw ParameterError(out.str());
    }
  }
  for (const auto& prior : prototype_priors)
    checkPrior(prior.first, prior.second);
  checkTableCacheDir(table_cache_dir);
  checkConsistency(*this);
}

void MemoryParams::validate() const
{
  // The other groups at their defaults, which are valid: what is refused is of this group.
  Params whole;
  static_cast<MemoryParams&>(whole) = *this;
  whole.validate();
}

const std::vector<ParameterInfo>& parameterTable()
{
  static const std::vector<ParameterInfo> table = infosOf(numericParameters());
  return table;
}

bool tablesDiffer(const Params& a, const Params& b)
{
  for (const auto& p : numericParameters())
    if (p.info.builds_tables && p.get(a) != p.get(b))
      return true;
  return false;
}

void setParameter(Params& params, const std::string& name, double value)
{
  const NumericParameter* p = findIn(numericParameters(), name);
  if (const WordParameter* word = p ? nullptr : findIn(wordParameters(), name))
    throw ParameterError("parameter '" + name + "' takes " + word->info.takes + ", not the number " +
                         formatNumber(value));
  if (!p)
    throw ParameterError("unknown parameter '" + name + "'");
  if (!std::isfinite(value) || value < p->info.min || value > p->info.max)
  {
    std::ostringstream out;
    out << "parameter '" << name << "' = " << formatNumber(value) << " is outside its range " << rangeText(p->info);
    throw ParameterError(out.str());
  }
  if (p->integer && std::abs(value - std::round(value)) > 1e-9)
  {
    std::ostringstream out;
    out << "parameter '" << name << "' = " << formatNumber(value) << " must be a whole number";
    throw ParameterError(out.str());
  }
  p->set(params, value);
}

void setParameter(Params& params, const std::string& name, const std::string& value)
{
  if (const WordParameter* p = findIn(wordParameters(), name))
    return p->set(params, value);
  if (findIn(numericParameters(), name))
    throw ParameterError("parameter '" + name + "' takes a number, not '" + value + "'");
  throw ParameterError("unknown parameter '" + name + "'");
}

std::map<std::string, double> parsePriors(const std::string& text)
{
  std::map<std::string, double> priors;
  std::stringstream entries(text);
  std::string entry;
  while (std::getline(entries, entry, ','))
  {
    const auto trim = [](std::string s) {
      const auto first = s.find_first_not_of(" \t\n");
      const auto last = s.find_last_not_of(" \t\n");
      return first == std::string::npos ? std::string() : s.substr(first, last - first + 1);
    };
    if (trim(entry).empty())
      continue;
    const auto colon = entry.rfind(':');
    const std::string label = colon == std::string::npos ? "" : trim(entry.substr(0, colon));
    const std::string number = colon == std::string::npos ? "" : trim(entry.substr(colon + 1));
    std::size_t used = 0;
    double weight = -1.0;
    try
    {
      weight = std::stod(number, &used);
    }
    catch (const std::exception&)
    {
      used = 0;
    }
    if (label.empty() || used == 0 || used != number.size())
      throw ParameterError("parameter 'prototype_priors': '" + trim(entry) + "' is not 'label: weight'");
    checkPrior(label, weight);
    priors[label] = weight;
  }
  return priors;
}

std::string formatPriors(const std::map<std::string, double>& priors)
{
  std::ostringstream out;
  out << std::setprecision(15);  // a decimal weight of up to 15 digits reads back unchanged
  for (auto it = priors.begin(); it != priors.end(); ++it)
    out << (it == priors.begin() ? "" : ", ") << it->first << ": " << it->second;
  return out.str();
}

double getParameter(const Params& params, const std::string& name)
{
  const NumericParameter* p = findIn(numericParameters(), name);
  if (!p)
    throw ParameterError("unknown numeric parameter '" + name + "'");
  return p->get(params);
}

std::string getWordParameter(const Params& params, const std::string& name)
{
  const WordParameter* p = findIn(wordParameters(), name);
  if (!p)
    throw ParameterError("unknown word parameter '" + name + "'");
  return p->get(params);
}

const std::vector<WordParameterInfo>& wordParameterTable()
{
  static const std::vector<WordParameterInfo> table = infosOf(wordParameters());
  return table;
}

bool sameParameters(const Params& a, const Params& b)
{
  for (const auto& p : numericParameters())
    if (p.get(a) != p.get(b))
      return false;
  for (const auto& p : wordParameters())  // the priors as maps: their text rounds the weights
    if (p.info.name == "prototype_priors" ? a.prototype_priors != b.prototype_priors : p.get(a) != p.get(b))
      return false;
  return true;
}

std::string toString(LikelihoodForm form) { return wordOf(likelihoodWords(), form); }

std::string toString(DeviationSpace space) { return wordOf(deviationWords(), space); }

std::string toString(RayCorrespondence correspondence) { return wordOf(correspondenceWords(), correspondence); }
}  // namespace amcr
