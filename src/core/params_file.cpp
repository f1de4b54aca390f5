// loadParams: the parameter file read as text (so that a missing header, a
// read error and the literal text of whole numbers can be handled), then
// parsed by cv::FileStorage from memory.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <vector>

#include <opencv2/core.hpp>

#include "amcr/errors.h"
#include "amcr/params.h"
#include "amcr/resource_bounds.h"

namespace amcr
{
namespace
{
namespace fs = std::filesystem;

constexpr long long kLargestExactInteger = 9007199254740992LL;  // 2^53

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

/// "line N: reason" from a cv::FileStorage parse error, whose text is
/// "<file>(<line>): <reason>" in e.err, or in e.func (OpenCV 4.5 to 4.8 pass
/// the two the other way round). `added_lines` were put before the file's text.
std::string parseErrorText(const cv::Exception& e, int added_lines)
{
  for (const std::string& part : {e.err, e.func})
  {
    const std::size_t close = part.find("): ");
    const std::size_t open = close == std::string::npos ? close : part.rfind('(', close);
    if (open == std::string::npos || open + 1 == close)
      continue;
    const std::string digits = part.substr(open + 1, close - open - 1);
    if (digits.find_first_not_of("0123456789") != std::string::npos)
      continue;
    return "line " + std::to_string(std::max(1, std::stoi(digits) - added_lines)) + ": " + part.substr(close + 3);
  }
  return e.err.empty() ? std::string(e.what()) : e.err;
}

/// The text of a value as written after `key:` in the file, and its line (1-based).
struct Literal
{
  std::string text;
  int line = 0;
};

/// Finds `key:` at the start of a line, after whitespace, '{' or ',' (outside
/// comments), and returns the value that follows, up to ',', '}', a space or
/// the end of the line. The last one wins, as a later key overrides.
Literal findLiteral(const std::vector<std::string>& lines, const std::string& key)
{
  Literal found;
  for (std::size_t l = 0; l < lines.size(); ++l)
  {
    const std::string& line = lines[l];
    for (std::size_t at = line.find(key); at != std::string::npos; at = line.find(key, at + 1))
    {
      if (at > 0 && std::string(" \t{,").find(line[at - 1]) == std::string::npos)
        continue;
      std::size_t pos = line.find_first_not_of(" \t", at + key.size());
      if (pos == std::string::npos || line[pos] != ':')
        continue;
      pos = line.find_first_not_of(" \t", pos + 1);
      if (pos == std::string::npos)
        continue;
      const std::size_t end = line.find_first_of(" \t,}", pos);
      found = {line.substr(pos, end == std::string::npos ? std::string::npos : end - pos), static_cast<int>(l) + 1};
    }
  }
  return found;
}

/// The file's lines with comments ('#' at the start or after whitespace, outside quotes) removed.
std::vector<std::string> codeLines(const std::string& text)
{
  std::vector<std::string> lines;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
  {
    char quote = 0;
    for (std::size_t i = 0; i < line.size(); ++i)
    {
      const char c = line[i];
      if (quote)
        quote = c == quote ? 0 : quote;
      else if (c == '"' || c == '\'')
        quote = c;
      else if (c == '#' && (i == 0 || line[i - 1] == ' ' || line[i - 1] == '\t'))
      {
        line.resize(i);
        break;
      }
    }
    lines.push_back(line);
  }
  return lines;
}

/// A number node's value. cv::FileStorage reads a whole number as a 32-bit
/// int (strtol, then a cast), so 4294967326 would become 30: its text is
/// read again here, as cv::FileStorage reads it (base 0: 0x1F, 010 octal).
double numberValue(const cv::FileNode& node, const Literal& literal, const std::string& name)
{
  if (!node.isInt())
    return node.real();
  const int parsed = static_cast<int>(node);
  if (literal.text.empty())
    return parsed;
  errno = 0;
  char* end = nullptr;
  const long long value = std::strtoll(literal.text.c_str(), &end, 0);
  if (end != literal.text.c_str() + literal.text.size())
    return parsed;  // not the text the parser read
  if (errno == ERANGE || value > kLargestExactInteger || value < -kLargestExactInteger)
    throw ParameterError("parameter '" + name + "' = " + literal.text +
                         " is beyond 2^53 = 9007199254740992, the largest whole number read exactly");
  if (static_cast<int>(static_cast<unsigned int>(value)) != parsed)
    return parsed;  // not the text the parser read
  return static_cast<double>(value);
}

void readPriors(const cv::FileNode& node, const std::vector<std::string>& lines, Params& params)
{
  params.prototype_priors.clear();
  for (const cv::FileNode& prior : node)
  {
    if (!prior.isInt() && !prior.isReal())
      throw ParameterError("parameter 'prototype_priors': the weight of '" + prior.name() + "' must be a number");
    const double weight = numberValue(prior, findLiteral(lines, prior.name()), "prototype_priors: " + prior.name());
    if (!std::isfinite(weight) || weight < 0.0)
      throw ParameterError("parameter 'prototype_priors': the weight of '" + prior.name() + "' = " +
                           formatNumber(weight) + " must be a finite number >= 0");
    params.prototype_priors[prior.name()] = weight;
  }
}

void readEntry(const cv::FileNode& node, const std::vector<std::string>& lines, Params& params)
{
  const std::string name = node.name();
  if (name == "prototype_priors" && node.isMap())
    readPriors(node, lines, params);
  else if (node.isString())
    setParameter(params, name, static_cast<std::string>(node));
  else if (node.isInt() || node.isReal())
    setParameter(params, name, numberValue(node, findLiteral(lines, name), name));
  else
    throw ParameterError("parameter '" + name + "' must be a number or a word (prototype_priors: a map)");
}
}  // namespace

/// The YAML that a parameter file may hold, checked line by line before
/// OpenCV reads it, because OpenCV's YAML reader (4.6) never returns on some
/// malformed files (found by fuzzing: "%YAML:1.0\n---s:0\n\")--\nr", a
/// tagged key "!name:" followed by a line "name-", and an indented first
/// entry followed by an indented "...--"). Allowed: the header on line 1; one
/// document marker "---" alone on its line; a first entry that is not
/// indented; top-level lines "name: value" or "name:" (a block map follows,
/// indented) with a name of
/// letters, digits and _, or a flow map "{...}"; indented lines of a map or a
/// flow value. Refused: other directives, a second document, YAML tags,
/// anchors, aliases and block scalars (!, &, *, |, >), and any other top-level
/// line. What passes is plain YAML that OpenCV parses or refuses with a line.
void checkLineForms(const std::vector<std::string>& lines, const std::string& yaml_path)
{
  static const std::string kYamlOnlySigils = "!&*|>%@`";
  bool started = false;  // the document marker was seen
  bool opened = false;   // an entry was seen
  for (std::size_t l = 0; l < lines.size(); ++l)
  {
    const std::string& line = lines[l];  // comments removed
    const std::string where = "cannot parse the parameter file '" + yaml_path + "', line " + std::to_string(l + 1) + ": ";
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || (l == 0 && line.compare(0, 5, "%YAML") == 0))
      continue;
    if (line.compare(0, 3, "---") == 0 || line.compare(0, 3, "...") == 0)
    {
      if (started || line[0] == '.')
        throw ParameterError(where + "a second document marker ('" + line.substr(0, 3) + "'): a parameter file is one document");
      if (line.find_first_not_of(" \t\r", 3) != std::string::npos)
        throw ParameterError(where + "the document marker '---' must stand alone on its line");
      started = true;
      continue;
    }
    // The top level starts at column 1: OpenCV never returned on an indented
    // top-level map followed by an indented "...--" (found by fuzzing).
    if (!opened && first != 0)
      throw ParameterError(where + "the first entry must not be indented: '" + line + "'");
    opened = true;
    const std::size_t colon = line.find(':', first);
    if (first == 0 && line[0] != '{')
    {
      std::size_t name_end = 0;
      while (name_end < line.size() && (std::isalnum(static_cast<unsigned char>(line[name_end])) || line[name_end] == '_'))
        ++name_end;
      const std::size_t after = line.find_first_not_of(" \t", name_end);
      if (name_end == 0 || std::isdigit(static_cast<unsigned char>(line[0])) || after == std::string::npos || line[after] != ':')
        throw ParameterError(where + "expected 'name: value' (a name of letters, digits and _), not '" + line + "'");
    }
    const std::size_t value = colon == std::string::npos ? first : line.find_first_not_of(" \t\r", colon + 1);
    if (kYamlOnlySigils.find(line[first]) != std::string::npos ||
        (value != std::string::npos && kYamlOnlySigils.find(line[value]) != std::string::npos))
      throw ParameterError(where + "YAML tags, anchors, aliases, block scalars and directives (" + kYamlOnlySigils +
                           ") are not parameter values: '" + line + "'");
  }
}

Params loadParams(const std::string& yaml_path, Params params)
{
  std::string text = readText(yaml_path);
  // cv::FileStorage wants the OpenCV header; a file without it gets one
  // (and the line numbers of its errors are counted without it).
  const bool has_header = text.compare(0, 5, "%YAML") == 0;
  const int added_lines = has_header ? 0 : 1;
  const std::vector<std::string> lines = codeLines(text);
  checkLineForms(lines, yaml_path);
  if (!has_header)
    text = "%YAML:1.0\n" + text;
  cv::FileStorage storage;
  try
  {
    if (!storage.open(text, cv::FileStorage::READ | cv::FileStorage::MEMORY | cv::FileStorage::FORMAT_YAML))
      throw ParameterError("cannot parse the parameter file '" + yaml_path + "'");
  }
  catch (const cv::Exception& e)
  {
    throw ParameterError("cannot parse the parameter file '" + yaml_path + "', " + parseErrorText(e, added_lines));
  }
  catch (const std::exception& e)  // OpenCV's YAML parser also throws std::length_error
  {
    throw ParameterError("cannot parse the parameter file '" + yaml_path + "': malformed YAML (" + e.what() + ")");
  }
  const cv::FileNode root = storage.root();
  if (root.empty() || root.isNone())
  {
    params.validate();  // an empty file: every value stays
    return params;
  }
  if (!root.isMap())
    throw ParameterError("the parameter file '" + yaml_path + "' is not a map of name: value");
  std::set<std::string> seen;
  for (const cv::FileNode& node : root)
  {
    try
    {
      if (!seen.insert(node.name()).second)
        throw ParameterError("parameter '" + node.name() + "' is given twice");
      readEntry(node, lines, params);
    }
    catch (const ParameterError& e)
    {
      const Literal literal = findLiteral(lines, node.name());
      throw ParameterError(yaml_path + (literal.line ? ":" + std::to_string(literal.line) : "") + ": " + e.what());
    }
  }
  try
  {
    params.validate();
  }
  catch (const ParameterError& e)
  {
    throw ParameterError(yaml_path + ": " + e.what());
  }
  return params;
}
}  // namespace amcr
