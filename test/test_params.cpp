// Parameters: defaults are valid; every out-of-range value is refused with a
// ParameterError whose message names the parameter; YAML loading reads
// values and refuses unknown keys and out-of-range values.
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "amcr/base/errors.h"
#include "amcr/base/params.h"
#include "amcr/io/params_file.h"
#include "scene_drawing.h"

namespace
{
// Runs `action`, expects a ParameterError whose what() contains `name`.
void expectParameterError(const std::function<void()>& action, const std::string& name, const std::string& context)
{
  try
  {
    action();
    ADD_FAILURE() << context << ": no ParameterError";
  }
  catch (const amcr::ParameterError& e)
  {
    EXPECT_NE(std::string(e.what()).find(name), std::string::npos)
        << context << ": the message does not name `" << name << "`: " << e.what();
  }
  catch (const std::exception& e)
  {
    ADD_FAILURE() << context << ": wrong exception type: " << e.what();
  }
}

struct BadValue
{
  std::string name;
  std::function<void(amcr::Params&)> set;
  std::string what;
};

TEST(Params, DefaultsAreValid)
{
  EXPECT_NO_THROW(amcr::Params{}.validate());
  // The paper's settings that the defaults keep. (num_v_particles is 60, not
  // the paper's 30, and V-particles are resampled every 3 iterations, not 10:
  // both found the shapes of the end-to-end and tracking tests sooner, see docs/how-it-works.md.)
  const amcr::Params p;
  EXPECT_EQ(p.m_particles_per_prototype, 60);
  EXPECT_DOUBLE_EQ(p.p_outlier, 0.1);
  EXPECT_DOUBLE_EQ(p.p_invalid, 0.1);
  EXPECT_TRUE(p.optical_flow);
  EXPECT_TRUE(p.fit_homography);
  EXPECT_TRUE(p.prototype_priors.empty());
}

TEST(Params, OutOfRangeValuesNameTheParameter)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<BadValue> cases = {
      {"num_v_particles", [](amcr::Params& p) { p.num_v_particles = -1; }, "negative count"},
      {"num_v_particles", [](amcr::Params& p) { p.num_v_particles = 0; }, "zero count"},
      {"m_particles_per_prototype", [](amcr::Params& p) { p.m_particles_per_prototype = -5; }, "negative count"},
      {"min_support", [](amcr::Params& p) { p.min_support = -2; }, "negative count"},
      {"v_resample_interval", [](amcr::Params& p) { p.v_resample_interval = -1; }, "negative count"},
      {"p_outlier", [](amcr::Params& p) { p.p_outlier = 1.5; }, "probability > 1"},
      {"p_outlier", [](amcr::Params& p) { p.p_outlier = -0.1; }, "probability < 0"},
      {"p_invalid", [](amcr::Params& p) { p.p_invalid = 2.0; }, "probability > 1"},
      {"p_invalid", [](amcr::Params& p) { p.p_invalid = -1e-3; }, "probability < 0"},
      {"v_reseed_fraction", [](amcr::Params& p) { p.v_reseed_fraction = 1.01; }, "share > 1"},
      {"m_reseed_fraction", [](amcr::Params& p) { p.m_reseed_fraction = -0.2; }, "share < 0"},
      {"injection_fraction", [](amcr::Params& p) { p.injection_fraction = 3.0; }, "share > 1"},
      {"decision_threshold", [](amcr::Params& p) { p.decision_threshold = 1.2; }, "score > 1"},
      {"working_resolution", [](amcr::Params& p) { p.working_resolution = -1; }, "size < 0"},
      {"working_resolution", [](amcr::Params& p) { p.working_resolution = 4001; }, "size > 4000"},
      {"min_object_size", [](amcr::Params& p) { p.min_object_size = -1.0; }, "size < 0"},
      {"sigma_w", [](amcr::Params& p) { p.sigma_w = 0.0; }, "sigma = 0"},
      {"sigma_w", [](amcr::Params& p) { p.sigma_w = -3.0; }, "sigma < 0"},
      {"sigma_w", [nan](amcr::Params& p) { p.sigma_w = nan; }, "sigma NaN"},
      {"blur_sigma", [](amcr::Params& p) { p.blur_sigma = -1.0; }, "sigma < 0"},
      {"motion_noise_translation", [](amcr::Params& p) { p.motion_noise_translation = -0.5; }, "sigma < 0"},
      {"max_ray_length", [](amcr::Params& p) { p.max_ray_length = 0.0; }, "length 0"},
  };
  for (const BadValue& c : cases)
  {
    amcr::Params p;
    c.set(p);
    expectParameterError([&p]() { p.validate(); }, c.name, c.name + " (" + c.what + ")");
  }
}

// A sweep over the parameter table (style point 7): every parameter, just
// above its maximum and just below its minimum, is refused by setParameter
// or by validate(), with its name in the message; its default is in range.
TEST(Params, TableRangesAreEnforced)
{
  const auto& table = amcr::parameterTable();
  ASSERT_FALSE(table.empty());
  const amcr::Params defaults;
  for (const amcr::ParameterInfo& info : table)
  {
    SCOPED_TRACE(info.name);
    EXPECT_FALSE(info.unit.empty() && info.description.empty()) << "undocumented parameter";
    const double value = amcr::getParameter(defaults, info.name);
    EXPECT_GE(value, info.min);
    EXPECT_LE(value, info.max);
    if (info.name == "seed")
      continue;  // any 64-bit value is a seed
    for (double bad : {info.max + std::max(1.0, std::abs(info.max)), info.min - std::max(1.0, std::abs(info.min))})
    {
      if (std::abs(bad) > 1e15)
        continue;
      expectParameterError(
          [&]() {
            amcr::Params p;
            amcr::setParameter(p, info.name, bad);
            p.validate();
          },
          info.name, info.name + " = " + std::to_string(bad));
    }
  }
}

TEST(Params, SetParameterRefusesUnknownNames)
{
  amcr::Params p;
  expectParameterError([&p]() { amcr::setParameter(p, "no_such_parameter", 1.0); }, "no_such_parameter",
                       "unknown numeric name");
  expectParameterError([&p]() { amcr::setParameter(p, "no_such_form", std::string("paper")); }, "no_such_form",
                       "unknown string name");
}

class ParamsYaml : public ::testing::Test
{
protected:
  std::string write(const std::string& body)
  {
    const std::string path = dir_.file("params_" + std::to_string(counter_++) + ".yaml");
    std::ofstream out(path);
    out << "%YAML:1.0\n---\n" << body;
    return path;
  }
  amcr_test::TempDir dir_;
  int counter_ = 0;
};

TEST_F(ParamsYaml, ReadsValuesOverTheGivenDefaults)
{
  const std::string path = write("num_v_particles: 45\n"
                                 "sigma_w: 7.5\n"
                                 "edge_threshold: 30\n"
                                 "v_resample_interval: 4\n"
                                 "likelihood_form: \"" +
                                 amcr::toString(amcr::LikelihoodForm::kMixture) +
                                 "\"\n"
                                 "deviation_space: \"" +
                                 amcr::toString(amcr::DeviationSpace::kPrototype) + "\"\n");
  amcr::Params base;
  base.m_particles_per_prototype = 77;  // not in the file: must be kept
  const amcr::Params p = amcr::loadParams(path, base);
  EXPECT_EQ(p.num_v_particles, 45);
  EXPECT_DOUBLE_EQ(p.sigma_w, 7.5);
  EXPECT_DOUBLE_EQ(p.edge_threshold, 30.0);
  EXPECT_EQ(p.v_resample_interval, 4);
  EXPECT_EQ(p.likelihood_form, amcr::LikelihoodForm::kMixture);
  EXPECT_EQ(p.deviation_space, amcr::DeviationSpace::kPrototype);
  EXPECT_EQ(p.m_particles_per_prototype, 77);
  EXPECT_DOUBLE_EQ(p.p_invalid, base.p_invalid);
}

TEST_F(ParamsYaml, RefusesAnUnknownKeyNamingIt)
{
  const std::string path = write("sigma_w: 6\nsigma_ww: 5\n");
  expectParameterError([&]() { amcr::loadParams(path); }, "sigma_ww", "unknown key");
}

TEST_F(ParamsYaml, RefusesAnOutOfRangeValueNamingTheKey)
{
  expectParameterError([&]() { amcr::loadParams(write("p_outlier: 1.5\n")); }, "p_outlier", "p_outlier: 1.5");
  expectParameterError([&]() { amcr::loadParams(write("num_v_particles: -4\n")); }, "num_v_particles",
                       "num_v_particles: -4");
  expectParameterError([&]() { amcr::loadParams(write("sigma_w: 0\n")); }, "sigma_w", "sigma_w: 0");
}

TEST_F(ParamsYaml, RefusesAnUnknownFormNamingTheKey)
{
  expectParameterError([&]() { amcr::loadParams(write("likelihood_form: \"gaussian_only\"\n")); }, "likelihood_form",
                       "likelihood_form: gaussian_only");
}

TEST_F(ParamsYaml, ReadsPrototypePriorsAsAMap)
{
  const amcr::Params p = amcr::loadParams(write("prototype_priors: { bat: 2.5, apple: 0 }\n"));
  ASSERT_EQ(p.prototype_priors.size(), 2u);
  EXPECT_DOUBLE_EQ(p.prototype_priors.at("bat"), 2.5);
  EXPECT_DOUBLE_EQ(p.prototype_priors.at("apple"), 0.0);
  EXPECT_TRUE(amcr::loadParams(write("prototype_priors: {}\n")).prototype_priors.empty());
  expectParameterError([&]() { amcr::loadParams(write("prototype_priors: { bat: -1 }\n")); }, "bat",
                       "negative weight");
  expectParameterError([&]() { amcr::loadParams(write("prototype_priors: { bat: heavy }\n")); }, "bat",
                       "weight that is not a number");
}

TEST(Priors, ParseAndFormatRoundTrip)
{
  const auto priors = amcr::parsePriors(" bat: 2, apple:0.5 ,bird : 0 ");
  ASSERT_EQ(priors.size(), 3u);
  EXPECT_DOUBLE_EQ(priors.at("bat"), 2.0);
  EXPECT_DOUBLE_EQ(priors.at("apple"), 0.5);
  EXPECT_DOUBLE_EQ(priors.at("bird"), 0.0);
  EXPECT_EQ(amcr::parsePriors(amcr::formatPriors(priors)), priors);
  EXPECT_TRUE(amcr::parsePriors("").empty());
  amcr::Params p;
  amcr::setParameter(p, "prototype_priors", std::string("bat: 3"));
  EXPECT_DOUBLE_EQ(p.prototype_priors.at("bat"), 3.0);
  p.prototype_priors["apple"] = -1.0;  // set directly, as the ROS map parameter does
  expectParameterError([&]() { p.validate(); }, "apple", "validate() of a negative prior");
}

TEST(Priors, MalformedEntriesNameTheParameterAndTheEntry)
{
  for (const std::string bad : {"bat", "bat: ", ": 2", "bat: 2x", "bat: -0.5", "bat: nan"})
    expectParameterError([&]() { amcr::parsePriors(bad); }, "prototype_priors", "'" + bad + "'");
}

TEST_F(ParamsYaml, MissingFileIsAnError)
{
  EXPECT_THROW(amcr::loadParams(dir_.file("does_not_exist.yaml")), amcr::Error);
}
// A seed set directly (amcr_offline --seed, ~seed as a string) is any 64-bit
// value; only a seed read as a number is bound to 2^53, the largest read exactly.
TEST(Params, EverySixtyFourBitSeedSetDirectlyIsValid)
{
  amcr::Params p;
  p.seed = std::numeric_limits<std::uint64_t>::max();
  EXPECT_NO_THROW(p.validate());
}

// The parameters that are not numbers go through one table: a choice takes each of its words (the
// default's first) and reads it back, refuses another word naming its own, and a number is refused
// naming what the parameter takes; the texts read back as they were set.
TEST(Params, WordParametersGoThroughTheirTable)
{
  const amcr::Params defaults;
  ASSERT_EQ(amcr::wordParameterTable().size(), 5u);
  for (const amcr::WordParameterInfo& info : amcr::wordParameterTable())
  {
    amcr::Params p;
    for (const std::string& word : info.words)
    {
      amcr::setParameter(p, info.name, word);
      EXPECT_EQ(amcr::getWordParameter(p, info.name), word) << info.name;
    }
    if (!info.words.empty())
    {
      EXPECT_EQ(amcr::getWordParameter(defaults, info.name), info.words.front()) << info.name;
      expectParameterError([&]() { amcr::setParameter(p, info.name, std::string("no_such_word")); },
                           "'" + info.words.back() + "'", info.name + " = no_such_word");
    }
    expectParameterError([&]() { amcr::setParameter(p, info.name, 1.0); }, info.takes, info.name + " = 1");
  }
  amcr::Params p;
  amcr::setParameter(p, "table_cache_dir", std::string("~/tables"));
  amcr::setParameter(p, "prototype_priors", std::string("bat: 2.5, apple: 0"));
  EXPECT_EQ(amcr::getWordParameter(p, "table_cache_dir"), "~/tables");
  EXPECT_EQ(amcr::getWordParameter(p, "prototype_priors"), "apple: 0, bat: 2.5");
  EXPECT_FALSE(amcr::sameParameters(p, defaults));
  expectParameterError([&]() { amcr::getWordParameter(p, "sigma_w"); }, "sigma_w", "a number as a word");
}

// MemoryParams::validate, which a memory's load runs, checks its own group (its EdgeParams with it)
// and no other.
TEST(Params, MemoryParamsValidateTheirGroupAlone)
{
  amcr::Params p;
  p.num_v_particles = -1;  // another group's
  EXPECT_NO_THROW(static_cast<const amcr::MemoryParams&>(p).validate());
  amcr::MemoryParams m;
  m.prototype_size = 8;
  expectParameterError([&]() { m.validate(); }, "prototype_size", "prototype_size = 8");
  m = amcr::MemoryParams();
  m.blur_sigma = -1.0;
  expectParameterError([&]() { m.validate(); }, "blur_sigma", "blur_sigma = -1");
  m = amcr::MemoryParams();
  m.table_cache_dir = "relative/tables";
  expectParameterError([&]() { m.validate(); }, "table_cache_dir", "a relative table_cache_dir");
}
}  // namespace
