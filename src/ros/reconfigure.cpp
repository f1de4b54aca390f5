#include "reconfigure.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

#include "amcr/base/errors.h"

namespace amcr_ros
{
namespace
{
template <class T>
using Field = amcr::AMCRConfig::ParamDescription<T>;

template <class T>
const Field<T>* asField(const amcr::AMCRConfig::AbstractParamDescriptionConstPtr& description)
{
  return dynamic_cast<const Field<T>*>(description.get());
}

/// The parameters of cfg/AMCR.cfg, in its order: the generated descriptions
/// name each one and point at its member of amcr::AMCRConfig.
const std::vector<amcr::AMCRConfig::AbstractParamDescriptionConstPtr>& configFields()
{
  return amcr::AMCRConfig::__getParamDescriptions__();
}

/// A string parameter of cfg/AMCR.cfg as the core's table of word parameters reads it.
std::string textParameter(const amcr::Params& params, const std::string& name)
{
  for (const amcr::WordParameterInfo& info : amcr::wordParameterTable())
    if (info.name == name)
      return amcr::getWordParameter(params, name);
  throw amcr::ParameterError("cfg/AMCR.cfg has the string parameter '" + name + "', which amcr::Params does not know");
}

/// The core's range of `name`.
const amcr::ParameterInfo* coreInfo(const std::string& name)
{
  for (const amcr::ParameterInfo& info : amcr::parameterTable())
    if (info.name == name)
      return &info;
  return nullptr;
}

int clampToInt(double value)
{
  return static_cast<int>(std::clamp(value, static_cast<double>(std::numeric_limits<int>::min()),
                                     static_cast<double>(std::numeric_limits<int>::max())));
}

/// The seed as dynamic_reconfigure's int_t (32-bit) shows it: a 64-bit seed
/// (~seed given as a string) above its range is shown as its largest value.
int shownSeed(std::uint64_t seed)
{
  return static_cast<int>(std::min<std::uint64_t>(seed, std::numeric_limits<int>::max()));
}

/// A value for a log line: an int_t or bool_t of the .cfg as an integer ("60", not "60.000000").
std::string formatValue(const std::string& name, double value)
{
  std::ostringstream out;
  for (const auto& d : configFields())
    if (d->name == name && d->type != "double")
    {
      out << std::llround(value);
      return out.str();
    }
  out.precision(10);
  out << value;
  return out.str();
}
}  // namespace

amcr::AMCRConfig toConfig(const amcr::Params& params)
{
  amcr::AMCRConfig config = amcr::AMCRConfig::__getDefault__();
  for (const auto& d : configFields())
  {
    if (const auto* f = asField<int>(d))
      config.*(f->field) = d->name == "seed" ? shownSeed(params.seed)
                                             : static_cast<int>(amcr::getParameter(params, d->name));
    else if (const auto* f = asField<double>(d))
      config.*(f->field) = amcr::getParameter(params, d->name);
    else if (const auto* f = asField<bool>(d))
      config.*(f->field) = static_cast<bool>(amcr::getParameter(params, d->name));
    else if (const auto* f = asField<std::string>(d))
      config.*(f->field) = textParameter(params, d->name);
  }
  return config;
}

amcr::Params fromConfig(const amcr::AMCRConfig& config, amcr::Params params)
{
  for (const auto& d : configFields())
  {
    if (const auto* f = asField<int>(d))
    {
      if (d->name == "seed" && config.*(f->field) == shownSeed(params.seed))
        continue;  // unchanged: a 64-bit seed stays whole
      amcr::setParameter(params, d->name, static_cast<double>(config.*(f->field)));
    }
    else if (const auto* f = asField<double>(d))
      amcr::setParameter(params, d->name, config.*(f->field));
    else if (const auto* f = asField<bool>(d))
      amcr::setParameter(params, d->name, static_cast<double>(config.*(f->field)));
    else if (const auto* f = asField<std::string>(d))
      amcr::setParameter(params, d->name, config.*(f->field));
  }
  return params;
}

ConfigBounds reconfigureBounds()
{
  ConfigBounds bounds{amcr::AMCRConfig::__getDefault__(), amcr::AMCRConfig::__getDefault__()};
  for (const auto& d : configFields())
  {
    const amcr::ParameterInfo* info = coreInfo(d->name);
    if (!info)
      continue;  // a string, or a name test_reconfigure_table.cpp reports
    if (const auto* f = asField<int>(d))
    {
      bounds.min.*(f->field) = clampToInt(std::ceil(info->min));
      bounds.max.*(f->field) = clampToInt(std::floor(info->max));
    }
    else if (const auto* f = asField<double>(d))
    {
      bounds.min.*(f->field) = info->min;
      bounds.max.*(f->field) = info->max;
    }
    else if (const auto* f = asField<bool>(d))
    {
      bounds.min.*(f->field) = false;
      bounds.max.*(f->field) = true;
    }
  }
  return bounds;
}

std::string describeChanges(const amcr::Params& before, const amcr::Params& after)
{
  std::string out;
  const auto note = [&out](const std::string& change) { out += (out.empty() ? "" : ", ") + change; };
  for (const amcr::ParameterInfo& info : amcr::parameterTable())
  {
    const double was = amcr::getParameter(before, info.name), is = amcr::getParameter(after, info.name);
    if (was != is)
      note(info.name + " " + formatValue(info.name, was) + " -> " + formatValue(info.name, is));
  }
  for (const amcr::WordParameterInfo& info : amcr::wordParameterTable())
  {
    const std::string was = amcr::getWordParameter(before, info.name), is = amcr::getWordParameter(after, info.name);
    if (was != is)  // a choice as its word, a text quoted
      note(info.name + " " + (info.words.empty() ? "'" + is + "'" : is));
  }
  return out;
}
}  // namespace amcr_ros
