// amcr::Params from a node's private namespace: first the YAML file named by
// ~config (amcr::loadParams, config/amcr.yaml), then every parameter of
// amcr::parameterTable() set individually under the private namespace. A ROS
// integer parameter is 32-bit (XML-RPC): ~seed may also be a string of
// digits, for any 64-bit seed.
#pragma once

#include <string>
#include <vector>

#include <ros/node_handle.h>

#include "amcr/base/params.h"

namespace amcr_ros
{
/// Reads and validates. Throws amcr::ParameterError (or amcr::Error) naming the
/// parameter or file at fault; `notes` receives one line per parameter that was set.
amcr::Params loadParams(const ros::NodeHandle& private_nh, std::vector<std::string>* notes = nullptr);
}  // namespace amcr_ros
