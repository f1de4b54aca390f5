#include "runner_options.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <limits>
#include <set>

namespace amcr
{
namespace offline
{
namespace
{
/// Parses a non-negative decimal integer (digits only) that fits `max`.
bool parseUnsigned(const std::string& text, std::uint64_t max, std::uint64_t& out)
{
  if (text.empty() || text.size() > 20)
    return false;
  std::uint64_t value = 0;
  for (const char c : text)
  {
    if (c < '0' || c > '9')
      return false;
    const std::uint64_t digit = static_cast<std::uint64_t>(c - '0');
    if (value > (max - digit) / 10)
      return false;
    value = value * 10 + digit;
  }
  out = value;
  return true;
}

std::string lower(std::string text)
{
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

std::string extension(const std::string& path)
{
  const std::size_t slash = path.find_last_of("/\\");
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash))
    return "";
  return lower(path.substr(dot));
}
}  // namespace

std::string overlayFourcc(const std::string& path)
{
  const std::string ext = extension(path);
  if (ext == ".avi")
    return "MJPG";
  if (ext == ".mp4" || ext == ".m4v" || ext == ".mov")
    return "mp4v";
  return "";
}

RunnerOptions parseRunnerOptions(const std::vector<std::string>& args)
{
  RunnerOptions options;
  std::set<std::string> seen;
  for (std::size_t i = 0; i < args.size(); ++i)
  {
    const std::string& arg = args[i];
    if (arg == "--help" || arg == "-h")
    {
      options.help = true;
      continue;
    }
    if (arg.size() < 3 || arg.compare(0, 2, "--") != 0)
      throw UsageError("unexpected argument '" + arg + "' (options start with --)");

    std::string name = arg;
    std::string value;
    bool has_value = false;
    const std::size_t equals = arg.find('=');
    if (equals != std::string::npos)
    {
      name = arg.substr(0, equals);
      value = arg.substr(equals + 1);
      has_value = true;
    }
    static const std::set<std::string> kKnown = {"--prototypes", "--input",  "--config", "--seed",
                                                 "--frames",     "--output", "--overlay"};
    if (kKnown.count(name) == 0)
      throw UsageError("unknown option '" + name + "'");
    if (!seen.insert(name).second)
      throw UsageError("option " + name + " given twice");
    if (!has_value)
    {
      if (i + 1 >= args.size() || args[i + 1].compare(0, 2, "--") == 0)
        throw UsageError("option " + name + " needs a value");
      value = args[++i];
    }
    if (value.empty())
      throw UsageError("option " + name + " needs a non-empty value");

    if (name == "--prototypes")
      options.prototypes = value;
    else if (name == "--input")
      options.input = value;
    else if (name == "--config")
      options.config = value;
    else if (name == "--output")
      options.output = value;
    else if (name == "--overlay")
    {
      if (overlayFourcc(value).empty())
        throw UsageError("--overlay '" + value + "': unsupported video type (use .avi for MJPG or .mp4 for mp4v)");
      options.overlay = value;
    }
    else if (name == "--seed")
    {
      if (!parseUnsigned(value, std::numeric_limits<std::uint64_t>::max(), options.seed))
        throw UsageError("--seed '" + value + "': expected an integer in [0, 18446744073709551615]");
      options.has_seed = true;
    }
    else if (name == "--frames")
    {
      std::uint64_t frames = 0;
      const std::uint64_t max = 1000000000;
      if (!parseUnsigned(value, max, frames) || frames < 1)
        throw UsageError("--frames '" + value + "': expected an integer in [1, 1000000000]");
      options.frames = static_cast<long>(frames);
      options.has_frames = true;
    }
  }
  if (!options.help)
  {
    if (options.prototypes.empty())
      throw UsageError("missing --prototypes DIR");
    if (options.input.empty())
      throw UsageError("missing --input PATH");
  }
  return options;
}

std::string usageText()
{
  return R"(Usage: amcr_offline --prototypes DIR --input PATH [options]

Runs Radial-AMCR (Active Monte Carlo Recognition) on recorded images and
writes one JSON object per input frame, one per line.

Required:
  --prototypes DIR    directory of prototype silhouettes: loose image files
                      (label = file name without extension) and label
                      directories (label = the directory's name, each image
                      in it an instance); unusable files are skipped with a
                      warning, an error if none is left
  --input PATH        a video file, a directory of images (taken in file-name
                      order; files without an image extension are ignored), or
                      one image (repeated --frames times)

Options:
  --config FILE.yaml  parameters (see config/amcr.yaml); defaults otherwise
  --seed N            seed of the random generator, overrides the YAML's seed
                      (0..18446744073709551615); same seed, same output
  --frames N          frames made from a single image (default 100); for a
                      video or a directory, the most frames read
  --output FILE       write the JSON lines to FILE (default: standard output)
  --overlay FILE      write an overlay video: the input with V-particles and
                      recognized outlines, beside it the prototypes with their
                      M-particles and the correspondence lines. The type comes
                      from the extension: .avi (MJPG) or .mp4 (mp4v). Its frame
                      rate is the input video's, else 10 fps; frames of another
                      size than the first are scaled to the first's size.
  --help, -h          print this text and exit

Output, one line per input frame (numbers in px, time in ms):
  {"frame": 0, "time_ms": 3.100, "iteration": 1, "objects": [{"label": "bird",
   "instance": "bird/bird-1.png", "track_id": 1, "state": "held", "score": 0.9300, "support": 17,
   "image_to_prototype": [[a, b, c], [d, e, f]],
   "prototype_to_image": [[a, b, c], [d, e, f]],
   "correspondences": [[x_image, y_image, x_prototype, y_prototype], ...]}],
   "lost": [...]}
  Each line also holds "iterations" (the share of an iteration the frame
  ran) and "mean_m_particles" (M-particles per V-particle, which
  KLD-sampling adapts). "state" is where the object is in its life cycle:
  "tentative" (reported in fewer than confirm_frames frames), "confirmed",
  "held" (confirmed and followed by the tracker). "lost" lists the objects
  whose tracks ended at this frame (as last reported, "state": "lost").
  "objects" is empty when nothing is recognized. Prototype coordinates are
  pixels of the original prototype file (OpenCV pixel-centre convention).
  Numbers that are not finite are written as null.

Unreadable frames: a file of a directory input that cannot be read as an
image is reported on standard error as a warning and gets a line without a
recognition step, so line N stays the N-th file:
  {"frame": 3, "time_ms": 0.000, "iteration": 12, "objects": [],
   "skipped": "cannot read image '...'"}
The overlay video holds only the frames that were processed. It is an error
when no frame at all could be read.

Damaged videos: a video that ends before the frame count of its container
(truncated or corrupt), or whose read fails, keeps the lines of the frames
that were read; the runner then says on standard error how many frames of
how many it read, and exits with 3.

Exit status:
  0  success: every frame of the input was read
  1  an error (missing or unreadable input or prototypes, a parameter out of
     range, an unusable image, a write failure)
  2  a bad command line
  3  the input ended early (a truncated or corrupt video): the frames read
     are written, the rest is missing
Errors are one line on standard error:
  amcr_offline: error: <what>
)";
}
}  // namespace offline
}  // namespace amcr
