// cfg/AMCR.cfg against amcr::parameterTable(): the same names (a missing or
// extra one is named), ranges and defaults, and Params survive the round trip
// through the generated config (src/ros/reconfigure.cpp walks the .cfg's own
// descriptions: it holds no list of names).
#include <map>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "amcr/errors.h"
#include "amcr/params.h"
#include "reconfigure.h"

namespace
{
TEST(ReconfigureTable, SameParametersRangesAndDefaultsAsTheCore)
{
  const auto& descriptions = amcr::AMCRConfig::__getParamDescriptions__();
  const amcr::AMCRConfig defaults = amcr::AMCRConfig::__getDefault__();
  // Strings have no range: the bounds keep the defaults' strings.
  amcr::AMCRConfig min = amcr::AMCRConfig::__getMin__();
  amcr::AMCRConfig max = amcr::AMCRConfig::__getMax__();
  for (amcr::AMCRConfig* c : {&min, &max})
  {
    c->likelihood_form = defaults.likelihood_form;
    c->deviation_space = defaults.deviation_space;
    c->prototype_priors = defaults.prototype_priors;
  }
  std::set<std::string> cfg_names;
  for (const auto& d : descriptions)
    cfg_names.insert(d->name);

  // Names first: a parameter that the .cfg lacks or the core does not know is named before anything else.
  std::set<std::string> core_names = {"likelihood_form", "deviation_space", "prototype_priors"};
  for (const amcr::ParameterInfo& info : amcr::parameterTable())
    core_names.insert(info.name);
  for (const std::string& name : core_names)
    EXPECT_TRUE(cfg_names.count(name)) << name << " is missing from cfg/AMCR.cfg";
  for (const std::string& name : cfg_names)
    EXPECT_TRUE(core_names.count(name)) << name << " is in cfg/AMCR.cfg but not in amcr::parameterTable()";

  const amcr::Params core_defaults;
  const amcr::Params cfg_defaults = amcr_ros::fromConfig(defaults, amcr::Params());
  const amcr::Params cfg_min = amcr_ros::fromConfig(min, amcr::Params());
  const amcr::Params cfg_max = amcr_ros::fromConfig(max, amcr::Params());
  for (const amcr::ParameterInfo& info : amcr::parameterTable())
  {
    EXPECT_DOUBLE_EQ(amcr::getParameter(cfg_defaults, info.name), amcr::getParameter(core_defaults, info.name))
        << info.name;
    // Ranges: the cfg may be narrower where the core's bound is open or beyond int.
    EXPECT_GE(amcr::getParameter(cfg_min, info.name), info.min) << info.name;
    EXPECT_LE(amcr::getParameter(cfg_max, info.name), info.max) << info.name;
    EXPECT_NO_THROW(cfg_min.validate()) << info.name;
    // Each maximum is a value the core takes; all of them together are not (min_support above
    // num_v_particles, the M-particle bound: Params::validate()'s checks across parameters).
    amcr::Params at_max;
    EXPECT_NO_THROW(amcr::setParameter(at_max, info.name, amcr::getParameter(cfg_max, info.name))) << info.name;
  }
}

// A whole-number parameter of the core is an int_t (or bool_t) in the .cfg, any other a double_t.
TEST(ReconfigureTable, WholeNumbersAreIntegersInTheCfg)
{
  std::map<std::string, std::string> cfg_type;
  for (const auto& d : amcr::AMCRConfig::__getParamDescriptions__())
    cfg_type[d->name] = d->type;
  for (const amcr::ParameterInfo& info : amcr::parameterTable())
  {
    const auto it = cfg_type.find(info.name);
    const double half = info.min + 0.5;
    if (it == cfg_type.end() || half > info.max)
      continue;  // a missing name is named above
    bool whole = false;
    try
    {
      amcr::Params p;
      amcr::setParameter(p, info.name, half);
    }
    catch (const amcr::ParameterError&)
    {
      whole = true;
    }
    EXPECT_EQ(it->second != "double", whole) << info.name << " is a " << it->second << " in cfg/AMCR.cfg";
  }
}

TEST(ReconfigureTable, RoundTrip)
{
  amcr::Params p;
  p.num_v_particles = 17;
  p.sigma_w = 7.5;
  p.likelihood_form = amcr::LikelihoodForm::kMixture;
  p.deviation_space = amcr::DeviationSpace::kPrototype;
  p.seed = 42;
  p.optical_flow = false;
  p.frame_budget_ms = 12.5;
  p.prototype_priors = {{"bat", 2.0}, {"apple", 0.0}};
  const amcr::Params back = amcr_ros::fromConfig(amcr_ros::toConfig(p), amcr::Params());
  for (const amcr::ParameterInfo& info : amcr::parameterTable())
    EXPECT_DOUBLE_EQ(amcr::getParameter(back, info.name), amcr::getParameter(p, info.name)) << info.name;
  EXPECT_EQ(back.likelihood_form, p.likelihood_form);
  EXPECT_EQ(back.deviation_space, p.deviation_space);
  EXPECT_EQ(back.prototype_priors, p.prototype_priors);
  EXPECT_TRUE(amcr_ros::tablesDiffer(p, [&] {
    amcr::Params q = p;
    q.prototype_size = 64;
    return q;
  }()));
}
}  // namespace
