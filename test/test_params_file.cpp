// The parameter file (issue 12, findings 2 and 7): whole numbers never wrap
// at 32 bits, syntax errors give the file, the line and the reason, a word
// parameter given a number says it takes a word, a file without the OpenCV
// header is read, and a file that cannot be read says why.
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "amcr/errors.h"
#include "amcr/params.h"
#include "scene_drawing.h"

namespace
{
class ParamsFile : public ::testing::Test
{
protected:
  /// Writes `text` as it is (no header added).
  std::string write(const std::string& text)
  {
    const std::string path = dir_.file("params_" + std::to_string(counter_++) + ".yaml");
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
  /// The ParameterError of loading `path` ("" when it loads).
  static std::string loadError(const std::string& path)
  {
    try
    {
      amcr::loadParams(path);
    }
    catch (const amcr::ParameterError& e)
    {
      return e.what();
    }
    return "";
  }
  amcr_test::TempDir dir_;
  int counter_ = 0;
};

TEST_F(ParamsFile, WholeNumbersBeyond32BitsAreNotWrapped)
{
  const std::string count = write("%YAML:1.0\n---\nnum_v_particles: 4294967326\n");  // 2^32 + 30
  const std::string error = loadError(count);
  EXPECT_NE(error.find("'num_v_particles' = 4294967326"), std::string::npos) << error;
  EXPECT_NE(error.find(count + ":3"), std::string::npos) << "the file and line: " << error;

  EXPECT_EQ(amcr::loadParams(write("%YAML:1.0\n---\nseed: 4294967297\n")).seed, 4294967297ull);
  EXPECT_EQ(amcr::loadParams(write("%YAML:1.0\n---\nseed: 3000000000\n")).seed, 3000000000ull);
  EXPECT_EQ(amcr::loadParams(write("%YAML:1.0\n---\nseed: 9007199254740992  # 2^53\n")).seed, 9007199254740992ull);
  const std::string beyond = loadError(write("%YAML:1.0\n---\nseed: 9007199254740993\n"));
  EXPECT_NE(beyond.find("'seed' = 9007199254740993"), std::string::npos) << beyond;
  const std::string huge = loadError(write("%YAML:1.0\n---\nseed: 99999999999999999999999\n"));
  EXPECT_NE(huge.find("99999999999999999999999"), std::string::npos) << huge;
  const std::string negative = loadError(write("%YAML:1.0\n---\nmin_support: -4294967295\n"));  // wraps to 1
  EXPECT_NE(negative.find("-4294967295"), std::string::npos) << negative;
  // In a flow map and in the priors as well.
  EXPECT_EQ(amcr::loadParams(write("%YAML:1.0\n---\n{seed: 5000000000, sigma_w: 5}\n")).seed, 5000000000ull);
  EXPECT_DOUBLE_EQ(amcr::loadParams(write("%YAML:1.0\n---\nprototype_priors: {bat: 4294967298}\n"))
                       .prototype_priors.at("bat"),
                   4294967298.0);
}

TEST_F(ParamsFile, SyntaxErrorsGiveTheFileTheLineAndTheReason)
{
  const std::string path = write("%YAML:1.0\n---\nsigma_w: 6\nnum_v_particles: [1, 2\nseed: 3\n");
  const std::string error = loadError(path);
  EXPECT_NE(error.find(path), std::string::npos) << error;
  EXPECT_NE(error.find("line "), std::string::npos) << error;
  for (const char* bare : {"parseValue", "parseKey", "skipSpaces"})
    EXPECT_EQ(error.find(bare), std::string::npos) << "an OpenCV function name instead of a reason: " << error;
  const std::string unclosed = loadError(write("%YAML:1.0\n---\nsigma_w: 6\np_outlier: {\n"));
  EXPECT_NE(unclosed.find("line 4: end of map flow not found"), std::string::npos) << unclosed;
}

TEST_F(ParamsFile, AWordParameterGivenANumberSaysItTakesAWord)
{
  const std::string error = loadError(write("%YAML:1.0\n---\nlikelihood_form: 5\n"));
  EXPECT_NE(error.find("'likelihood_form' takes a word (paper or mixture)"), std::string::npos) << error;
  EXPECT_EQ(error.find("unknown"), std::string::npos) << error;
  const std::string space = loadError(write("%YAML:1.0\n---\ndeviation_space: 1\n"));
  EXPECT_NE(space.find("image or prototype"), std::string::npos) << space;
}

TEST_F(ParamsFile, AFileWithoutTheOpenCvHeaderIsRead)
{
  const amcr::Params p = amcr::loadParams(write("# no header\nnum_v_particles: 45\nsigma_w: 7.5\n"));
  EXPECT_EQ(p.num_v_particles, 45);
  EXPECT_DOUBLE_EQ(p.sigma_w, 7.5);
  // Its line numbers are those of the file.
  const std::string error = loadError(write("sigma_w: 6\np_outlier: {\n"));
  EXPECT_NE(error.find("line 2:"), std::string::npos) << error;
  EXPECT_EQ(amcr::loadParams(write("")).num_v_particles, amcr::Params().num_v_particles);  // empty: the defaults
}

TEST_F(ParamsFile, AFileThatCannotBeReadSaysWhy)
{
  EXPECT_NE(loadError(dir_.file("none.yaml")).find("No such file or directory"), std::string::npos)
      << loadError(dir_.file("none.yaml"));
  EXPECT_NE(loadError(dir_.path()).find("it is a directory"), std::string::npos) << loadError(dir_.path());
  const std::string binary = loadError(write(std::string("%YAML:1.0\nsigma_w: 5\n\0\1", 23)));
  EXPECT_NE(binary.find("not a text file"), std::string::npos) << binary;
  const std::string locked = write("%YAML:1.0\nsigma_w: 5\n");
  ASSERT_EQ(chmod(locked.c_str(), 0), 0);
  if (access(locked.c_str(), R_OK) == 0)
    GTEST_SKIP() << "running as a user who reads any file (root): no permission error to test";
  EXPECT_NE(loadError(locked).find("Permission denied"), std::string::npos) << loadError(locked);
}

TEST_F(ParamsFile, AKeyGivenTwiceIsRefused)
{
  const std::string error = loadError(write("%YAML:1.0\n---\nsigma_w: 5\nsigma_w: 6\n"));
  EXPECT_NE(error.find("'sigma_w' is given twice"), std::string::npos) << error;
}
}  // namespace
