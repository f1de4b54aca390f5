// amcr::Params <-> the dynamic_reconfigure config of cfg/AMCR.cfg (same names).
// No list of names here: both directions walk the generated parameter
// descriptions of cfg/AMCR.cfg and read or write each one through amcr's
// getParameter/setParameter by its name. test/ros/test_reconfigure_table.cpp
// names every parameter that the .cfg lacks or the core does not know.
//
// Ranges: the .cfg's generated bounds are open, because dynamic_reconfigure's
// Server clamps to them before any callback sees a value (-5 V-particles would
// become 1). fromConfig() refuses a value out of the core's range instead, and
// reconfigureBounds() gives the core's ranges for the published descriptions.
#pragma once

#include <string>

#include "amcr/base/params.h"
#include <amcr/AMCRConfig.h>

namespace amcr_ros
{
/// Level bit of cfg/AMCR.cfg: the prototype lookup tables must be rebuilt.
constexpr std::uint32_t kReconfigureTables = 1;

/// A seed above int_t's range (~seed given as a string) is shown as 2147483647.
amcr::AMCRConfig toConfig(const amcr::Params& params);

/// `base` with every value of `config`; throws amcr::ParameterError (not validated here),
/// also for a parameter of the .cfg that amcr::Params does not know. The seed
/// is kept whole while `config` shows it as toConfig(base) does.
amcr::Params fromConfig(const amcr::AMCRConfig& config, amcr::Params base);

/// The smallest and largest value of every numeric parameter: amcr::parameterTable()'s range, within int
/// for an int_t of the .cfg; strings keep the defaults. For Server::setConfigMin/setConfigMax (what
/// clients show; the Server's clamp uses the .cfg's open bounds).
struct ConfigBounds
{
  amcr::AMCRConfig min, max;
};
ConfigBounds reconfigureBounds();

/// The parameters that differ, readable ("num_v_particles 60 -> 40, sigma_w 5 -> 7.5,
/// prototype_priors 'bat: 2'"; whole numbers as integers); empty when none.
std::string describeChanges(const amcr::Params& before, const amcr::Params& after);
}  // namespace amcr_ros
