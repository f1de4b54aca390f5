#include "parameter_loading.h"

#include <charconv>
#include <filesystem>
#include <limits>
#include <map>
#include <system_error>

#include "amcr/base/errors.h"
#include "amcr/io/params_file.h"

namespace amcr_ros
{
namespace
{
/// ~seed given as a string: every 64-bit seed, which an XML-RPC integer
/// (32-bit) cannot carry. Whole decimal digits only, as amcr_offline --seed.
std::uint64_t seedFromText(const std::string& text)
{
  std::uint64_t seed = 0;
  const char* end = text.data() + text.size();
  const auto parsed = std::from_chars(text.data(), end, seed);
  if (text.empty() || parsed.ec != std::errc() || parsed.ptr != end)
    throw amcr::ParameterError("~seed '" + text + "' must be a whole number in [0, " +
                               std::to_string(std::numeric_limits<std::uint64_t>::max()) + "]");
  return seed;
}
}  // namespace

amcr::Params loadParams(const ros::NodeHandle& private_nh, std::vector<std::string>* notes)
{
  amcr::Params params;
  std::string config;
  if (private_nh.getParam("config", config) && !config.empty())
  {
    std::error_code error;
    if (!std::filesystem::is_regular_file(config, error))
      throw amcr::ParameterError("~config: file '" + config + "' does not exist or is not a file");
    params = amcr::loadParams(config, params);  // a ParameterError names the file and the line
    if (notes)
      notes->push_back("config file " + config);
  }

  for (const amcr::ParameterInfo& info : amcr::parameterTable())
  {
    if (!private_nh.hasParam(info.name))
      continue;
    std::string seed_text;
    if (info.name == "seed" && private_nh.getParam(info.name, seed_text))
    {
      params.seed = seedFromText(seed_text);
      if (notes)
        notes->push_back("seed = " + seed_text);
      continue;
    }
    double value = 0.0;
    int int_value = 0;
    bool bool_value = false;
    if (private_nh.getParam(info.name, value))
      ;
    else if (private_nh.getParam(info.name, int_value))
      value = int_value;
    else if (private_nh.getParam(info.name, bool_value))
      value = bool_value ? 1.0 : 0.0;
    else
      throw amcr::ParameterError("~" + info.name + " must be a number (" + info.unit + ", [" +
                                 std::to_string(info.min) + ", " + std::to_string(info.max) + "])" +
                                 (info.name == "seed" ? " or, for a seed above 2147483647, a string of digits" : ""));
    amcr::setParameter(params, info.name, value);
    if (notes)
      notes->push_back(info.name + " = " + std::to_string(value));
  }
  for (const amcr::WordParameterInfo& info : amcr::wordParameterTable())
  {
    if (info.name == "prototype_priors" || !private_nh.hasParam(info.name))
      continue;  // prototype_priors below: a map or a string
    std::string value;
    if (!private_nh.getParam(info.name, value))
      throw amcr::ParameterError("~" + info.name + " must be a string: " + info.takes);
    amcr::setParameter(params, info.name, value);
    if (notes)
      notes->push_back(info.name + " = " + value);
  }
  // ~prototype_priors: a map {label: weight} or the string "label: weight, ...".
  if (private_nh.hasParam("prototype_priors"))
  {
    std::map<std::string, double> priors;  // checked by params.validate() below
    std::string text;
    if (private_nh.getParam("prototype_priors", priors))
      params.prototype_priors = priors;
    else if (private_nh.getParam("prototype_priors", text))
      amcr::setParameter(params, "prototype_priors", text);
    else
      throw amcr::ParameterError("~prototype_priors must be a map {label: weight} or a string 'label: weight, ...'");
    if (notes)
      notes->push_back("prototype_priors = " + amcr::formatPriors(params.prototype_priors));
  }
  params.validate();
  return params;
}
}  // namespace amcr_ros
