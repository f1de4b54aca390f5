// The parameter file, read with yaml-cpp: whole numbers never wrap at 32 bits
// (cv::FileStorage, which read it before, wrapped them), every error gives
// the file and the line, a
// word parameter given a number says it takes a word, a file with or without
// the OpenCV header is read, a file that cannot be read says why, and nesting
// deeper than a parameter file needs is refused before it is built.
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "amcr/base/errors.h"
#include "amcr/base/params.h"
#include "amcr/io/params_file.h"
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
  const std::string path = write("%YAML:1.0\n---\nsigma_w: 5\nsigma_w: 6\n");
  const std::string error = loadError(path);
  EXPECT_NE(error.find(path + ":4: parameter 'sigma_w' is given twice"), std::string::npos) << error;
  const std::string prior = write("prototype_priors:\n  bat: 1\n  bat: 2\n");
  EXPECT_NE(loadError(prior).find(prior + ":3: parameter 'prototype_priors': 'bat' is given twice"), std::string::npos)
      << loadError(prior);
}

TEST_F(ParamsFile, EveryErrorGivesTheFileAndTheLine)
{
  const auto expectAt = [&](const std::string& text, const std::string& place, const std::string& reason) {
    const std::string path = write(text);
    const std::string error = loadError(path);
    EXPECT_NE(error.find(path + place), std::string::npos) << "not at " << place << ": " << error;
    EXPECT_NE(error.find(reason), std::string::npos) << error;
  };
  expectAt("sigma_w: 6\n\n# the key below is misspelt\nsigma_ww: 5\n", ":4: ", "unknown parameter 'sigma_ww'");
  expectAt("%YAML:1.0\nsigma_w: 6\np_outlier: 1.5\n", ":3: ", "'p_outlier' = 1.5 is outside its range");
  expectAt("sigma_w: 6\nlikelihood_form: 5\n", ":2: ", "takes a word");
  expectAt("sigma_w: 6\nseed: two\n", ":2: ", "'seed' takes a number, not 'two'");
  expectAt("prototype_priors:\n  bat: 1\n  cup: -2\n", ":3: ", "the weight of 'cup' = -2 must be a finite number >= 0");
  expectAt("prototype_priors: {bat: 1,\n  cup: heavy}\n", ":2: ", "the weight of 'cup' must be a number");
  // A parameter that contradicts another: the line of the one in the file (no line before yaml-cpp).
  expectAt("sigma_w: 6\nnum_v_particles: 1\n", ":2: ", "'min_support' = 2 is above 'num_v_particles' = 1");
  // The top level that is not a map (no line before yaml-cpp either).
  expectAt("\n- sigma_w\n- 6\n", ":2: ", "not a map of name: value");
  expectAt("sigma_w: 6\n[a]: 1\n", ":2: ", "a key must be a name");
  expectAt("sigma_w: 6\n\"seed\": [1, 2]\n", ":2: ", "'seed' must be a number or a word");
  const std::string parse = write("sigma_w: 6\nseed: 3: 4\n");
  EXPECT_NE(loadError(parse).find("'" + parse + "', line 2: "), std::string::npos) << loadError(parse);
}

TEST_F(ParamsFile, NestingDeeperThanAParameterFileNeedsIsRefused)
{
  // Flow and block collections a million and half a million levels deep: yaml-cpp 0.6 would
  // overflow the stack building them; both are refused at the ninth level.
  std::string block = "seed:\n";
  for (int level = 0; level < 500000; ++level)
    block += "- ";
  for (const std::string& deep : {"sigma_w: " + std::string(1000000, '['), block})
  {
    const std::string error = loadError(write(deep));
    EXPECT_NE(error.find(deep == block ? "line 2: " : "line 1: "), std::string::npos) << error.substr(0, 200);
    EXPECT_NE(error.find("nested deeper than 8"), std::string::npos) << error.substr(0, 200);
  }
  std::string indented;
  for (int level = 0; level < 12; ++level)
    indented += std::string(level, ' ') + "k" + std::to_string(level) + ":\n";
  EXPECT_NE(loadError(write(indented)).find("line 9: lists and maps nested deeper than 8"), std::string::npos)
      << loadError(write(indented));
  // The two levels of prototype_priors are read; a third is the value's error, not the nesting's.
  EXPECT_DOUBLE_EQ(amcr::loadParams(write("prototype_priors:\n  bat: 2\n")).prototype_priors.at("bat"), 2.0);
  EXPECT_NE(loadError(write("prototype_priors: {bat: [2]}\n")).find("the weight of 'bat' must be a number"),
            std::string::npos);
}

TEST_F(ParamsFile, OneDocumentWithOrWithoutTheOpenCvHeader)
{
  const std::string two = write("%YAML:1.0\n---\nsigma_w: 5\n---\nsigma_w: 6\n");
  EXPECT_NE(loadError(two).find("line 4: a second document"), std::string::npos) << loadError(two);
  EXPECT_DOUBLE_EQ(amcr::loadParams(write("---\nsigma_w: 5\n...\n")).sigma_w, 5.0);  // an end marker is no second document
  // The header keeps the lines their numbers.
  const std::string header = write("%YAML:1.0\n---\nsigma_w: 6\nsigma_ww: 5\n");
  EXPECT_NE(loadError(header).find(header + ":4: "), std::string::npos) << loadError(header);
  // Only comments, only a marker, or nothing at all: every value stays.
  for (const char* empty : {"# nothing set\n", "%YAML:1.0\n---\n", "---\n", ""})
    EXPECT_EQ(amcr::loadParams(write(empty)).sigma_w, amcr::Params().sigma_w) << empty;
}

TEST_F(ParamsFile, NumbersWordsAndSwitches)
{
  // Whole numbers as before: exact up to 2^53 either way, hexadecimal and octal as strtoll reads them.
  EXPECT_EQ(amcr::loadParams(write("seed: 0x1F\n")).seed, 31u);
  EXPECT_EQ(amcr::loadParams(write("seed: 010\n")).seed, 8u);
  EXPECT_DOUBLE_EQ(amcr::loadParams(write("prototype_priors: {bat: 9007199254740992}\n")).prototype_priors.at("bat"),
                   9007199254740992.0);
  EXPECT_NE(loadError(write("prototype_priors: {bat: 9007199254740993}\n")).find("beyond 2^53"), std::string::npos);
  EXPECT_NE(loadError(write("sigma_w: -9007199254740993\n")).find("beyond 2^53"), std::string::npos);
  EXPECT_DOUBLE_EQ(amcr::loadParams(write("sigma_w: 2.5e1\np_outlier: .25\n")).sigma_w, 25.0);
  EXPECT_NE(loadError(write("sigma_w: .inf\n")).find("'sigma_w' = inf is outside its range"), std::string::npos);
  // Quoted, a number is a word, as it was.
  EXPECT_NE(loadError(write("sigma_w: \"5\"\n")).find("'sigma_w' takes a number, not '5'"), std::string::npos);
  EXPECT_EQ(amcr::loadParams(write("likelihood_form: 'mixture'\n")).likelihood_form, amcr::LikelihoodForm::kMixture);
  // true and false switch a numeric parameter, as the nodelet's ROS parameters do (a word before yaml-cpp).
  const amcr::Params switched = amcr::loadParams(write("optical_flow: false\nfit_homography: True\n"));
  EXPECT_FALSE(switched.optical_flow);
  EXPECT_TRUE(switched.fit_homography);
  EXPECT_NE(loadError(write("likelihood_form: true\n")).find("must be 'paper' or 'mixture'"), std::string::npos);
}

TEST_F(ParamsFile, AnchorsAndAliasesAreReadTagsAreRefused)
{
  // Refused before yaml-cpp, for OpenCV's sake.
  const amcr::Params p = amcr::loadParams(write("sigma_w: &tolerance 6\nverify_tolerance: *tolerance\n"));
  EXPECT_DOUBLE_EQ(p.sigma_w, 6.0);
  EXPECT_DOUBLE_EQ(p.verify_tolerance, 6.0);
  const std::string tagged = write("sigma_w: 6\nseed: !!str 5\n");
  EXPECT_NE(loadError(tagged).find(tagged + ":2: YAML tags ('tag:yaml.org,2002:str') are not parameter values"),
            std::string::npos)
      << loadError(tagged);
  EXPECT_NE(loadError(write("sigma_w: *nowhere\n")).find("line 1: "), std::string::npos);
}
}  // namespace
