// amcr_offline: Radial-AMCR on recorded data, without ROS (for benchmarks,
// tests and recordings at hand). One JSON line per input frame; optionally
// an overlay video. See usageText() for the command line, the output and
// the exit codes.
//
// Only this file decides exit codes: the library and the helpers throw.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "amcr/base/errors.h"
#include "amcr/base/params.h"
#include "amcr/io/params_file.h"
#include "amcr/memory/edge_model.h"
#include "amcr/memory/edge_model_picture.h"
#include "amcr/memory/prototype_memory.h"
#include "amcr/overlay.h"
#include "amcr/recognizer.h"
#include "frame_source.h"
#include "json_output.h"
#include "runner_options.h"

namespace
{
using namespace amcr::offline;

constexpr const char* kProgram = "amcr_offline";
constexpr int kExitError = 1;
constexpr int kExitUsage = 2;
constexpr int kExitIncomplete = 3;  // the input ended early: what was read is written, the rest is missing
constexpr double kDefaultOverlayFps = 10.0;

/// One line: newlines and tabs become spaces, runs of spaces collapse.
std::string oneLine(const std::string& text)
{
  std::string out;
  out.reserve(text.size());
  for (const char c : text)
  {
    const char s = (c == '\n' || c == '\r' || c == '\t') ? ' ' : c;
    if (s == ' ' && (out.empty() || out.back() == ' '))
      continue;
    out += s;
  }
  while (!out.empty() && out.back() == ' ')
    out.pop_back();
  return out.empty() ? "unknown error" : out;
}

void reportError(const std::string& what) { std::cerr << kProgram << ": error: " << oneLine(what) << std::endl; }

void reportWarning(const std::string& what)
{
  std::cerr << kProgram << ": warning: " << oneLine(what) << std::endl;
}

amcr::Params loadConfiguredParams(const RunnerOptions& options)
{
  amcr::Params params;
  if (!options.config.empty())
  {
    std::error_code error;
    if (!std::filesystem::is_regular_file(options.config, error))
      throw std::runtime_error("config file '" + options.config + "' does not exist or is not a file");
    params = amcr::loadParams(options.config);  // a ParameterError names the file and the line
  }
  if (options.has_seed)
    params.seed = options.seed;
  params.validate();
  return params;
}

/// Writes overlay frames; the video is opened at the first frame, whose size
/// all later frames are scaled to.
class OverlayVideo
{
public:
  OverlayVideo(std::string path, double fps) : path_(std::move(path)), fps_(fps) {}

  void write(const cv::Mat& frame)
  {
    if (!writer_.isOpened())
    {
      const std::string fourcc = overlayFourcc(path_);
      writer_.open(path_, cv::VideoWriter::fourcc(fourcc[0], fourcc[1], fourcc[2], fourcc[3]), fps_, frame.size(),
                   true);
      if (!writer_.isOpened())
        throw std::runtime_error("cannot open overlay video '" + path_ + "' for writing (codec " + fourcc + ")");
      size_ = frame.size();
    }
    if (frame.size() == size_)
      writer_.write(frame);
    else
    {
      cv::Mat scaled;
      cv::resize(frame, scaled, size_, 0, 0, cv::INTER_AREA);
      writer_.write(scaled);
    }
  }

  void close() { writer_.release(); }

private:
  std::string path_;
  double fps_;
  cv::VideoWriter writer_;
  cv::Size size_;
};

std::shared_ptr<amcr::PrototypeMemory> loadMemory(const RunnerOptions& options, const amcr::Params& params)
{
  return std::make_shared<amcr::PrototypeMemory>(
      amcr::PrototypeMemory::loadDirectory(options.prototypes, params, reportWarning, [](const std::string& line) {
        std::cerr << "amcr_offline: " << line << "\n";
      }));
}

/// Each prototype's edge model (amcr/memory/edge_model.h) as DIR/<instance>.model.png:
/// the instance's file name without its extension, its folders joined by '_'
/// ("bird/bird-3.png" -> "bird_bird-3.model.png").
void writeModels(const amcr::PrototypeMemory& memory, const std::string& folder)
{
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (!std::filesystem::is_directory(folder, error))
    throw std::runtime_error("cannot write the models to '" + folder + "': not a folder that can be made");
  int templates = 0;
  for (std::size_t p = 0; p < memory.size(); ++p)
  {
    std::string name = std::filesystem::path(memory[p].instance()).replace_extension().string();
    for (char& c : name)
      c = (c == '/' || c == '\\') ? '_' : c;
    const std::string path = (std::filesystem::path(folder) / (name + ".model.png")).string();
    if (!cv::imwrite(path, amcr::drawEdgeModel(memory[p])))
      throw std::runtime_error("cannot write '" + path + "'");
    templates += memory[p].isTemplate() ? 1 : 0;
  }
  std::cerr << kProgram << ": wrote the models of " << memory.size() << " prototypes (" << templates
            << " grey templates, " << memory.size() - templates << " silhouettes) to '" << folder << "'"
            << std::endl;
}

int run(const RunnerOptions& options)
{
  // Cheap checks first, the prototype tables last.
  const amcr::Params params = loadConfiguredParams(options);
  if (options.input.empty())  // --write-models alone
  {
    writeModels(*loadMemory(options, params), options.write_models);
    return 0;
  }
  std::unique_ptr<FrameSource> source = FrameSource::open(
      options.input, options.has_frames ? options.frames : kDefaultSingleImageFrames, options.has_frames);

  std::ofstream file;
  std::ostream* out = &std::cout;
  std::string destination = "standard output";
  if (!options.output.empty())
  {
    file.open(options.output, std::ios::out | std::ios::trunc);
    if (!file)
      throw std::runtime_error("cannot open output file '" + options.output + "' for writing");
    out = &file;
    destination = "'" + options.output + "'";
  }

  // The overlay video opens at the first frame (its size is known then);
  // catch a missing folder before any work.
  if (!options.overlay.empty())
  {
    const std::filesystem::path folder = std::filesystem::path(options.overlay).parent_path();
    std::error_code error;
    if (!folder.empty() && !std::filesystem::is_directory(folder, error))
      throw std::runtime_error("cannot write overlay video '" + options.overlay + "': folder '" + folder.string() +
                               "' does not exist");
  }

  auto memory = loadMemory(options, params);
  if (!options.write_models.empty())
    writeModels(*memory, options.write_models);
  amcr::Recognizer recognizer(params, memory);
  for (const std::string& warning : recognizer.filter().indexWarnings())
    reportWarning(warning);

  std::unique_ptr<OverlayVideo> overlay;
  if (!options.overlay.empty())
    overlay = std::make_unique<OverlayVideo>(options.overlay, source->fps() > 0.0 ? source->fps() : kDefaultOverlayFps);

  long processed = 0;
  long over_limit_frames = 0;  // frames with objects found but not reported (max_objects)
  Frame frame;
  while (source->next(frame))
  {
    if (frame.image.empty())
    {
      reportWarning("frame " + std::to_string(frame.index) + " skipped: " + frame.problem);
      writeJsonLine(*out, skippedFrameJson(frame.index, recognizer.iteration(), frame.problem), destination);
      continue;
    }
    amcr::RecognitionResult result;
    try
    {
      result = recognizer.step(frame.image);
    }
    catch (const amcr::InputError& e)
    {
      throw amcr::InputError("frame " + std::to_string(frame.index) + " (" + frame.name + "): " + e.what());
    }
    writeJsonLine(*out, frameJson(frame.index, result), destination);
    if (result.objects_over_limit > 0 && over_limit_frames++ == 0)
      reportWarning("frame " + std::to_string(frame.index) + ": " + std::to_string(result.objects_over_limit) +
                    " objects found were not reported: max_objects (" + std::to_string(params.max_objects) +
                    ") tracks are kept already; raise max_objects to see them");
    if (overlay)
      overlay->write(amcr::drawOverlay(frame.image, recognizer, result));
    ++processed;
  }
  if (overlay)
    overlay->close();
  if (over_limit_frames > 0)
    reportWarning("objects found were not reported in " + std::to_string(over_limit_frames) + " of " +
                  std::to_string(processed) + " frames: max_objects (" + std::to_string(params.max_objects) +
                  ") was reached");
  const std::string incomplete = source->incomplete();
  if (processed == 0)
    throw std::runtime_error(incomplete.empty() ? "no frame of input '" + options.input + "' could be read"
                                                : incomplete);
  if (!incomplete.empty())
  {
    reportError(incomplete + "; the " + std::to_string(processed) + " frames read are written to " + destination);
    return kExitIncomplete;
  }
  return 0;
}
}  // namespace

int main(int argc, char** argv)
{
  // OpenCV logs its backends' failures (a video backend refusing a file) over
  // several lines; the runner reports problems itself, in one line. The
  // environment variable OPENCV_LOG_LEVEL still takes precedence.
  if (std::getenv("OPENCV_LOG_LEVEL") == nullptr)
    cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
  // The same for FFmpeg's own lines on a damaged video ("[mjpeg @ 0x...] error count: 64"): the runner
  // says in one line how far the video could be read (OpenCV >= 4.5 reads OPENCV_FFMPEG_LOGLEVEL; -8 is
  // FFmpeg's AV_LOG_QUIET).
  if (std::getenv("OPENCV_FFMPEG_LOGLEVEL") == nullptr && std::getenv("OPENCV_FFMPEG_DEBUG") == nullptr)
    setenv("OPENCV_FFMPEG_LOGLEVEL", "-8", 0);
  try
  {
    const RunnerOptions options = parseRunnerOptions(std::vector<std::string>(argv + 1, argv + argc));
    if (options.help)
    {
      std::cout << usageText();
      return 0;
    }
    return run(options);
  }
  catch (const UsageError& e)
  {
    reportError(std::string(e.what()) + " (see --help)");
    return kExitUsage;
  }
  catch (const cv::Exception& e)
  {
    reportError("OpenCV: " + e.err + (e.func.empty() ? "" : " (in " + e.func + ")"));
    return kExitError;
  }
  catch (const std::exception& e)
  {
    reportError(e.what());
    return kExitError;
  }
  catch (...)
  {
    reportError("unknown error");
    return kExitError;
  }
}
