#include "json_output.h"

#include <cmath>
#include <iomanip>
#include <locale>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <nlohmann/json.hpp>

namespace amcr
{
namespace offline
{
namespace
{
/// The JSON text of a string, integer or boolean, by nlohmann's serializer.
/// Invalid UTF-8 (a file name can hold any bytes) becomes U+FFFD instead of
/// an exception, so the line is always valid JSON.
std::string dumped(const nlohmann::json& value)
{
  return value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

/// `[a, b, ...]` from elements that are JSON text already.
std::string jsonArray(const std::vector<std::string>& elements)
{
  std::string out = "[";
  for (std::size_t i = 0; i < elements.size(); ++i)
  {
    if (i > 0)
      out += ", ";
    out += elements[i];
  }
  return out + "]";
}

/// `{"key": value, ...}` with the members in the order they are added.
/// nlohmann::json cannot write the line itself: its objects sort their keys
/// (ordered_json came in 3.9, Ubuntu 20.04 has 3.7), its dump puts no space
/// after ',' and ':', and it writes doubles in shortest form, where the
/// output has a fixed number of decimals per field.
class JsonObject
{
public:
  /// A member whose value is JSON text already.
  JsonObject& member(const std::string& key, const std::string& json)
  {
    if (text_.size() > 1)
      text_ += ", ";
    text_ += dumped(key) + ": " + json;
    return *this;
  }
  JsonObject& value(const std::string& key, const nlohmann::json& content) { return member(key, dumped(content)); }
  JsonObject& number(const std::string& key, double content, int decimals)
  {
    return member(key, jsonNumber(content, decimals));
  }
  std::string text() const { return text_ + "}"; }

private:
  std::string text_ = "{";
};

/// A matrix as an array of rows, each entry with `decimals` decimals.
template <int Rows, int Cols>
std::string jsonMatrix(const cv::Matx<double, Rows, Cols>& m, int decimals)
{
  std::vector<std::string> rows;
  for (int row = 0; row < Rows; ++row)
  {
    std::vector<std::string> entries;
    for (int col = 0; col < Cols; ++col)
      entries.push_back(jsonNumber(m(row, col), decimals));
    rows.push_back(jsonArray(entries));
  }
  return jsonArray(rows);
}

std::string jsonCorrespondence(const Correspondence& c)
{
  return jsonArray({jsonNumber(c.image.x, kPixelDecimals), jsonNumber(c.image.y, kPixelDecimals),
                    jsonNumber(c.prototype.x, kPixelDecimals), jsonNumber(c.prototype.y, kPixelDecimals)});
}

std::string objectJson(const RecognizedObject& object)
{
  std::vector<std::string> correspondences;
  for (const Correspondence& c : object.correspondences)
    correspondences.push_back(jsonCorrespondence(c));
  return JsonObject()
      .value("label", object.label)
      .value("instance", object.instance)
      .value("track_id", object.track_id)
      .value("state", toString(object.state))
      .number("score", object.score, kScoreDecimals)
      .number("visible_share", object.visible_share, kScoreDecimals)
      .value("support", object.support)
      .member("image_to_prototype", jsonMatrix(object.image_to_prototype, kAffineDecimals))
      .member("prototype_to_image", jsonMatrix(object.prototype_to_image, kAffineDecimals))
      .member("homography", jsonMatrix(object.homography, kHomographyDecimals))
      .value("homography_valid", object.homography_valid)
      .number("anisotropy", object.anisotropy, kAnisotropyDecimals)
      .number("viewing_angle_deg", object.viewing_angle_deg, kAngleDecimals)
      .member("correspondences", jsonArray(correspondences))
      .text();
}

std::string objectsJson(const std::vector<RecognizedObject>& objects)
{
  std::vector<std::string> elements;
  for (const RecognizedObject& object : objects)
    elements.push_back(objectJson(object));
  return jsonArray(elements);
}
}  // namespace

std::string jsonString(const std::string& text)
{
  return dumped(text);
}

std::string jsonNumber(double value, int decimals)
{
  if (!std::isfinite(value))
    return "null";
  std::ostringstream stream;
  stream.imbue(std::locale::classic());
  stream << std::fixed << std::setprecision(decimals < 0 ? 0 : decimals) << value;
  std::string text = stream.str();
  // A negative value that rounds to zero prints as "-0.000".
  if (!text.empty() && text[0] == '-' && text.find_first_not_of("0.", 1) == std::string::npos)
    text.erase(0, 1);
  return text;
}

std::string frameJson(long frame, const RecognitionResult& result)
{
  return JsonObject()
      .value("frame", frame)
      .number("time_ms", result.time_ms, kTimeDecimals)
      .value("iteration", result.iteration)
      .number("iterations", result.iterations, kShareDecimals)
      .number("mean_m_particles", result.mean_m_particles, 1)
      .member("objects", objectsJson(result.objects))
      .member("lost", objectsJson(result.lost))
      .text();
}

std::string skippedFrameJson(long frame, long iteration, const std::string& reason)
{
  return JsonObject()
      .value("frame", frame)
      .number("time_ms", 0.0, kTimeDecimals)
      .value("iteration", iteration)
      .value("iterations", 0)
      .member("objects", "[]")
      .member("lost", "[]")
      .value("skipped", reason)
      .text();
}

void writeJsonLine(std::ostream& out, const std::string& json, const std::string& destination)
{
  out << json << '\n';
  out.flush();
  if (!out)
    throw std::runtime_error("cannot write to " + destination);
}
}  // namespace offline
}  // namespace amcr
