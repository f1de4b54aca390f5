// cfg/AMCR.cfg against amcr::parameterTable(): the same names (a missing or
// extra one is named), ranges (in the descriptions and the published bounds;
// the generated bounds are open so that nothing is clamped) and defaults, and
// Params survive the round trip through the generated config (src/ros/reconfigure.cpp walks the .cfg's own
// descriptions: it holds no list of names).
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "amcr/base/errors.h"
#include "amcr/base/params.h"
#include "reconfigure.h"

namespace
{
TEST(ReconfigureTable, SameParametersRangesAndDefaultsAsTheCore)
{
  const auto& descriptions = amcr::AMCRConfig::__getParamDescriptions__();
  const amcr::AMCRConfig defaults = amcr::AMCRConfig::__getDefault__();
  std::set<std::string> cfg_names;
  for (const auto& d : descriptions)
    cfg_names.insert(d->name);

  // Names first: a parameter that the .cfg lacks or the core does not know is named before anything else.
  // table_cache_dir is read when the memory is loaded: it is not reconfigured.
  std::set<std::string> core_names;
  for (const amcr::WordParameterInfo& info : amcr::wordParameterTable())
    if (info.name != "table_cache_dir")
      core_names.insert(info.name);
  for (const amcr::ParameterInfo& info : amcr::parameterTable())
    core_names.insert(info.name);
  for (const std::string& name : core_names)
    EXPECT_TRUE(cfg_names.count(name)) << name << " is missing from cfg/AMCR.cfg";
  for (const std::string& name : cfg_names)
    EXPECT_TRUE(core_names.count(name)) << name << " is in cfg/AMCR.cfg but not in amcr::parameterTable()";

  const amcr::Params core_defaults;
  const amcr::Params cfg_defaults = amcr_ros::fromConfig(defaults, amcr::Params());
  for (const amcr::ParameterInfo& info : amcr::parameterTable())
    EXPECT_DOUBLE_EQ(amcr::getParameter(cfg_defaults, info.name), amcr::getParameter(core_defaults, info.name))
        << info.name;
}

/// The core's range of a parameter as an int_t of the .cfg can hold it.
std::pair<double, double> expectedRange(const amcr::ParameterInfo& info, const std::string& cfg_type)
{
  if (cfg_type != "int")
    return {info.min, info.max};
  return {std::max(std::ceil(info.min), double(std::numeric_limits<int>::min())),
          std::min(std::floor(info.max), double(std::numeric_limits<int>::max()))};
}

// The range in each description of the .cfg (what `dynparam` and the .cfg's reader see) and the bounds the
// nodelet publishes are the core's.
TEST(ReconfigureTable, DescriptionsAndPublishedBoundsGiveTheCoreRanges)
{
  const amcr_ros::ConfigBounds bounds = amcr_ros::reconfigureBounds();
  const amcr::Params low = amcr_ros::fromConfig(bounds.min, amcr::Params());
  const amcr::Params high = amcr_ros::fromConfig(bounds.max, amcr::Params());
  const std::regex range(R"(range \[([-+0-9.e]+), ([-+0-9.e]+)\]$)");
  for (const auto& d : amcr::AMCRConfig::__getParamDescriptions__())
  {
    const amcr::ParameterInfo* info = nullptr;
    for (const amcr::ParameterInfo& i : amcr::parameterTable())
      if (i.name == d->name)
        info = &i;
    if (!info || d->type == "bool")
      continue;  // a string, a flag, or a name the test above reports
    const auto expected = expectedRange(*info, d->type);
    std::smatch m;
    ASSERT_TRUE(std::regex_search(d->description, m, range))
        << d->name << ": no 'range [min, max]' at the end of its description in cfg/AMCR.cfg: " << d->description;
    EXPECT_DOUBLE_EQ(std::stod(m[1]), expected.first) << d->name << " (description in cfg/AMCR.cfg)";
    EXPECT_DOUBLE_EQ(std::stod(m[2]), expected.second) << d->name << " (description in cfg/AMCR.cfg)";
    EXPECT_DOUBLE_EQ(amcr::getParameter(low, d->name), expected.first) << d->name << " (published minimum)";
    EXPECT_DOUBLE_EQ(amcr::getParameter(high, d->name), expected.second) << d->name << " (published maximum)";
  }
}

using Description = amcr::AMCRConfig::AbstractParamDescriptionConstPtr;

void setNumber(amcr::AMCRConfig& config, const Description& d, double value)
{
  if (const auto* f = dynamic_cast<const amcr::AMCRConfig::ParamDescription<int>*>(d.get()))
    config.*(f->field) = static_cast<int>(value);
  else if (const auto* f = dynamic_cast<const amcr::AMCRConfig::ParamDescription<double>*>(d.get()))
    config.*(f->field) = value;
}

double number(const amcr::AMCRConfig& config, const Description& d)
{
  if (const auto* f = dynamic_cast<const amcr::AMCRConfig::ParamDescription<int>*>(d.get()))
    return config.*(f->field);
  if (const auto* f = dynamic_cast<const amcr::AMCRConfig::ParamDescription<double>*>(d.get()))
    return config.*(f->field);
  return 0.0;
}

// dynamic_reconfigure's Server clamps to the .cfg's generated bounds before the nodelet sees a value: they
// must be open, so that a value out of the core's range reaches fromConfig(), which refuses it naming it.
TEST(ReconfigureTable, TheServerNeverClampsAndOutOfRangeValuesAreRefused)
{
  for (const auto& d : amcr::AMCRConfig::__getParamDescriptions__())
  {
    const amcr::ParameterInfo* info = nullptr;
    for (const amcr::ParameterInfo& i : amcr::parameterTable())
      if (i.name == d->name)
        info = &i;
    if (!info || (d->type != "int" && d->type != "double"))
      continue;
    const auto expected = expectedRange(*info, d->type);
    for (const double outside : {expected.first - 1.0, expected.second + 1.0})
    {
      if (d->type == "int" && (outside < std::numeric_limits<int>::min() || outside > std::numeric_limits<int>::max()))
        continue;
      amcr::AMCRConfig config = amcr::AMCRConfig::__getDefault__();
      setNumber(config, d, outside);
      amcr::AMCRConfig clamped = config;
      clamped.__clamp__();
      EXPECT_EQ(number(clamped, d), outside) << d->name << " = " << outside << " is clamped by the Server";
      try
      {
        amcr_ros::fromConfig(clamped, amcr::Params());
        ADD_FAILURE() << d->name << " = " << outside << " accepted";
      }
      catch (const amcr::ParameterError& e)
      {
        const std::string what = e.what();
        EXPECT_NE(what.find(d->name), std::string::npos) << what;
        EXPECT_NE(what.find("range"), std::string::npos) << what;
      }
    }
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
  p.ray_correspondence = amcr::RayCorrespondence::kPaper;
  p.seed = 42;
  p.optical_flow = false;
  p.fit_homography = false;
  p.frame_budget_ms = 12.5;
  p.prototype_priors = {{"bat", 2.0}, {"apple", 0.0}};
  const amcr::Params back = amcr_ros::fromConfig(amcr_ros::toConfig(p), amcr::Params());
  for (const amcr::ParameterInfo& info : amcr::parameterTable())
    EXPECT_DOUBLE_EQ(amcr::getParameter(back, info.name), amcr::getParameter(p, info.name)) << info.name;
  EXPECT_EQ(back.likelihood_form, p.likelihood_form);
  EXPECT_EQ(back.deviation_space, p.deviation_space);
  EXPECT_EQ(back.ray_correspondence, p.ray_correspondence);
  EXPECT_EQ(back.prototype_priors, p.prototype_priors);
}

// A parameter of the TABLES level of the .cfg (a change rebuilds the lookup tables) is one the core's
// table marks as building them, and tablesDiffer sees a change of each of them alone, and of no other.
TEST(ReconfigureTable, TheTablesLevelIsTheParametersThatBuildTheTables)
{
  std::set<std::string> cfg_tables, core_tables;
  for (const auto& d : amcr::AMCRConfig::__getParamDescriptions__())
    if (d->level & amcr_ros::kReconfigureTables)
      cfg_tables.insert(d->name);
  for (const amcr::ParameterInfo& info : amcr::parameterTable())
    if (info.builds_tables)
      core_tables.insert(info.name);
  EXPECT_EQ(cfg_tables, core_tables);

  for (const amcr::ParameterInfo& info : amcr::parameterTable())
  {
    amcr::Params changed;
    // Another value within the range: 1 up or down (an integer's range spans at least that), else
    // halfway to the upper bound (a share).
    const double value = amcr::getParameter(changed, info.name);
    const double other = value + 1.0 <= info.max   ? value + 1.0
                         : value - 1.0 >= info.min ? value - 1.0
                                                   : value + 0.5 * (info.max - value);
    amcr::setParameter(changed, info.name, other);
    ASSERT_NE(amcr::getParameter(changed, info.name), value) << info.name;
    EXPECT_EQ(amcr::tablesDiffer(amcr::Params(), changed), info.builds_tables) << info.name;
  }
}
}  // namespace

namespace
{
// A choice's words in the .cfg (its enum's values) are those the core's table of word parameters takes.
TEST(ReconfigureTable, ChoicesOfferTheCoresWords)
{
  const std::regex value(R"('value': '([^']*)')");
  int choices = 0;
  for (const amcr::WordParameterInfo& info : amcr::wordParameterTable())
    for (const auto& d : amcr::AMCRConfig::__getParamDescriptions__())
      if (d->name == info.name && !info.words.empty())
      {
        std::set<std::string> offered;
        for (std::sregex_iterator it(d->edit_method.begin(), d->edit_method.end(), value), end; it != end; ++it)
          offered.insert((*it)[1]);
        EXPECT_EQ(offered, std::set<std::string>(info.words.begin(), info.words.end())) << info.name;
        ++choices;
      }
  EXPECT_EQ(choices, 3) << "likelihood_form, deviation_space and ray_correspondence";
}

// The log line of a reconfiguration: whole numbers as integers, and a change of prototype_priors alone is a
// change (it was not compared, so dynamic_reconfigure showed priors that were not in effect).
TEST(ReconfigureTable, ChangesNameIntegersAsIntegersAndThePriors)
{
  const amcr::Params before;
  amcr::Params after;
  after.num_v_particles = 40;
  after.sigma_w = 7.5;
  after.seed = 12;
  after.prototype_priors = {{"bat", 2.0}};
  const std::string what = amcr_ros::describeChanges(before, after);
  EXPECT_NE(what.find("num_v_particles 60 -> 40"), std::string::npos) << what;
  EXPECT_NE(what.find("seed 0 -> 12"), std::string::npos) << what;
  EXPECT_NE(what.find("sigma_w 5 -> 7.5"), std::string::npos) << what;
  EXPECT_NE(what.find("prototype_priors '" + amcr::formatPriors(after.prototype_priors) + "'"), std::string::npos)
      << what;
  EXPECT_EQ(what.find(".000000"), std::string::npos) << what;

  amcr::Params priors_only;
  priors_only.prototype_priors = {{"bat", 0.0}};
  EXPECT_FALSE(amcr_ros::describeChanges(before, priors_only).empty()) << "a change of prototype_priors alone";
  EXPECT_TRUE(amcr_ros::describeChanges(before, amcr::Params()).empty());
}
}  // namespace
