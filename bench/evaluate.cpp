// amcr_evaluate: runs AMCR and the baselines on the same frames of one benchmark suite
// (as bench/make_sequences writes it) and writes what each reports, frame by frame.
//
//   amcr_evaluate --suite DIR --out DIR [--config FILE] [--methods amcr,orb,hu,ght,line2d,sc]
//                 [--seed N] [--ght-frames 9,29,59,-1] [--ght-sequences N] [--prototypes DIR]
//                 [--every METHOD=N,...] [--target-size MIN,MAX] [--anisotropy MAX]
//                 [--line2d-threshold PERCENT] [--line2d-reports N]
//
// The memory is <suite>/prototypes unless --prototypes names another folder (the `memory-growth`
// suite runs the same sequences once per memory, prototypes-3 ... prototypes-70). For the baselines,
// the folder holds loose .png files (label: the file name) and/or one sub-directory per label, each
// .png in it an instance of that label (`within-class-1330`, `within-class-85`). A file that amcr
// reads as a grey template (an alpha channel short of opaque, or more than two grey levels) is one
// for the baselines too: LINE-2D and shape contexts take its grey image and inner edges, the others
// its region as a silhouette.
//
// Writes <out>/<sequence>.<method>.jsonl, one line per frame run:
//   {"frame": k, "time_ms": t, "objects": [{"label": ..., "score": s,
//    "prototype_to_image": [a,b,c,d,e,f], "track_id": n, "state": s, "correspondences": [[xi,yi,xp,yp], ...]}]}
// ("track_id" and "state": the recognizer's track of the object and where it is in its life cycle,
// "tentative" | "confirmed" | "held"; amcr only, the baselines keep no tracks and omit both)
// and <out>/init.<method>.json (set-up time; for amcr the lookup tables' size). For amcr also
// <out>/<sequence>.amcr.funnel.jsonl, the recall funnel (recall_funnel.h) of every true object in
// every frame, and as its last line the sequence's summary: the frames that reached each stage and
// the first stage none reached. A file that
// exists is not computed again (files are written under a temporary name, then renamed), so
// an interrupted run resumes. Frames are processed on one core (OpenCV threads off). GHT is slow: it runs on --ght-frames (0-based; -1 = the last)
// of the first --ght-sequences sequences only. `--every line2d=5` runs a method on every 5th frame
// (frames 5, 10, ... numbered from 1, and the last) of every sequence: each frame on its own, so the
// figures at those frames are what it does on every frame, at a fifth of the cost.
//
// LINE-2D (line2d) and shape contexts (sc) are built when OpenCV has its rgbd (contrib) and shape
// modules; without them they are left out of the default --methods, and asking for them says why.
// Both are set for the poses the suite draws: --target-size (the longer side of a target's bounding
// box in the frames, px; default 110,260) and --anisotropy (the largest ratio of the singular values
// of a target's affine; default 1.7, the aspect and shear of the `paper` suites; 3 for `oblique`).
// --line2d-threshold overrides LINE-2D's similarity threshold (to choose it on sequences of a seed
// that the benchmark does not score); --line2d-reports its most reports per frame (5), for frames
// that show more objects (bench/real_tags.py: 12 tags).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>

#include "amcr/base/params.h"
#include "amcr/io/params_file.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr_method.h"
#include "recall_funnel.h"
#include "sequence_truth.h"
#include "baselines/generalized_hough.h"
#include "baselines/hu_moments.h"
#include "baselines/orb_homography.h"
#include "baselines/prototype_image.h"
#ifdef AMCR_HAVE_LINE2D
#include "baselines/line2d.h"
#endif
#ifdef AMCR_HAVE_SHAPE_CONTEXT
#include "baselines/shape_context.h"
#endif

namespace fs = std::filesystem;
using amcr_bench::Detection;
using amcr_bench::Method;
using amcr_bench::PrototypeImage;

namespace
{
/// The methods this build has, in the order they run by default.
std::vector<std::string> defaultMethods()
{
  std::vector<std::string> methods = {"amcr", "orb", "hu", "ght"};
#ifdef AMCR_HAVE_LINE2D
  methods.push_back("line2d");
#endif
#ifdef AMCR_HAVE_SHAPE_CONTEXT
  methods.push_back("sc");
#endif
  return methods;
}

struct Options
{
  std::string suite, out, config = "config/amcr.yaml", prototypes;  // prototypes: default <suite>/prototypes
  std::vector<std::string> methods = defaultMethods();
  std::uint64_t seed = 1;
  std::vector<int> ght_frames = {9, 29, 59, -1};
  int ght_sequences = 1000000;
  std::map<std::string, int> every;  ///< method -> run on every Nth frame (and the last)
  double min_target_size = 110, max_target_size = 260;  ///< longer side of a target in the frames, px
  double max_anisotropy = 1.7;
  float line2d_threshold = 0;  ///< 0: Line2dConfig's
  int line2d_reports = 0;      ///< 0: Line2dConfig's
};

std::vector<std::string> split(const std::string& text)
{
  std::vector<std::string> parts;
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, ',');)
    if (!part.empty())
      parts.push_back(part);
  return parts;
}

[[noreturn]] void usage(const std::string& error)
{
  std::cerr << "amcr_evaluate: " << error << "\n"
            << "usage: amcr_evaluate --suite DIR --out DIR [--config FILE] [--methods amcr,orb,hu,ght,line2d,sc]\n"
            << "                     [--seed N] [--ght-frames 9,29,59,-1] [--ght-sequences N] [--prototypes DIR]\n"
            << "                     [--every METHOD=N,...] [--target-size MIN,MAX] [--anisotropy MAX]\n"
            << "                     [--line2d-threshold PERCENT] [--line2d-reports N]\n";
  std::exit(2);
}

Options parse(int argc, char** argv)
{
  Options o;
  for (int i = 1; i < argc; ++i)
  {
    const std::string key = argv[i];
    if (i + 1 >= argc)
      usage("missing value after " + key);
    const std::string value = argv[++i];
    if (key == "--suite")
      o.suite = value;
    else if (key == "--out")
      o.out = value;
    else if (key == "--config")
      o.config = value;
    else if (key == "--methods")
      o.methods = split(value);
    else if (key == "--seed")
      o.seed = std::stoull(value);
    else if (key == "--ght-frames")
    {
      o.ght_frames.clear();
      for (const std::string& f : split(value))
        o.ght_frames.push_back(std::stoi(f));
    }
    else if (key == "--ght-sequences")
      o.ght_sequences = std::stoi(value);
    else if (key == "--prototypes")
      o.prototypes = value;
    else if (key == "--every")
    {
      for (const std::string& item : split(value))
      {
        const std::size_t eq = item.find('=');
        const int n = eq == std::string::npos ? 0 : std::atoi(item.c_str() + eq + 1);
        if (n < 1)
          usage("--every wants METHOD=N with N >= 1, got " + item);
        o.every[item.substr(0, eq)] = n;
      }
    }
    else if (key == "--target-size")
    {
      const std::vector<std::string> range = split(value);
      if (range.size() != 2 || (o.min_target_size = std::atof(range[0].c_str())) <= 0 ||
          (o.max_target_size = std::atof(range[1].c_str())) < o.min_target_size)
        usage("--target-size wants MIN,MAX in px with 0 < MIN <= MAX, got " + value);
    }
    else if (key == "--line2d-threshold")
    {
      if ((o.line2d_threshold = std::atof(value.c_str())) <= 0 || o.line2d_threshold > 100)
        usage("--line2d-threshold wants a similarity in (0, 100] percent, got " + value);
    }
    else if (key == "--line2d-reports")
    {
      if ((o.line2d_reports = std::atoi(value.c_str())) < 1)
        usage("--line2d-reports wants a number of reports >= 1, got " + value);
    }
    else if (key == "--anisotropy")
    {
      if ((o.max_anisotropy = std::atof(value.c_str())) < 1)
        usage("--anisotropy wants a ratio >= 1, got " + value);
    }
    else
      usage("unknown option " + key);
  }
  if (o.suite.empty() || o.out.empty())
    usage("--suite and --out are required");
  if (o.prototypes.empty())
    o.prototypes = (fs::path(o.suite) / "prototypes").string();
  return o;
}

// The memory of a prototype folder: its loose .png files (label: the file name without extension)
// and, one level down, one sub-directory per label (label: the sub-directory's name), every .png in
// it an instance of that label. Sorted by path. Each is a silhouette or a grey template as amcr
// reads it (baselines/prototype_image.h).
std::vector<PrototypeImage> loadPrototypes(const std::string& dir)
{
  std::vector<std::pair<std::string, std::string>> files;  // (path, label)
  for (const auto& entry : fs::directory_iterator(dir))
  {
    if (entry.is_directory())
    {
      const std::string label = entry.path().filename().string();
      for (const auto& inner : fs::directory_iterator(entry.path()))
        if (inner.is_regular_file() && inner.path().extension() == ".png")
          files.emplace_back(inner.path().string(), label);
    }
    else if (entry.path().extension() == ".png")
      files.emplace_back(entry.path().string(), entry.path().stem().string());
  }
  std::sort(files.begin(), files.end());
  std::vector<PrototypeImage> prototypes;
  for (const auto& [path, label] : files)
    prototypes.push_back(amcr_bench::readPrototypeImage(label, path));
  return prototypes;
}

std::string number(double v)
{
  char text[32];
  std::snprintf(text, sizeof(text), "%.4f", v);
  return text;
}

std::string jsonLine(int frame, double time_ms, const std::vector<Detection>& found)
{
  std::ostringstream s;
  s << "{\"frame\": " << frame << ", \"time_ms\": " << number(time_ms) << ", \"objects\": [";
  for (std::size_t i = 0; i < found.size(); ++i)
  {
    const Detection& d = found[i];
    s << (i ? ", " : "") << "{\"label\": \"" << d.label << "\", \"score\": " << number(d.score)
      << ", \"prototype_to_image\": [";
    for (int k = 0; k < 6; ++k)
      s << (k ? ", " : "") << number(d.prototype_to_image(k / 3, k % 3));
    s << "]";
    if (d.track_id >= 0)
      s << ", \"track_id\": " << d.track_id << ", \"state\": \"" << d.state << "\"";
    s << ", \"correspondences\": [";
    for (std::size_t c = 0; c < d.correspondences.size(); ++c)
    {
      const auto& p = d.correspondences[c];
      s << (c ? ", " : "") << "[" << number(p.first.x) << ", " << number(p.first.y) << ", " << number(p.second.x)
        << ", " << number(p.second.y) << "]";
    }
    s << "]}";
  }
  s << "]}";
  return s.str();
}

void writeAtomically(const fs::path& path, const std::string& text)
{
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp);
    out << text;
    if (!out)
      throw std::runtime_error("cannot write " + tmp.string());
  }
  fs::rename(tmp, path);
}

double millisecondsSince(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// Which of the 0-based frames of a sequence of `count` frames `method` runs on: GHT on --ght-frames,
/// a method given to --every on every Nth frame and the last, any other on every frame.
std::vector<bool> framesToRun(const std::string& method, int count, const Options& o)
{
  const auto every = o.every.find(method);
  const bool every_nth = every != o.every.end() && every->second > 1;
  std::vector<bool> run(count, method != "ght" && !every_nth);
  if (method == "ght")
    for (int f : o.ght_frames)
    {
      const int k = f < 0 ? count + f : f;
      if (k >= 0 && k < count)
        run[k] = true;
    }
  if (every_nth && count > 0)
  {
    for (int k = every->second - 1; k < count; k += every->second)
      run[k] = true;
    run[count - 1] = true;
  }
  return run;
}

/// Builds one method; `init` receives its set-up figures as JSON members.
std::unique_ptr<Method> makeMethod(const std::string& name, const Options& o, const std::vector<PrototypeImage>& prototypes,
                                   std::string& init)
{
  if (name == "amcr")
  {
    amcr::Params params = amcr::loadParams(o.config);
    params.seed = o.seed;
    auto memory = std::make_shared<amcr::PrototypeMemory>(
        amcr::PrototypeMemory::loadDirectory(o.prototypes, params));
    init = "\"table_bytes\": " + std::to_string(memory->tableBytes()) + ", \"prototypes\": " +
           std::to_string(memory->size()) + ", \"num_v_particles\": " + std::to_string(params.num_v_particles) +
           ", \"m_particles_per_prototype\": " + std::to_string(params.m_particles_per_prototype);
    return std::make_unique<amcr_bench::AmcrMethod>(params, memory);
  }
  if (name == "orb")
    return std::make_unique<amcr_bench::OrbHomography>(prototypes);
  if (name == "hu")
    return std::make_unique<amcr_bench::HuMoments>(prototypes);
  if (name == "ght")
    return std::make_unique<amcr_bench::GeneralizedHough>(prototypes);
  if (name == "line2d")
  {
#ifdef AMCR_HAVE_LINE2D
    amcr_bench::Line2dConfig config;
    config.min_size = o.min_target_size;
    config.max_size = o.max_target_size;
    config.max_anisotropy = o.max_anisotropy;
    if (o.line2d_threshold > 0)
      config.threshold = o.line2d_threshold;
    if (o.line2d_reports > 0)
      config.max_reports = o.line2d_reports;
    auto line2d = std::make_unique<amcr_bench::Line2d>(prototypes, config);
    init = "\"templates\": " + std::to_string(line2d->templateCount());
    return line2d;
#else
    usage("line2d is not in this build: OpenCV's rgbd module (Debian and Ubuntu: libopencv-contrib-dev) was "
          "missing when amcr_evaluate was built");
#endif
  }
  if (name == "sc")
  {
#ifdef AMCR_HAVE_SHAPE_CONTEXT
    // The candidates are contours, measured by their own bounding box: a squashed view makes the
    // longer side up to sqrt(anisotropy) longer or shorter, and a silhouette fills only part of its
    // prototype image.
    amcr_bench::ShapeContextConfig config;
    config.min_size = 0.6 * o.min_target_size / std::sqrt(o.max_anisotropy);
    config.max_size = o.max_target_size * std::sqrt(o.max_anisotropy);
    config.max_anisotropy = std::max(config.max_anisotropy, o.max_anisotropy);
    return std::make_unique<amcr_bench::ShapeContext>(prototypes, config);
#else
    usage("sc is not in this build: OpenCV's shape module (Debian and Ubuntu: libopencv-shape-dev) was missing "
          "when amcr_evaluate was built");
#endif
  }
  usage("unknown method " + name);
}
}  // namespace

int main(int argc, char** argv)
{
  const Options o = parse(argc, argv);
  try
  {
    const std::vector<PrototypeImage> prototypes = loadPrototypes(o.prototypes);
    if (prototypes.empty())
      usage("no prototypes in " + o.prototypes);
    std::vector<fs::path> sequences;
    for (const auto& entry : fs::directory_iterator(o.suite))
      if (fs::exists(entry.path() / "truth.json"))
        sequences.push_back(entry.path());
    std::sort(sequences.begin(), sequences.end());
    fs::create_directories(o.out);

    for (const std::string& name : o.methods)
    {
      // Skip the set-up when every sequence of this method is done already.
      const int runs = name == "ght" ? std::min<int>(o.ght_sequences, sequences.size()) : sequences.size();
      int todo = 0;
      for (int s = 0; s < runs; ++s)
        todo += !fs::exists(fs::path(o.out) / (sequences[s].filename().string() + "." + name + ".jsonl"));
      if (todo == 0)
        continue;
      std::string init;
      cv::setNumThreads(-1);  // the set-up may use every core
      const auto start = std::chrono::steady_clock::now();
      std::unique_ptr<Method> method = makeMethod(name, o, prototypes, init);
      const double init_ms = millisecondsSince(start);
      cv::setNumThreads(1);  // frames: one core for every method
      writeAtomically(fs::path(o.out) / ("init." + name + ".json"),
                      "{\"init_ms\": " + number(init_ms) + (init.empty() ? "" : ", " + init) + "}\n");
      std::cerr << fs::path(o.suite).filename().string() << ": " << name << " ready in " << number(init_ms / 1000) << " s, "
                << todo << " sequences to run\n";

      for (int s = 0; s < runs; ++s)
      {
        const fs::path result = fs::path(o.out) / (sequences[s].filename().string() + "." + name + ".jsonl");
        if (fs::exists(result))
          continue;
        std::vector<cv::String> files;
        cv::glob((sequences[s] / "frames" / "*.png").string(), files);
        std::sort(files.begin(), files.end());
        const int count = static_cast<int>(files.size());
        const std::vector<bool> run = framesToRun(name, count, o);
        method->reset();
        // AMCR: the recall funnel against the sequence's truth, outside the timed step.
        const auto* amcr_method = dynamic_cast<const amcr_bench::AmcrMethod*>(method.get());
        const std::vector<amcr_bench::TruthFrame> truth =
            amcr_method ? amcr_bench::readSequenceTruth((sequences[s] / "truth.json").string())
                        : std::vector<amcr_bench::TruthFrame>();
        amcr_bench::FunnelRecorder funnel;
        std::string lines, funnel_lines;
        for (int k = 0; k < count; ++k)
        {
          if (!run[k])
            continue;
          const cv::Mat frame = cv::imread(files[k], cv::IMREAD_GRAYSCALE);
          if (frame.empty())
            throw std::runtime_error("cannot read " + files[k]);
          const auto t0 = std::chrono::steady_clock::now();
          const std::vector<Detection> found = method->detect(frame);
          lines += jsonLine(k, millisecondsSince(t0), found) + "\n";
          if (amcr_method && k < static_cast<int>(truth.size()))
          {
            const std::vector<amcr_bench::ObjectFunnel> objects =
                amcr_bench::measureFunnel(amcr_method->recognizer(), amcr_method->lastResult(), truth[k]);
            funnel.add(k, objects);
            funnel_lines += amcr_bench::funnelJson(k, objects) + "\n";
          }
        }
        if (amcr_method)
          writeAtomically(fs::path(o.out) / (sequences[s].filename().string() + ".amcr.funnel.jsonl"),
                          funnel_lines + amcr_bench::funnelSummaryJson(funnel.summaries()) + "\n");
        writeAtomically(result, lines);
      }
    }
  }
  catch (const std::exception& e)
  {
    std::cerr << "amcr_evaluate: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
