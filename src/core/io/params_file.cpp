// loadParams: the parameter file read as text (so that a read error and
// OpenCV's header line are dealt with first), then parsed by yaml-cpp. Every
// error names the file and the line.
#include "amcr/io/params_file.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <optional>
#include <set>
#include <sstream>
#include <vector>

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include "amcr/base/errors.h"
#include "amcr/base/resource_bounds.h"
#include "number_text.h"

namespace amcr
{
namespace
{
namespace fs = std::filesystem;

/// Collections nested in each other: a parameter file needs 2 (the top map
/// and prototype_priors). yaml-cpp 0.6 recurses once per level without a
/// bound (a stack overflow on "[[[[..."), so deeper nesting is refused while
/// it parses, far below where that is a danger.
constexpr int kMaxNesting = 8;

/// An error at a place in the file; loadParams puts the file's name and the line in front.
struct LocatedError
{
  YAML::Mark mark;
  std::string reason;
};

[[noreturn]] void refuse(const YAML::Node& node, const std::string& reason)
{
  throw LocatedError{node.Mark(), reason};
}

/// The 1-based line of `mark`, within the file's lines (yaml-cpp places an
/// error at the end of the input on the line after a final newline).
int lineOf(const YAML::Mark& mark, const std::string& text)
{
  const int lines = static_cast<int>(std::count(text.begin(), text.end(), '\n')) +
                    (text.empty() || text.back() == '\n' ? 0 : 1);
  return std::clamp(mark.line + 1, 1, std::max(1, lines));
}

std::string readText(const std::string& path)
{
  const std::string prefix = "cannot read the parameter file '" + path + "': ";
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (error)
    throw ParameterError(prefix + error.message());
  if (fs::is_directory(status))
    throw ParameterError(prefix + "it is a directory");
  if (!fs::is_regular_file(status))
    throw ParameterError(prefix + "not a regular file");
  const std::uintmax_t size = fs::file_size(path, error);
  if (!error && size > static_cast<std::uintmax_t>(kMaxParameterFileBytes))
    throw ParameterError(prefix + "it has " + std::to_string(size) + " bytes, above the bound of " +
                         std::to_string(kMaxParameterFileBytes));
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw ParameterError(prefix + (errno ? std::strerror(errno) : "cannot open it"));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad())
    throw ParameterError(prefix + "a read error");
  const std::size_t nul = text.find('\0');
  if (nul != std::string::npos)
    throw ParameterError(prefix + "not a text file: a NUL byte on line " +
                         std::to_string(1 + std::count(text.begin(), text.begin() + nul, '\n')));
  return text;
}

/// OpenCV's header line "%YAML:1.0", which old amcr parameter files start
/// with, is a directive yaml-cpp refuses: it becomes a comment, so that every
/// line keeps its number.
void commentOutOpenCvHeader(std::string& text)
{
  if (text.compare(0, 6, "%YAML:") == 0)
    text[0] = '#';
}

/// Follows yaml-cpp's parse events before the tree is built, and stops the
/// parse (a ParserException at the place) at a second document or at a
/// collection nested deeper than kMaxNesting: yaml-cpp reports a
/// collection's start before it recurses into it.
class StructureCheck : public YAML::EventHandler
{
public:
  void OnDocumentStart(const YAML::Mark& mark) override
  {
    if (++documents_ > 1)
      throw YAML::ParserException(mark, "a second document: a parameter file is one document");
  }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t, const std::string&) override {}
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override
  {
    open(mark);
  }
  void OnSequenceEnd() override { --depth_; }
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override
  {
    open(mark);
  }
  void OnMapEnd() override { --depth_; }

private:
  void open(const YAML::Mark& mark)
  {
    if (++depth_ > kMaxNesting)
      throw YAML::ParserException(mark, "lists and maps nested deeper than " + std::to_string(kMaxNesting) +
                                            " (a parameter file needs 2: the top map and prototype_priors)");
  }
  int documents_ = 0;
  int depth_ = 0;
};

/// The file's one document; YAML::Exception when it is not valid YAML, not
/// one document or nested too deep.
YAML::Node parseDocument(const std::string& text)
{
  std::istringstream stream(text);
  YAML::Parser parser(stream);
  StructureCheck check;
  while (parser.HandleNextDocument(check))
  {
  }
  return YAML::Load(text);
}

bool isNumericParameter(const std::string& name)
{
  const auto& table = parameterTable();
  return std::any_of(table.begin(), table.end(), [&](const ParameterInfo& info) { return info.name == name; });
}

/// Runs `read`; a ParameterError it throws is placed at `node`.
void readAt(const YAML::Node& node, const std::function<void()>& read)
{
  try
  {
    read();
  }
  catch (const ParameterError& e)
  {
    refuse(node, e.what());
  }
}

/// YAML tags ("!!str", "!name") are no part of a parameter file; "?" (plain)
/// and "!" (quoted) are the tags yaml-cpp gives untagged nodes.
void refuseTag(const YAML::Node& node)
{
  const std::string& tag = node.Tag();
  if (!tag.empty() && tag != "?" && tag != "!")
    refuse(node, "YAML tags ('" + tag + "') are not parameter values");
}

std::string keyName(const YAML::Node& key)
{
  refuseTag(key);
  if (!key.IsScalar())
    refuse(key, std::string("a key must be a name, not ") + (key.IsNull() ? "empty" : "a list or a map"));
  return key.Scalar();
}

/// A plain scalar that is a number (or, for a numeric parameter, true or
/// false, as ROS parameters may be) goes to setParameter as a number; any
/// other scalar, quoted numbers included, as a word.
void readScalar(const std::string& name, const YAML::Node& value, Params& params)
{
  const std::string& text = value.Scalar();
  if (value.Tag() == "?")
  {
    if (const std::optional<double> number = numberFromText(text, name))
      return setParameter(params, name, *number);
    const bool is_true = text == "true" || text == "True" || text == "TRUE";
    if (isNumericParameter(name) && (is_true || text == "false" || text == "False" || text == "FALSE"))
      return setParameter(params, name, is_true ? 1.0 : 0.0);
  }
  setParameter(params, name, text);
}

void readPriors(const YAML::Node& map, Params& params)
{
  std::map<std::string, double> priors;
  for (const auto& prior : map)
  {
    const std::string label = keyName(prior.first);
    const std::string weight_of = "parameter 'prototype_priors': the weight of '" + label + "'";
    if (priors.count(label))
      refuse(prior.first, "parameter 'prototype_priors': '" + label + "' is given twice");
    refuseTag(prior.second);
    std::optional<double> weight;
    if (prior.second.IsScalar() && prior.second.Tag() == "?")
      readAt(prior.first, [&]() { weight = numberFromText(prior.second.Scalar(), "prototype_priors: " + label); });
    if (!weight)
      refuse(prior.first, weight_of + " must be a number");
    if (!std::isfinite(*weight) || *weight < 0.0)
      refuse(prior.first, weight_of + " = " + formatNumber(*weight) + " must be a finite number >= 0");
    priors[label] = *weight;
  }
  params.prototype_priors = priors;
}

void readEntry(const std::string& name, const YAML::Node& value, Params& params)
{
  refuseTag(value);
  if (name == "prototype_priors" && value.IsMap())
    readPriors(value, params);
  else if (value.IsScalar())
    readScalar(name, value, params);
  else
    throw ParameterError("parameter '" + name + "' must be a number or a word (prototype_priors: a map)");
}

/// A parameter read from the file, and the line of its key.
struct ReadEntry
{
  std::string name;
  YAML::Mark mark;
};

/// Reads the top-level map into `params`; an empty document keeps every value.
std::vector<ReadEntry> readEntries(const YAML::Node& root, Params& params)
{
  std::vector<ReadEntry> read;
  if (root.IsNull())
    return read;
  refuseTag(root);
  if (!root.IsMap())
    refuse(root, "the parameter file is not a map of name: value");
  std::set<std::string> seen;
  for (const auto& entry : root)
  {
    const std::string name = keyName(entry.first);
    readAt(entry.first, [&]() {
      if (!seen.insert(name).second)
        throw ParameterError("parameter '" + name + "' is given twice");
      readEntry(name, entry.second, params);
    });
    read.push_back({name, entry.first.Mark()});
  }
  return read;
}

/// "file:line: " of the last entry read that `message` names ('name'), or "file: ".
std::string placeOfNamedEntry(const std::string& path, const std::string& text, const std::vector<ReadEntry>& read,
                              const std::string& message)
{
  for (auto entry = read.rbegin(); entry != read.rend(); ++entry)
  {
    if (message.find("'" + entry->name + "'") != std::string::npos)
      return path + ":" + std::to_string(lineOf(entry->mark, text)) + ": ";
  }
  return path + ": ";
}
}  // namespace

Params loadParams(const std::string& yaml_path, Params params)
{
  std::string text = readText(yaml_path);
  commentOutOpenCvHeader(text);
  std::vector<ReadEntry> read;
  try
  {
    read = readEntries(parseDocument(text), params);
  }
  catch (const LocatedError& e)
  {
    throw ParameterError(yaml_path + ":" + std::to_string(lineOf(e.mark, text)) + ": " + e.reason);
  }
  catch (const YAML::Exception& e)
  {
    throw ParameterError("cannot parse the parameter file '" + yaml_path + "', line " +
                         std::to_string(lineOf(e.mark, text)) + ": " + e.msg);
  }
  catch (const std::exception& e)  // yaml-cpp may throw the standard library's exceptions too
  {
    throw ParameterError("cannot parse the parameter file '" + yaml_path + "': malformed YAML (" + e.what() + ")");
  }
  try
  {
    params.validate();
  }
  catch (const ParameterError& e)
  {
    throw ParameterError(placeOfNamedEntry(yaml_path, text, read, e.what()) + e.what());
  }
  return params;
}
}  // namespace amcr
