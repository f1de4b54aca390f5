// Inputs the fuzzers (fuzz/, scripts/fuzz) found, each run through the API its fuzz target calls.
// A new finding: its bytes here, the target that found it, what went wrong.
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "amcr/base/errors.h"
#include "amcr/io/image_file.h"
#include "amcr/base/params.h"
#include "amcr/io/params_file.h"
#include "scene_drawing.h"

namespace
{
std::string writeFile(const amcr_test::TempDir& dir, const std::string& name, const std::string& bytes)
{
  const std::string path = dir.file(name);
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

/// loadParams must refuse the file with a ParameterError naming it and holding `place` (anything
/// else escaping is what the fuzzer reported).
void expectParameterErrorNamingTheFile(const std::string& path, const std::string& place = "")
{
  try
  {
    amcr::loadParams(path);
    ADD_FAILURE() << "loadParams accepted " << path;
  }
  catch (const amcr::ParameterError& e)
  {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(place), std::string::npos) << "not at " << place << ": " << e.what();
  }
}
}  // namespace

// fuzz_param_file: OpenCV 4.6's YAML parser (the reader before yaml-cpp) threw std::length_error
// ("basic_string::_M_create"), not cv::Exception, on an empty key after an entry of a nested map;
// loadParams let it out.
TEST(FuzzRegression, ParamFileWithAnEmptyKeyInANestedMap)
{
  amcr_test::TempDir dir;
  expectParameterErrorNamingTheFile(writeFile(dir, "empty_key.yaml", "%YAML:1.0\n---\na:\n  b: 1\n  :\n"));
  // The input as the fuzzer found it (NUL bytes in the header line).
  const char found[] = "%YAML:1.0\0---\nprototype_priorsML:1.0\0---\nprototype_priors:\n  disc: 2.0\n  :\n"
                       "  disc: 2.0\n  triangle: 0.5#min_support: 3\n";
  expectParameterErrorNamingTheFile(writeFile(dir, "found.yaml", std::string(found, sizeof(found) - 1)));
}

// fuzz_param_file: OpenCV 4.6's YAML reader, which read the parameter file before yaml-cpp, never
// returned on these files (a document marker with text after it, then a line with an open quote; a
// tagged key followed by a line that is no entry; an indented top-level map followed by an indented
// "...--"), and refused the YAML forms around them. Each must now come back at once, refused with
// the file and the line, or read. Should a reader hang on one again, this test hangs instead of
// failing (CI stops it at its time limit).
TEST(FuzzRegression, ParamFileOnWhichOpenCVNeverReturned)
{
  amcr_test::TempDir dir;
  expectParameterErrorNamingTheFile(writeFile(dir, "hang.yaml", "%YAML:1.\n---s:0\n\")--\nr"), ":2: ");
  expectParameterErrorNamingTheFile(writeFile(dir, "tag.yaml", "%YAML:1.0\n---\n!p:\n  d: 2.0\nmyn-\nl: 3\n"), "line 6");
  expectParameterErrorNamingTheFile(writeFile(dir, "no_entry.yaml", "%YAML:1.0\n---\nsigma_w: 5\nmyn-\n"), ":4: ");
  expectParameterErrorNamingTheFile(writeFile(dir, "indented.yaml", " sigma_w: 2.0\n ...--\n  p_invalid: 0.5\n"), "line 3");
  const char found_indented[] = "%YAML:1.0\n dic: 2.0\n \x8b\x8b\x8b\x8b\xff" "c: 2.0\n ...--\n  ttriangle: 0.5\n"
                                "miriangle:miriangle: 0.5\nmt: 3\n";
  expectParameterErrorNamingTheFile(writeFile(dir, "indented_found.yaml", found_indented), "line 5");
  // A second document is refused; an end marker, an anchor and an indented map are plain YAML.
  expectParameterErrorNamingTheFile(
      writeFile(dir, "two_documents.yaml", "%YAML:1.0\n---\nsigma_w: 5\n---\nsigma_w: 6\n"), "line 4");
  EXPECT_DOUBLE_EQ(amcr::loadParams(writeFile(dir, "end_marker.yaml", "%YAML:1.0\n---\nsigma_w: 5\n...\n")).sigma_w, 5.0);
  EXPECT_DOUBLE_EQ(amcr::loadParams(writeFile(dir, "anchor.yaml", "%YAML:1.0\n---\nsigma_w: &a 5\n")).sigma_w, 5.0);
  EXPECT_DOUBLE_EQ(amcr::loadParams(writeFile(dir, "indented_map.yaml", " sigma_w: 2.0\n p_invalid: 0.5\n")).sigma_w, 2.0);
  const std::string valid = writeFile(dir, "valid.yaml", "%YAML:1.0\n---   # parameters\nsigma_w: 6\n");
  EXPECT_DOUBLE_EQ(amcr::loadParams(valid).sigma_w, 6.0);
}

// fuzz_frame_source: a PNG whose header claims 4294967295 x 4294967295 pixels made the image bound
// multiply the two in 64 bits (signed overflow, UBSan); readImageFile must refuse it naming the bound.
TEST(FuzzRegression, PngHeaderWithTheLargestSize)
{
  amcr_test::TempDir dir;
  const unsigned char bytes[] = {0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48,
                                 0x44, 0x52, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0x04, 0x00, 0x00, 0x18,
                                 0x00, 0xff, 0xff, 0xff, 0xdc, 0x00, 0x00, 0x00, 0x00, 0x3f, 0x49, 0x45, 0x4e, 0x44,
                                 0xae, 0x42, 0x60, 0x82};
  const std::string path = writeFile(dir, "huge.png", std::string(reinterpret_cast<const char*>(bytes), sizeof(bytes)));
  try
  {
    amcr::readImageFile(path);
    ADD_FAILURE() << "readImageFile accepted " << path;
  }
  catch (const amcr::InputError& e)
  {
    EXPECT_NE(std::string(e.what()).find("4294967295 x 4294967295"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("above the bound"), std::string::npos) << e.what();
  }
}

