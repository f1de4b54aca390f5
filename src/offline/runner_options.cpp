#include "runner_options.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <limits>
#include <set>

#include <boost/program_options.hpp>

namespace po = boost::program_options;

namespace amcr
{
namespace offline
{
namespace
{
/// Parses a non-negative decimal integer (digits only) in [min, max].
bool parseUnsigned(const std::string& text, std::uint64_t min, std::uint64_t max, std::uint64_t& out)
{
  std::uint64_t value = 0;
  const char* end = text.data() + text.size();
  const std::from_chars_result parsed = std::from_chars(text.data(), end, value);
  if (parsed.ec != std::errc() || parsed.ptr != end || value < min || value > max)
    return false;
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

bool startsWithDashes(const std::string& text) { return text.compare(0, 2, "--") == 0; }

/// The options with a value, by name without the dashes; --help (-h) has none.
const char* const kValueOptions[] = {"prototypes", "input",   "config",      "seed",
                                     "frames",     "output", "overlay", "write-models"};

/// Splits the command line with program_options: "--name value" and
/// "--name=value", no abbreviations, "-h" for --help. Unknown options and
/// stray arguments are returned too (unregistered or positional), so that
/// parseRunnerOptions names them in the runner's words, in the order given.
std::vector<po::option> splitOptions(const std::vector<std::string>& args)
{
  po::options_description known;
  known.add_options()("help,h", "");
  for (const char* name : kValueOptions)
    known.add_options()(name, po::value<std::string>(), "");
  namespace style = po::command_line_style;
  try
  {
    return po::command_line_parser(args)
        .options(known)
        .style(style::allow_long | style::long_allow_adjacent | style::long_allow_next | style::allow_short |
               style::short_allow_next | style::allow_dash_for_short)
        .allow_unregistered()
        .run()
        .options;
  }
  catch (const po::invalid_command_line_syntax& e)
  {
    const std::string name = e.get_option_name();
    switch (e.kind())
    {
      case po::invalid_command_line_syntax::missing_parameter:
        throw UsageError("option " + name + " needs a value");
      case po::invalid_command_line_syntax::empty_adjacent_parameter:
        throw UsageError("option " + name + " needs a non-empty value");
      case po::invalid_command_line_syntax::extra_parameter:
        throw UsageError("option " + name + " takes no value");
      default:
        throw UsageError(e.what());
    }
  }
  catch (const po::error& e)
  {
    throw UsageError(e.what());
  }
}

/// Sets the field of option `name` ("--seed") from its non-empty `value`.
void setOption(RunnerOptions& options, const std::string& name, const std::string& value)
{
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
  else if (name == "--write-models")
    options.write_models = value;
  else if (name == "--seed")
  {
    if (!parseUnsigned(value, 0, std::numeric_limits<std::uint64_t>::max(), options.seed))
      throw UsageError("--seed '" + value + "': expected an integer in [0, 18446744073709551615]");
    options.has_seed = true;
  }
  else if (name == "--frames")
  {
    std::uint64_t frames = 0;
    if (!parseUnsigned(value, 1, 1000000000, frames))
      throw UsageError("--frames '" + value + "': expected an integer in [1, 1000000000]");
    options.frames = static_cast<long>(frames);
    options.has_frames = true;
  }
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
  for (const po::option& option : splitOptions(args))
  {
    const std::string token = option.original_tokens.empty() ? "" : option.original_tokens.front();
    if (option.position_key >= 0 || (option.unregistered && !startsWithDashes(token)))
      throw UsageError("unexpected argument '" + token + "' (options start with --)");
    if (option.unregistered)
      throw UsageError("unknown option '" + token.substr(0, token.find('=')) + "'");
    if (option.string_key == "help")
    {
      options.help = true;
      continue;
    }
    const std::string name = "--" + option.string_key;
    if (!seen.insert(name).second)
      throw UsageError("option " + name + " given twice");
    // program_options takes the next word as the value even when it is an
    // option ("--input --frames 3"): that is an option whose value is missing.
    if (option.original_tokens.size() == 2 && startsWithDashes(option.original_tokens[1]))
      throw UsageError("option " + name + " needs a value");
    const std::string value = option.value.empty() ? "" : option.value.front();
    if (value.empty())
      throw UsageError("option " + name + " needs a non-empty value");
    setOption(options, name, value);
  }
  if (!options.help)
  {
    if (options.prototypes.empty())
      throw UsageError("missing --prototypes DIR");
    if (options.input.empty() && options.write_models.empty())
      throw UsageError("missing --input PATH");
  }
  return options;
}

std::string usageText()
{
  return R"(Usage: amcr_offline --prototypes DIR --input PATH [options]
       amcr_offline --prototypes DIR --write-models DIR [--config FILE.yaml]

Runs Radial-AMCR (Active Monte Carlo Recognition) on recorded images and
writes one JSON object per input frame, one per line.

Required:
  --prototypes DIR    directory of prototype images (silhouettes, or grey
                      templates whose edges are the model): loose image files
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
  --write-models DIR  write each prototype's model as a picture to DIR
                      (created if missing), DIR/<instance>.model.png: the
                      image it was scanned in, its region, and every point
                      the score checks, with its normal; how a grey template
                      was read is checked there. Without --input, only that.
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
