// amcr::Params <-> the dynamic_reconfigure config of cfg/AMCR.cfg (same names).
// No list of names here: both directions walk the generated parameter
// descriptions of cfg/AMCR.cfg and read or write each one through amcr's
// getParameter/setParameter by its name. test/ros/test_reconfigure_table.cpp
// names every parameter that the .cfg lacks or the core does not know.
#pragma once

#include <string>

#include "amcr/params.h"
#include <amcr/AMCRConfig.h>

namespace amcr_ros
{
/// Level bit of cfg/AMCR.cfg: the prototype lookup tables must be rebuilt.
constexpr std::uint32_t kReconfigureTables = 1;

amcr::AMCRConfig toConfig(const amcr::Params& params);

/// `base` with every value of `config`; throws amcr::ParameterError (not validated here),
/// also for a parameter of the .cfg that amcr::Params does not know.
amcr::Params fromConfig(const amcr::AMCRConfig& config, amcr::Params base);

/// True when a memory built with `a` differs from one built with `b`.
bool tablesDiffer(const amcr::Params& a, const amcr::Params& b);

/// The numeric parameters and forms that differ, readable ("sigma_w 5.000000 -> 7.000000, ...");
/// empty when none.
std::string describeChanges(const amcr::Params& before, const amcr::Params& after);
}  // namespace amcr_ros
