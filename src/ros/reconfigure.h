// amcr::Params <-> the dynamic_reconfigure config of cfg/AMCR.cfg (same names).
#pragma once

#include "amcr/params.h"
#include <amcr/AMCRConfig.h>

namespace amcr_ros
{
/// Level bit of cfg/AMCR.cfg: the prototype lookup tables must be rebuilt.
constexpr std::uint32_t kReconfigureTables = 1;

amcr::AMCRConfig toConfig(const amcr::Params& params);

/// `base` with every value of `config`; throws amcr::ParameterError (not validated here).
amcr::Params fromConfig(const amcr::AMCRConfig& config, amcr::Params base);

/// True when a memory built with `a` differs from one built with `b`.
bool tablesDiffer(const amcr::Params& a, const amcr::Params& b);
}  // namespace amcr_ros
