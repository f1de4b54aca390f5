#include "reconfigure.h"

#include <memory>

#include "amcr/errors.h"

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

/// The string parameters of amcr::Params (the numeric ones are in amcr::parameterTable()).
std::string textParameter(const amcr::Params& params, const std::string& name)
{
  if (name == "likelihood_form")
    return amcr::toString(params.likelihood_form);
  if (name == "deviation_space")
    return amcr::toString(params.deviation_space);
  if (name == "prototype_priors")
    return amcr::formatPriors(params.prototype_priors);
  throw amcr::ParameterError("cfg/AMCR.cfg has the string parameter '" + name + "', which amcr::Params does not know");
}
}  // namespace

amcr::AMCRConfig toConfig(const amcr::Params& params)
{
  amcr::AMCRConfig config = amcr::AMCRConfig::__getDefault__();
  for (const auto& d : configFields())
  {
    if (const auto* f = asField<int>(d))
      config.*(f->field) = static_cast<int>(amcr::getParameter(params, d->name));
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
      amcr::setParameter(params, d->name, static_cast<double>(config.*(f->field)));
    else if (const auto* f = asField<double>(d))
      amcr::setParameter(params, d->name, config.*(f->field));
    else if (const auto* f = asField<bool>(d))
      amcr::setParameter(params, d->name, static_cast<double>(config.*(f->field)));
    else if (const auto* f = asField<std::string>(d))
      amcr::setParameter(params, d->name, config.*(f->field));
  }
  return params;
}

bool tablesDiffer(const amcr::Params& a, const amcr::Params& b)
{
  return a.prototype_size != b.prototype_size || a.edge_threshold != b.edge_threshold ||
         a.blur_sigma != b.blur_sigma;
}

std::string describeChanges(const amcr::Params& before, const amcr::Params& after)
{
  std::string out;
  for (const amcr::ParameterInfo& info : amcr::parameterTable())
  {
    const double was = amcr::getParameter(before, info.name), is = amcr::getParameter(after, info.name);
    if (was != is)
      out += (out.empty() ? "" : ", ") + info.name + " " + std::to_string(was) + " -> " + std::to_string(is);
  }
  if (after.likelihood_form != before.likelihood_form)
    out += (out.empty() ? "" : ", ") + std::string("likelihood_form ") + amcr::toString(after.likelihood_form);
  if (after.deviation_space != before.deviation_space)
    out += (out.empty() ? "" : ", ") + std::string("deviation_space ") + amcr::toString(after.deviation_space);
  return out;
}
}  // namespace amcr_ros
