// Every tunable of Radial-AMCR, with its unit, range and the paper's value.
// The same names are used in config/amcr.yaml and in the dynamic_reconfigure
// file; validate() throws ParameterError naming the parameter and its range.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace amcr
{
/// How a ray's deviation dw_j enters the likelihood (spec "Observation model").
enum class LikelihoodForm
{
  kPaper,    ///< paper eq. 5: p_outlier + (1 - p_outlier) N(dw; 0, sigma_w^2)
  kMixture,  ///< normalised: p_outlier / L + (1 - p_outlier) N(dw; 0, sigma_w^2)
};

/// Where the deviations dw_j are measured.
enum class DeviationSpace
{
  kImage,      ///< prototype points mapped into the input image by A^-1 (input pixels)
  kPrototype,  ///< input points mapped into the prototype by A, as in the paper
};

/// Which table ray a V-particle's image ray is compared with.
enum class RayCorrespondence
{
  kPaper,   ///< the ray at the same angle from the M-particle's heading (paper 4.1; exact for similarities)
  kAffine,  ///< the ray in the direction the relational affine maps the image ray to (oblique views)
};

// The parameters come in groups, each read by the component that owns it;
// a component takes the group(s) it reads (a Params binds to each), and only
// what builds everything (Recognizer, FilterMemory), the files and the
// checks take the whole Params (test/test_core_layout.py keeps the list).

/// Particle counts, and how a V-particle's M-particles are shared among the
/// prototypes (PrototypePrior; the particle filter's seeding and resampling).
struct ParticleCounts
{
  int num_v_particles = 60;            ///< V-particles in the input image [1, 5000]; paper 30
  int m_particles_per_prototype = 60;  ///< M-particles per prototype per V [1, 5000]; paper 60
  /// M-particle budget of a V-particle, shared among the prototypes
  /// [0, 100000]; 0 = the paper's m_particles_per_prototype per prototype.
  int m_particles_per_v = 1000;
  int min_m_particles_per_v = 60;  ///< fewest M-particles KLD-sampling leaves a V-particle [1, 100000]
  double kld_error = 0.2;          ///< KLD-sampling's bound on the KL divergence (Fox 2003) [0, 1]; 0 = a fixed count
  double kld_z = 2.33;             ///< KLD-sampling's upper standard normal quantile (2.33: 99%) [0, 10]

  /// Context prior over the memory (paper 3.6, "context"): label -> weight
  /// of the label in the initial and re-seeded M-particles, shared equally
  /// among the label's instances. Labels not listed weigh 1; weight 0
  /// removes a label (all its instances) from the filter.
  std::map<std::string, double> prototype_priors;
};

/// Data-driven proposals (proposal_index.h, profile_index.h; FilterMemory
/// builds the indexes, the particle filter draws from them).
struct ProposalParams
{
  double index_share = 0.5;  ///< share of new M-particles drawn from the proposal index [0, 1]; 0 = none
  /// Exponent of the importance weight pi / q of a new M-particle under the mixture proposal [0, 1]:
  /// 1 = exact importance sampling, 0 = sensor resetting (weighed by its likelihood alone).
  double proposal_correction = 0.0;
  int index_stride = 6;      ///< table px between the indexed points of a prototype [1, 64]
  int index_candidates = 64; ///< places a V-particle's query returns [1, 1000]
  /// The frontal candidates from the radial-profile index (profile_index.h):
  /// the best aligned 8 of the index_candidates places nearest in profile
  /// key; false (the default: more false reports, docs/how-it-works.md,
  /// "Proposals from the radial profile"): from the 8-ray index
  /// (proposal_index.h).
  bool profile_index = false;
  /// Most entries the index holds [0, 1e9]; a memory that would need more
  /// is indexed at a larger stride (ProposalIndex); 0 = no limit.
  int index_max_entries = 3000000;
};

/// What counts as an edge, in the frames (the recognizer's scans) and in the
/// prototypes (their lookup tables, MemoryParams): lengths in px of the
/// working image (working_scale.h).
struct EdgeParams
{
  double edge_threshold = 40.0;   ///< grey-level step over 2 px that counts as an edge [1, 255]
  /// Local edge strength at which edge_threshold applies in full, grey
  /// levels [0, 255]: where the strongest 2 px steps within about 50 px are
  /// weaker, a point's threshold falls in proportion, down to the frame's
  /// noise floor; 0 = edge_threshold everywhere (edge_thresholds.h).
  double edge_full_strength = 100.0;
  double blur_sigma = 1.0;        ///< Gaussian smoothing before scanning, working px [0, 10]
  /// A grey template's edges count only where the grey rises across them as
  /// in the template (shape-based matching's "use polarity"); false: the
  /// polarity most of its points show, so a part in reversed contrast is
  /// found (edge_model.h). Silhouettes: no effect (no side of theirs is darker).
  bool keep_polarity = false;
};

/// Prototype memory: what its lookup tables are built with (the edges'
/// definition with them) and where they are cached (prototype_memory.h,
/// prototype_file.h, table_cache.h, table_stride_choice.h).
struct MemoryParams : EdgeParams
{
  int prototype_size = 128;  ///< longer side of a prototype in the lookup tables, px [32, 512]
  /// Spacing of the lookup tables' nodes, table px [0, 4]: 1 = a scan at
  /// every pixel (exact lookups); s = one per s x s block, s^2 times less
  /// memory and build time (Prototype(); docs/configuration.md, "Compact tables"); 0 = the
  /// smallest stride whose tables fit table_budget_mb for the memory's size
  /// (table_stride_choice.h).
  int table_stride = 0;
  /// Most memory the lookup tables may take when table_stride is 0, MB
  /// [16, 4096]; a given table_stride above it is used with a warning.
  int table_budget_mb = 1024;
  /// Directory of the cached lookup tables (table_cache.h), read when a
  /// memory is loaded from a directory, and of the proposal index's k-d
  /// tree (index_cache.h), read when a recognizer is built: "" =
  /// $ROS_HOME/amcr/tables, or
  /// ~/.ros/amcr/tables when ROS_HOME is not set; "none" = no cache;
  /// otherwise an absolute path or one starting with "~/".
  std::string table_cache_dir;

  /// Params::validate's checks of these parameters alone.
  void validate() const;
};

/// Radial edge scans in the working image: the input reduced to
/// working_resolution (working_scale.h). Every length in px of the groups
/// is of the working image, except min_object_size (input px).
struct ScanParams
{
  double max_ray_length = 200.0;  ///< longest ray, working px [10, 4000]
  /// Longer side of the working image, input px [0, 4000]; a larger input is
  /// reduced to it (never enlarged), and results come back in input px; 0 = the input's own size.
  int working_resolution = 640;
};

/// Observation model (paper eqs. 5-6; observation_model.h) and the view
/// shapes it compares under (ray_correspondence affine).
struct ObservationParams
{
  LikelihoodForm likelihood_form = LikelihoodForm::kPaper;
  DeviationSpace deviation_space = DeviationSpace::kImage;
  double sigma_w = 5.0;           ///< std. dev. of a ray's deviation, working px (prototype px with deviation_space prototype) (0, 1000]; paper 10
  double p_outlier = 0.1;         ///< probability that a ray is an outlier [0, 1]; paper 0.1
  double p_invalid = 0.1;         ///< probability of an invalid ray [0, 1]; paper 0.1
  double min_triangle_area = 20;  ///< smaller affine triangles are degenerate, working px^2 [0, 1e6]
  double max_affine_scale = 8.0;  ///< largest accepted scale ratio of A (either way) [1, 100]
  RayCorrespondence ray_correspondence = RayCorrespondence::kAffine;
  int affine_refits = 0;          ///< re-estimates of A from affine-corrected triangle rays [0, 5]
  double max_anisotropy = 3.0;    ///< largest anisotropy of the view shapes new M-particles get, and of a new object reported [1, 10]; 1 = frontal
  double oblique_share = 0.5;     ///< share of new M-particles given an oblique view shape, and of index candidates read under one [0, 1]
};

/// Motion model (paper 4.2; motion_model.h) and the exploration policy's
/// moves (paper 4.3; exploration_policy.h).
struct MotionParams
{
  double motion_noise_shape = 0.05;      ///< M-particle view-shape noise per iteration [0, 1]
  double v_step = 4.0;                   ///< forward step of a V-particle per iteration, working px [0, 100]
  double motion_noise_translation = 1.5; ///< M-particle translation noise, prototype px [0, 100]
  double motion_noise_rotation = 0.08;   ///< M-particle rotation noise, rad [0, 3.15]
  double reflection_jitter = 0.3;        ///< random turn added at a reflection, rad [0, 3.15]
};

/// Attention: where the V-particles look (discriminative_attention.h,
/// discriminative_places.h, the held objects of the particle filter).
struct AttentionParams
{
  /// Attention that discriminates (discriminative_attention.h): a V-particle
  /// whose M-particles have found a shape while another prototype's cluster
  /// competes moves where their predicted scans differ most.
  bool discriminative_moves = false;
  /// With discriminative_moves: the look-alike pairs and the places where
  /// their scans differ are precomputed (discriminative_places.h), and a
  /// V-particle deciding between two heads for the nearest such place.
  bool discriminative_places = true;
  double discriminative_min_share = 0.05;  ///< share of a V's M-particles a competing cluster needs [0, 1]
  double discriminative_min_gain = 0.2;    ///< least expected log-likelihood ratio of a discriminative move, nats [0, 100]
  int held_v_particles = 3;  ///< V-particles a held object keeps at V-resampling [0, 5000]
  double scene_prior_share = 0.25;  ///< share of new M-particles drawn in the held objects' prototypes [0, 1]
};

/// Resampling and seeding (paper 3.6; the particle filter).
struct ResamplingParams
{
  int v_resample_interval = 3;      ///< w: V-particles are resampled every w iterations [1, 1000]; paper 10
  double v_reseed_fraction = 0.5;   ///< share of V-particles re-seeded at V-resampling [0, 1]
  double m_reseed_fraction = 0.02;  ///< share of M-particles re-seeded uniformly per iteration [0, 1]
  double injection_fraction = 0.1;  ///< share of M-particles placed at leading hypotheses [0, 1]
  int seed_enclosure_rays = 6;      ///< a new V-particle wants this many of 8 rays to hit an edge [0, 8]
  int seed_attempts = 10;           ///< tries to find such a place before taking any [1, 1000]
};

/// Result extraction (object_extractor.h and its steps).
struct ExtractionParams
{
  double cluster_radius = 6.0;        ///< M-cluster radius, prototype px [0.5, 100]
  double cluster_min_share = 0.3;     ///< share of a V's M-particles its cluster needs [0, 1]
  /// Competing clusters of V-particles, then look-alikes of tracked objects'
  /// prototypes (discriminative_places.h), fitted and verified on the image
  /// per frame beside the groups' (fit_starts.cpp) [0, 64]; 0 = none
  /// (and no look-alike pairs are found).
  int competing_fits = 4;
  int likeliest_fits = 0;             ///< unconverged V-particles' likeliest modes fitted per frame; 0 = off
  int pose_vote_fits = 4;             ///< pools of the image's pose votes fitted per frame; 0 = off
  /// K: frames in which the coverage lattice (coverage_schedule.h) reads the
  /// whole image for pose votes [0, 100]; 0 = the V-particles' places only.
  int coverage_frames = 2;
  double group_tolerance = 8.0;       ///< V-particles agree when they map within this, working px [0.5, 200]
  int min_support = 2;                ///< V-particles an object needs [1, 5000]
  int refine_iterations = 5;          ///< outline-to-edge refinement passes of the affine [0, 100]
  double refine_search = 6.0;         ///< search along the outline normal for an edge, working px [0, 100]
  bool fit_homography = true;         ///< after the affine, fit a homography and use it when the outline demands it
  double decision_threshold = 0.75;   ///< smallest score reported [0, 1]
  /// Distance along the outline's normal within which an outline point
  /// finds its image edge in the score, working px [0.5, 20].
  double verify_tolerance = 2.0;
  /// The score's tolerance as a share of the object's size (the longer side
  /// of its outline's box) [0, 0.1]: the smaller of the two applies, never
  /// less than 1 px; 0 = verify_tolerance at every size (outline_fit.h).
  double verify_relative_tolerance = 0.008;
  /// Share of the outline points that tell the prototype from its generic
  /// rivals (an ellipse, its convex hull, its rectangle, a pair of lines)
  /// that must lie on image edges for a new object's report (a tracked one
  /// until it has missed 0.65 of it in 10 reports in a row) [0, 1]; 0 = no
  /// such check (generic_rivals.h).
  double rival_part_support = 0.45;
  /// How far an inner part of a prototype's outline (a hole's outline) may
  /// move and scale on its own before the score counts it, as a share of the
  /// object's size [0, 0.2]: the error of a prototype drawn from a measured
  /// target; 0 = the whole outline moves as one (outline_parts.h).
  double part_shift = 0.05;
  /// Smallest share of a new object's outline that must be visible, the
  /// rest covered by something in front of it (covered_outline.h); the
  /// score is then the share of the visible outline on edges (a tracked
  /// object needs 0.65 of it) [0, 1]; 1 = no outline point counts as
  /// covered: the score is the share of the whole outline.
  double min_visible_share = 0.5;
  double min_object_size = 64.0;      ///< smallest object reported: longer side of its outline's box, input px [0, 4000]
};

/// Tracking (spec "Tracking"; flow_tracker.h): the optical flow the
/// V-particles ride and the objects' life cycle (track_registry.h).
struct TrackingParams
{
  int confirm_frames = 3;    ///< frames an object is reported in before it is confirmed [1, 1000]
  int lost_frames = 5;       ///< frames in a row without a report after which a track ends [1, 1000]
  /// Frames after its end during which a lost track's id is given back to an
  /// object of its label found where it was last [0, 10000]; 0 = never.
  int recall_frames = 30;
  int max_objects = 64;      ///< tracks kept at once; no new object is reported beyond [1, 256]
  bool optical_flow = true;        ///< V-particles ride pyramidal Lucas-Kanade flow between frames
  int flow_window = 21;            ///< side of the Lucas-Kanade window, working px [5, 101]
  int flow_levels = 3;             ///< pyramid levels above the frame [0, 8]
  double flow_max_error = 40.0;    ///< a flow whose mean grey-level difference over the window exceeds this fails [1, 255]
};

/// How a frame's work is run: its time cap, its threads and the random seed.
struct RunParams
{
  double frame_budget_ms = 0.0;    ///< time cap per frame, ms; 0 = a full iteration every frame [0, 10000]
  /// Threads the V-particles' iterations run on; 0 = every core [0, 256].
  /// The output is the same for any count.
  int num_threads = 0;
  std::uint64_t seed = 0;  ///< seed of the recognizer's random generator
};

/// Every parameter: the groups together, read by name through
/// parameterTable() and wordParameterTable().
struct Params : ParticleCounts,
                ProposalParams,
                MemoryParams,
                ScanParams,
                ObservationParams,
                MotionParams,
                AttentionParams,
                ResamplingParams,
                ExtractionParams,
                TrackingParams,
                RunParams
{
  /// Throws ParameterError naming the first parameter out of range (or the
  /// prototype_priors entry with a negative or non-finite weight), or the
  /// pair of parameters where one makes the other meaningless:
  /// min_support above num_v_particles (nothing could be reported),
  /// injection_fraction + m_reseed_fraction >= 1 (no M-particle would be
  /// drawn by its likelihood); and when num_v_particles x
  /// m_particles_per_prototype alone exceeds kMaxMParticles
  /// (resource_bounds.h; the prototypes multiply it in the filter), or
  /// num_v_particles x m_particles_per_v does, or min_m_particles_per_v is
  /// above a non-zero m_particles_per_v; and for a table_cache_dir that
  /// is relative.
  void validate() const;
};

/// Description of one parameter, for documentation and YAML loading.
struct ParameterInfo
{
  std::string name;
  std::string unit;
  double min;
  double max;
  std::string description;
  /// The prototype memory is built with it: a change needs new lookup
  /// tables (the TABLES level of cfg/AMCR.cfg).
  bool builds_tables = false;
};

/// All numeric parameters, in the order of config/amcr.yaml.
const std::vector<ParameterInfo>& parameterTable();

/// True when a memory built with `a` differs from one built with `b`: a
/// parameter that builds the tables (ParameterInfo::builds_tables) differs.
bool tablesDiffer(const Params& a, const Params& b);

/// Description of a parameter that is not a number: it is read and written
/// as a word (a choice among `words`) or a text (no `words`).
struct WordParameterInfo
{
  std::string name;
  std::string takes;               ///< what it takes, for messages: "a word (paper or mixture)"
  std::vector<std::string> words;  ///< the words of a choice, the default's first; empty for a free text
};

/// All parameters that are not numbers (likelihood_form, deviation_space,
/// ray_correspondence, table_cache_dir, prototype_priors), in the order of
/// config/amcr.yaml. With parameterTable() it is the one table by name that
/// YAML files, rosparam and dynamic_reconfigure go through.
const std::vector<WordParameterInfo>& wordParameterTable();

/// Sets one parameter by name from a number, or one of wordParameterTable()
/// from a string. Throws ParameterError for an unknown name, a value out of
/// range or a word not among those the parameter takes.
void setParameter(Params& params, const std::string& name, double value);
void setParameter(Params& params, const std::string& name, const std::string& value);

/// Parses prototype priors written as "label: weight, label: weight"
/// (ParameterError for a malformed entry or a negative weight).
std::map<std::string, double> parsePriors(const std::string& text);
/// The inverse of parsePriors, labels in order.
std::string formatPriors(const std::map<std::string, double>& priors);

/// Reads one numeric parameter by name.
double getParameter(const Params& params, const std::string& name);
/// Reads one parameter of wordParameterTable() by name, as setParameter
/// takes it back (prototype_priors as formatPriors writes it).
std::string getWordParameter(const Params& params, const std::string& name);

/// True when every parameter of `a` equals `b`'s (numbers, forms, priors,
/// table_cache_dir).
bool sameParameters(const Params& a, const Params& b);

/// A number for messages: whole numbers in full (4294967326), others with
/// up to 15 digits.
std::string formatNumber(double value);

std::string toString(LikelihoodForm form);
std::string toString(DeviationSpace space);
std::string toString(RayCorrespondence correspondence);
}  // namespace amcr
