#include "json_output.h"

#include <cmath>
#include <iomanip>
#include <locale>
#include <sstream>
#include <stdexcept>

namespace amcr
{
namespace offline
{
namespace
{
/// Length of the valid UTF-8 sequence starting at text[i], or 0 when invalid.
std::size_t utf8SequenceLength(const std::string& text, std::size_t i)
{
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char lead = byte(i);
  std::size_t length = 0;
  unsigned char low = 0x80, high = 0xBF;  // range of the second byte
  if (lead >= 0xC2 && lead <= 0xDF)
    length = 2;
  else if (lead >= 0xE0 && lead <= 0xEF)
  {
    length = 3;
    if (lead == 0xE0)
      low = 0xA0;  // no overlong forms
    if (lead == 0xED)
      high = 0x9F;  // no surrogates
  }
  else if (lead >= 0xF0 && lead <= 0xF4)
  {
    length = 4;
    if (lead == 0xF0)
      low = 0x90;  // no overlong forms
    if (lead == 0xF4)
      high = 0x8F;  // nothing above U+10FFFF
  }
  else
    return 0;
  if (i + length > text.size())
    return 0;
  if (byte(i + 1) < low || byte(i + 1) > high)
    return 0;
  for (std::size_t k = 2; k < length; ++k)
    if (byte(i + k) < 0x80 || byte(i + k) > 0xBF)
      return 0;
  return length;
}

void appendAffine(std::string& out, const Affine& a)
{
  out += "[[";
  for (int row = 0; row < 2; ++row)
  {
    if (row > 0)
      out += "], [";
    for (int col = 0; col < 3; ++col)
    {
      if (col > 0)
        out += ", ";
      out += jsonNumber(a(row, col), kAffineDecimals);
    }
  }
  out += "]]";
}

void appendHomography(std::string& out, const Homography& h)
{
  out += "[[";
  for (int row = 0; row < 3; ++row)
  {
    if (row > 0)
      out += "], [";
    for (int col = 0; col < 3; ++col)
    {
      if (col > 0)
        out += ", ";
      out += jsonNumber(h(row, col), kHomographyDecimals);
    }
  }
  out += "]]";
}

void appendObject(std::string& out, const RecognizedObject& object)
{
  out += "{\"label\": " + jsonString(object.label);
  out += ", \"instance\": " + jsonString(object.instance);
  out += ", \"track_id\": " + std::to_string(object.track_id);
  out += ", \"state\": " + jsonString(toString(object.state));
  out += ", \"score\": " + jsonNumber(object.score, kScoreDecimals);
  out += ", \"support\": " + std::to_string(object.support);
  out += ", \"image_to_prototype\": ";
  appendAffine(out, object.image_to_prototype);
  out += ", \"prototype_to_image\": ";
  appendAffine(out, object.prototype_to_image);
  out += ", \"homography\": ";
  appendHomography(out, object.homography);
  out += std::string(", \"homography_valid\": ") + (object.homography_valid ? "true" : "false");
  out += ", \"anisotropy\": " + jsonNumber(object.anisotropy, kAnisotropyDecimals);
  out += ", \"viewing_angle_deg\": " + jsonNumber(object.viewing_angle_deg, kAngleDecimals);
  out += ", \"correspondences\": [";
  for (std::size_t i = 0; i < object.correspondences.size(); ++i)
  {
    const Correspondence& c = object.correspondences[i];
    if (i > 0)
      out += ", ";
    out += "[" + jsonNumber(c.image.x, kPixelDecimals) + ", " + jsonNumber(c.image.y, kPixelDecimals) + ", " +
           jsonNumber(c.prototype.x, kPixelDecimals) + ", " + jsonNumber(c.prototype.y, kPixelDecimals) + "]";
  }
  out += "]}";
}
}  // namespace

std::string jsonString(const std::string& text)
{
  static const char* const kHex = "0123456789abcdef";
  std::string out;
  out.reserve(text.size() + 2);
  out += '"';
  for (std::size_t i = 0; i < text.size();)
  {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c >= 0x80)
    {
      const std::size_t length = utf8SequenceLength(text, i);
      if (length == 0)
      {
        out += "\\ufffd";
        ++i;
      }
      else
      {
        out.append(text, i, length);
        i += length;
      }
      continue;
    }
    switch (c)
    {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\b':
        out += "\\b";
        break;
      case '\f':
        out += "\\f";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (c < 0x20 || c == 0x7F)
        {
          out += "\\u00";
          out += kHex[c >> 4];
          out += kHex[c & 0xF];
        }
        else
          out += static_cast<char>(c);
    }
    ++i;
  }
  out += '"';
  return out;
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
  std::string out = "{\"frame\": " + std::to_string(frame);
  out += ", \"time_ms\": " + jsonNumber(result.time_ms, kTimeDecimals);
  out += ", \"iteration\": " + std::to_string(result.iteration);
  out += ", \"iterations\": " + jsonNumber(result.iterations, kShareDecimals);
  out += ", \"mean_m_particles\": " + jsonNumber(result.mean_m_particles, 1);
  out += ", \"objects\": [";
  for (std::size_t i = 0; i < result.objects.size(); ++i)
  {
    if (i > 0)
      out += ", ";
    appendObject(out, result.objects[i]);
  }
  out += "], \"lost\": [";
  for (std::size_t i = 0; i < result.lost.size(); ++i)
  {
    if (i > 0)
      out += ", ";
    appendObject(out, result.lost[i]);
  }
  out += "]}";
  return out;
}

std::string skippedFrameJson(long frame, long iteration, const std::string& reason)
{
  return "{\"frame\": " + std::to_string(frame) + ", \"time_ms\": " + jsonNumber(0.0, kTimeDecimals) +
         ", \"iteration\": " + std::to_string(iteration) + ", \"iterations\": 0, \"objects\": [], \"lost\": [], \"skipped\": " + jsonString(reason) +
         "}";
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
