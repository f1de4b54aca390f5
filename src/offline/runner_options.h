// Command line of amcr_offline.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace amcr
{
namespace offline
{
/// A bad command line: the message names the option and what was wrong.
class UsageError : public std::runtime_error
{
public:
  explicit UsageError(const std::string& what) : std::runtime_error(what) {}
};

struct RunnerOptions
{
  bool help = false;
  std::string prototypes;  ///< --prototypes DIR (required)
  std::string input;       ///< --input PATH (required unless --write-models)
  std::string config;      ///< --config FILE.yaml, empty: built-in defaults
  bool has_seed = false;
  std::uint64_t seed = 0;  ///< --seed N, overrides the YAML's seed
  bool has_frames = false;
  long frames = 100;       ///< --frames N: repeats of a single image; cap for videos and directories
  std::string output;      ///< --output FILE.jsonl, empty: standard output
  std::string overlay;     ///< --overlay FILE (.avi: MJPG, .mp4: mp4v), empty: none
  std::string write_models;  ///< --write-models DIR: each prototype's edge model as a picture, empty: none
};

/// The default number of frames made from a single image.
constexpr long kDefaultSingleImageFrames = 100;

/// Parses the arguments after the program name (Boost.Program_options splits
/// them). Accepts "--name value" and "--name=value", never an abbreviated
/// name; "--" ends the options, so what follows it is a stray argument.
/// Throws UsageError for an unknown option, a missing or malformed value, an
/// option given twice, a stray argument, a missing required option (unless
/// --help), or an overlay file of unknown type.
RunnerOptions parseRunnerOptions(const std::vector<std::string>& args);

/// The --help text.
std::string usageText();

/// The video codec for an overlay file, from its extension (case-insensitive):
/// .avi -> "MJPG", .mp4 / .m4v / .mov -> "mp4v". Empty when unsupported.
std::string overlayFourcc(const std::string& path);
}  // namespace offline
}  // namespace amcr
