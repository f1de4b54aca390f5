// A dynamic_reconfigure request, as `dynparam set` sends it, for the ROS tests.
#pragma once

#include <string>

#include <dynamic_reconfigure/Reconfigure.h>

namespace amcr_test
{
/// A dynamic_reconfigure request that sets one integer parameter.
inline dynamic_reconfigure::Reconfigure intParameterRequest(const std::string& name, int value)
{
  dynamic_reconfigure::Reconfigure request;
  dynamic_reconfigure::IntParameter parameter;
  parameter.name = name;
  parameter.value = value;
  request.request.config.ints.push_back(parameter);
  return request;
}
}  // namespace amcr_test
