// amcr_offline's JSON writer and option parser, compiled directly.
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "json_output.h"
#include "runner_options.h"
#include "strict_json.h"

using amcr::offline::frameJson;
using amcr::offline::jsonNumber;
using amcr::offline::jsonString;
using amcr::offline::parseRunnerOptions;
using amcr::offline::RunnerOptions;
using amcr::offline::skippedFrameJson;
using amcr::offline::UsageError;
using amcr_test::member;
using amcr_test::parseStrictJson;
using nlohmann::json;

namespace
{
/// Parses `text` as one JSON string value and returns it decoded.
std::string roundTrip(const std::string& text)
{
  json value;
  std::string error;
  const std::string quoted = jsonString(text);
  EXPECT_TRUE(parseStrictJson(quoted, value, error)) << quoted << ": " << error;
  if (!value.is_string())
  {
    ADD_FAILURE() << quoted << " is no string";
    return "";
  }
  return value.get<std::string>();
}
}  // namespace

// The tests below read the output with it: it must refuse what strict JSON
// forbids, or a writer's slip would pass.
TEST(JsonOutput, TheStrictReaderRefusesWhatJsonForbids)
{
  json value;
  std::string error;
  EXPECT_TRUE(parseStrictJson(" {\"a\": [1, 2.5, null, true], \"b\": {\"a\": \"x\"}}\n", value, error)) << error;
  for (const char* bad :
       {"{\"a\": NaN}", "{\"a\": nan}", "[Infinity]", "[-inf]", "{\"a\": 1} x", "{\"a\": 1}{}", "[1,]", "{\"a\": 01}",
        "{\"a\": .5}", "{\"a\": 1.}", "[\"\t\"]", "[\"\\ud800\"]", "{'a': 1}", "{\"a\": 1, \"a\": 2}", "", "[1] // note"})
  {
    error.clear();
    EXPECT_FALSE(parseStrictJson(bad, value, error)) << "accepted: " << bad;
    EXPECT_FALSE(error.empty()) << bad;
  }
}

TEST(JsonOutput, EscapesQuotesBackslashesAndControlCharacters)
{
  EXPECT_EQ(jsonString("bird-1"), "\"bird-1\"");
  EXPECT_EQ(jsonString("a\"b"), "\"a\\\"b\"");
  EXPECT_EQ(jsonString("C:\\x"), "\"C:\\\\x\"");
  EXPECT_EQ(jsonString("l1\nl2\r\t"), "\"l1\\nl2\\r\\t\"");
  EXPECT_EQ(jsonString(std::string("\b\f", 2)), "\"\\b\\f\"");
  EXPECT_EQ(jsonString(std::string("\x01\x1f", 2)), "\"\\u0001\\u001f\"");
  EXPECT_EQ(jsonString("\x7f"), "\"\x7f\"");  // DEL is no control character to JSON
  EXPECT_EQ(jsonString(std::string("a\0b", 3)), "\"a\\u0000b\"");
  EXPECT_EQ(jsonString(""), "\"\"");
  EXPECT_EQ(jsonString("/"), "\"/\"");
}

TEST(JsonOutput, StringsRoundTripThroughAStrictParser)
{
  const std::vector<std::string> samples = {"plain", "quote \" and \\ backslash", "tab\tnew\nline",
                                            std::string("nul\0byte", 8), "caf\xc3\xa9",  // UTF-8 e-acute
                                            "\xe2\x82\xac", "\xf0\x9f\x90\xa6"};          // euro, bird
  for (const std::string& s : samples)
    EXPECT_EQ(roundTrip(s), s);
}

TEST(JsonOutput, InvalidUtf8BecomesReplacementCharacters)
{
  const std::string fffd = "\xef\xbf\xbd";  // U+FFFD in UTF-8
  const auto quoted = [](const std::string& text) { return "\"" + text + "\""; };
  // Latin-1 e-acute, a lone continuation byte, a sequence cut short (one
  // U+FFFD for the part read, before 'x' and at the end), then an overlong
  // '/', a surrogate and a code point above U+10FFFF, whose second byte
  // already breaks the sequence: one U+FFFD per byte.
  EXPECT_EQ(jsonString("caf\xe9"), quoted("caf" + fffd));
  EXPECT_EQ(jsonString("\x80"), quoted(fffd));
  EXPECT_EQ(jsonString("\xe2\x82" "x"), quoted(fffd + "x"));
  EXPECT_EQ(jsonString("\xe2\x82"), quoted(fffd));
  EXPECT_EQ(jsonString("\xc0\xaf"), quoted(fffd + fffd));
  EXPECT_EQ(jsonString("\xed\xa0\x80"), quoted(fffd + fffd + fffd));
  EXPECT_EQ(jsonString("\xf4\x90\x80\x80"), quoted(fffd + fffd + fffd + fffd));
  EXPECT_EQ(roundTrip("ok\xffok"), "ok" + fffd + "ok");
}

TEST(JsonOutput, NumbersAreFixedPrecisionAndFinite)
{
  EXPECT_EQ(jsonNumber(3.1, 3), "3.100");
  EXPECT_EQ(jsonNumber(0.93, 4), "0.9300");
  EXPECT_EQ(jsonNumber(2.0 / 3.0, 2), "0.67");
  EXPECT_EQ(jsonNumber(-1.25, 1), "-1.2");  // round half to even in binary: -1.25 is exact
  EXPECT_EQ(jsonNumber(-12.5, 0), "-12");
  EXPECT_EQ(jsonNumber(1234567.0, 2), "1234567.00");
  EXPECT_EQ(jsonNumber(0.0, 3), "0.000");
  EXPECT_EQ(jsonNumber(-0.0, 3), "0.000");
  EXPECT_EQ(jsonNumber(-0.0004, 3), "0.000");
  EXPECT_EQ(jsonNumber(-0.0006, 3), "-0.001");
  EXPECT_EQ(jsonNumber(1e-9, 6), "0.000000");
  EXPECT_EQ(jsonNumber(std::nan(""), 3), "null");
  EXPECT_EQ(jsonNumber(std::numeric_limits<double>::infinity(), 3), "null");
  EXPECT_EQ(jsonNumber(-std::numeric_limits<double>::infinity(), 3), "null");
  // Whatever the magnitude, the text is a valid JSON number.
  for (double v : {1e300, -1e300, 5e-324, 123.456})
  {
    json value;
    std::string error;
    EXPECT_TRUE(parseStrictJson(jsonNumber(v, 6), value, error)) << error;
    EXPECT_TRUE(value.is_number());
  }
}

TEST(JsonOutput, FrameLineHasTheDocumentedShape)
{
  amcr::RecognitionResult result;
  result.iteration = 7;
  result.iterations = 0.5;
  result.mean_m_particles = 412.3;
  result.time_ms = 3.14159;  // the core's measurement is the one written
  amcr::RecognizedObject object;
  object.label = "bird \"1\"";
  object.instance = "bird \"1\"/bird-3.png";
  object.prototype_id = 2;
  object.track_id = 4;
  object.state = amcr::ObjectState::kHeld;
  object.score = 0.93;
  object.support = 17;
  object.image_to_prototype = amcr::Affine(0.5, 0, -10, 0, 0.5, std::nan(""));
  object.prototype_to_image = amcr::Affine(2, 0, 20, 0, 2, -0.0);
  // A perspective view: the small perspective terms keep their digits.
  object.homography = amcr::Homography(2, 0.1, 20, 0, 2, -3, 0.000123456789, -0.0000012, 1);
  object.homography_valid = true;
  object.anisotropy = 2.000049;
  object.viewing_angle_deg = 60.004;
  object.correspondences.push_back({cv::Point2d(10.126, 20.5), cv::Point2d(1, 2)});
  object.correspondences.push_back({cv::Point2d(30, 40), cv::Point2d(5.555, -6)});
  result.objects.push_back(object);

  const std::string line = frameJson(3, result);
  EXPECT_EQ(line.find('\n'), std::string::npos);
  EXPECT_EQ(line,
            "{\"frame\": 3, \"time_ms\": 3.142, \"iteration\": 7, \"iterations\": 0.500, \"mean_m_particles\": 412.3, "
            "\"objects\": [{\"label\": \"bird \\\"1\\\"\", \"instance\": \"bird \\\"1\\\"/bird-3.png\", "
            "\"track_id\": 4, \"state\": \"held\", \"score\": 0.9300, \"visible_share\": 1.0000, \"support\": 17, "
            "\"image_to_prototype\": [[0.500000, 0.000000, -10.000000], [0.000000, 0.500000, null]], "
            "\"prototype_to_image\": [[2.000000, 0.000000, 20.000000], [0.000000, 2.000000, 0.000000]], "
            "\"homography\": [[2.0000000000, 0.1000000000, 20.0000000000], [0.0000000000, 2.0000000000, -3.0000000000], "
            "[0.0001234568, -0.0000012000, 1.0000000000]], \"homography_valid\": true, "
            "\"anisotropy\": 2.0000, \"viewing_angle_deg\": 60.00, "
            "\"correspondences\": [[10.13, 20.50, 1.00, 2.00], [30.00, 40.00, 5.55, -6.00]]}], \"lost\": []}");
  json value;
  std::string error;
  ASSERT_TRUE(parseStrictJson(line, value, error)) << error;
  const json* objects = member(value, "objects");
  ASSERT_TRUE(objects && objects->is_array());
  ASSERT_EQ(objects->size(), 1u);
  const json& first = (*objects)[0];
  const json* label = member(first, "label");
  ASSERT_TRUE(label && label->is_string());
  EXPECT_EQ(label->get<std::string>(), "bird \"1\"");
  const json* valid = member(first, "homography_valid");
  ASSERT_TRUE(valid && valid->is_boolean());
  EXPECT_TRUE(valid->get<bool>());
  const json* h = member(first, "homography");
  ASSERT_TRUE(h && h->is_array() && h->size() == 3u);
  EXPECT_NEAR((*h)[2][0].get<double>(), 0.000123456789, 1e-10);

  // A track that ended is listed under "lost" with its state.
  object.state = amcr::ObjectState::kLost;
  result.lost.push_back(object);
  result.objects.clear();
  json with_lost;
  ASSERT_TRUE(parseStrictJson(frameJson(4, result), with_lost, error)) << error;
  const json* lost = member(with_lost, "lost");
  ASSERT_TRUE(lost && lost->is_array());
  ASSERT_EQ(lost->size(), 1u);
  const json* state = member((*lost)[0], "state");
  const json* track_id = member((*lost)[0], "track_id");
  ASSERT_TRUE(state && state->is_string() && track_id && track_id->is_number());
  EXPECT_EQ(state->get<std::string>(), "lost");
  EXPECT_EQ(track_id->get<double>(), 4);
}

TEST(JsonOutput, EmptyAndSkippedFrames)
{
  amcr::RecognitionResult empty;
  empty.iteration = 1;
  empty.iterations = 1.0;
  empty.time_ms = 0.5;
  EXPECT_EQ(frameJson(0, empty),
            "{\"frame\": 0, \"time_ms\": 0.500, \"iteration\": 1, \"iterations\": 1.000, \"mean_m_particles\": 0.0, "
            "\"objects\": [], \"lost\": []}");
  const std::string skipped = skippedFrameJson(5, 4, "cannot read image 'a\\b.png'");
  EXPECT_EQ(skipped,
            "{\"frame\": 5, \"time_ms\": 0.000, \"iteration\": 4, \"iterations\": 0, \"objects\": [], "
            "\"lost\": [], \"skipped\": \"cannot read image 'a\\\\b.png'\"}");
  json value;
  std::string error;
  EXPECT_TRUE(parseStrictJson(skipped, value, error)) << error;
}

TEST(JsonOutput, WriteFailureThrows)
{
  std::ostringstream out;
  amcr::offline::writeJsonLine(out, "{}", "memory");
  EXPECT_EQ(out.str(), "{}\n");
  out.setstate(std::ios::badbit);
  EXPECT_THROW(amcr::offline::writeJsonLine(out, "{}", "memory"), std::runtime_error);
}

TEST(RunnerOptions, ParsesEveryOption)
{
  const RunnerOptions o = parseRunnerOptions({"--prototypes", "protos", "--input=in.avi", "--config", "c.yaml",
                                              "--seed", "18446744073709551615", "--frames", "7", "--output",
                                              "o.jsonl", "--overlay", "v.MP4"});
  EXPECT_EQ(o.prototypes, "protos");
  EXPECT_EQ(o.input, "in.avi");
  EXPECT_EQ(o.config, "c.yaml");
  EXPECT_TRUE(o.has_seed);
  EXPECT_EQ(o.seed, 18446744073709551615ull);
  EXPECT_TRUE(o.has_frames);
  EXPECT_EQ(o.frames, 7);
  EXPECT_EQ(o.output, "o.jsonl");
  EXPECT_EQ(o.overlay, "v.MP4");
  EXPECT_FALSE(o.help);

  const RunnerOptions d = parseRunnerOptions({"--input", "x.png", "--prototypes", "p"});
  EXPECT_FALSE(d.has_seed);
  EXPECT_FALSE(d.has_frames);
  EXPECT_TRUE(d.output.empty());
  EXPECT_TRUE(parseRunnerOptions({"--help"}).help);
  EXPECT_EQ(amcr::offline::overlayFourcc("a/b.avi"), "MJPG");
  EXPECT_EQ(amcr::offline::overlayFourcc("b.mp4"), "mp4v");
  EXPECT_EQ(amcr::offline::overlayFourcc("dir.avi/b"), "");
}

TEST(RunnerOptions, RejectsBadCommandLinesNamingTheProblem)
{
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--input", "x"}, "--prototypes"},
      {{"--prototypes", "p"}, "--input"},
      {{"--prototypes", "p", "--input", "x", "--seed", "abc"}, "--seed"},
      {{"--prototypes", "p", "--input", "x", "--seed", "-1"}, "--seed"},
      {{"--prototypes", "p", "--input", "x", "--seed", "18446744073709551616"}, "--seed"},
      {{"--prototypes", "p", "--input", "x", "--seed", "1.5"}, "--seed"},
      {{"--prototypes", "p", "--input", "x", "--frames", "0"}, "--frames"},
      {{"--prototypes", "p", "--input", "x", "--frames", "ten"}, "--frames"},
      {{"--prototypes", "p", "--input", "x", "--frames"}, "--frames"},
      {{"--prototypes", "p", "--input", "--frames", "3"}, "--input"},
      {{"--prototypes", "p", "--input", "x", "--overlay", "v.gif"}, "--overlay"},
      {{"--prototypes", "p", "--input", "x", "--bogus", "1"}, "--bogus"},
      {{"--prototypes", "p", "--input", "x", "stray"}, "stray"},
      {{"--prototypes", "p", "--prototypes", "q", "--input", "x"}, "twice"},
      {{"--prototypes=", "--input", "x"}, "--prototypes"},
      {{"--prototypes", "", "--input", "x"}, "--prototypes"},
      // No abbreviated names, no other sign than digits, no value taken from the next option.
      {{"--proto", "p", "--input", "x"}, "unknown option '--proto'"},
      {{"--prototypes", "p", "--input", "x", "--seed", "+5"}, "--seed"},
      {{"--prototypes", "p", "--input", "x", "--seed", " 5"}, "--seed"},
      {{"--prototypes", "p", "--input", "x", "--frames", "1000000001"}, "--frames"},
      {{"--prototypes", "p", "--input", "--bogus"}, "option --input needs a value"},
      {{"--prototypes", "p", "--input", "x", "-x"}, "unexpected argument '-x'"},
      {{"--prototypes", "p", "--input", "x", "--help=yes"}, "--help"},
  };
  for (const auto& c : cases)
  {
    std::string joined;
    for (const std::string& a : c.first)
      joined += a + " ";
    try
    {
      parseRunnerOptions(c.first);
      ADD_FAILURE() << "accepted: " << joined;
    }
    catch (const UsageError& e)
    {
      EXPECT_NE(std::string(e.what()).find(c.second), std::string::npos) << joined << "-> " << e.what();
    }
  }
}
