// config/amcr.yaml is the documented set of parameters: it must hold every
// parameter of amcr::Params, each at its default, and load cleanly. It is
// plain YAML (no OpenCV header), so that rosparam reads it too
// (test/test_package_files.py reads it as rosparam does).
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "amcr/base/params.h"
#include "amcr/io/params_file.h"

namespace
{
const std::string kConfigPath = std::string(AMCR_SOURCE_DIR) + "/config/amcr.yaml";

TEST(ConfigFile, HoldsEveryParameterAtItsDefault)
{
  std::ifstream in(kConfigPath);
  std::stringstream text;
  text << in.rdbuf();
  ASSERT_NE(text.str().rfind("%YAML", 0), 0u) << kConfigPath << " must not start with OpenCV's header (rosparam refuses it)";
  const YAML::Node file = YAML::Load(text.str());
  ASSERT_TRUE(file.IsMap()) << "cannot read " << kConfigPath;
  const amcr::Params defaults;
  for (const amcr::ParameterInfo& info : amcr::parameterTable())
  {
    ASSERT_TRUE(file[info.name].IsScalar()) << info.name << " is missing from " << kConfigPath;
    EXPECT_DOUBLE_EQ(file[info.name].as<double>(), amcr::getParameter(defaults, info.name))
        << info.name << " in " << kConfigPath << " differs from the default in params.h";
  }
  EXPECT_EQ(file["likelihood_form"].as<std::string>(), amcr::toString(defaults.likelihood_form));
  EXPECT_EQ(file["deviation_space"].as<std::string>(), amcr::toString(defaults.deviation_space));
  EXPECT_TRUE(file["prototype_priors"].IsMap()) << "prototype_priors is missing from " << kConfigPath;
  EXPECT_EQ(file["prototype_priors"].size(), defaults.prototype_priors.size());
}

TEST(ConfigFile, LoadsWithoutError)
{
  const amcr::Params loaded = amcr::loadParams(kConfigPath);
  const amcr::Params defaults;
  for (const amcr::ParameterInfo& info : amcr::parameterTable())
    EXPECT_DOUBLE_EQ(amcr::getParameter(loaded, info.name), amcr::getParameter(defaults, info.name)) << info.name;
}

// config/large_memory.yaml (for memories of a thousand prototypes and more) changes only the tables' stride.
TEST(ConfigFile, LargeMemoryFileSetsCompactTablesOnly)
{
  const std::string path = std::string(AMCR_SOURCE_DIR) + "/config/large_memory.yaml";
  const amcr::Params loaded = amcr::loadParams(path);
  const amcr::Params defaults;
  EXPECT_EQ(loaded.table_stride, 2);
  for (const amcr::ParameterInfo& info : amcr::parameterTable())
  {
    if (info.name != "table_stride")
    {
      EXPECT_DOUBLE_EQ(amcr::getParameter(loaded, info.name), amcr::getParameter(defaults, info.name)) << info.name;
    }
  }
}
}  // namespace
