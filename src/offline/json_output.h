// amcr_offline's output: one JSON object per input frame, one per line; the
// strings, integers and booleans by nlohmann's serializer, the layout (key
// order, ", " and ": ") and the fixed-decimal numbers here:
//   {"frame": 0, "time_ms": 3.100, "iteration": 1, "objects": [{"label": "bird-1",
//    "track_id": 1, "state": "held", "score": 0.9300, "support": 17,
//    "image_to_prototype": [[a, b, c], [d, e, f]], "prototype_to_image": [[a, b, c], [d, e, f]],
//    "homography": [[a, b, c], [d, e, f], [g, h, 1]], "homography_valid": false,
//    "anisotropy": 1.0000, "viewing_angle_deg": 0.00,
//    "correspondences": [[xi, yi, xp, yp], ...]}], "lost": [...]}
// Other tools read these names: keep them.
#pragma once

#include <ostream>
#include <string>

#include "amcr/extraction/recognition_result.h"

namespace amcr
{
namespace offline
{
/// Digits after the decimal point, per kind of number.
constexpr int kTimeDecimals = 3;    ///< time_ms
constexpr int kScoreDecimals = 4;   ///< score in [0, 1]
constexpr int kAffineDecimals = 6;  ///< affine matrix entries
/// Homography entries: its perspective terms are about 1e-4 / px, and w
/// must stay exact to 1e-6 over a few thousand px.
constexpr int kHomographyDecimals = 10;
constexpr int kAnisotropyDecimals = 4;  ///< anisotropy, >= 1
constexpr int kAngleDecimals = 2;       ///< viewing_angle_deg, degrees
constexpr int kPixelDecimals = 2;   ///< correspondence coordinates, px
constexpr int kShareDecimals = 3;   ///< iterations (share of an iteration run on a frame)

/// A quoted JSON string (nlohmann's serializer). Escapes '"', '\\' and the
/// control characters U+0000..U+001F (as \n, \t, ... or \u00XX); valid UTF-8
/// passes through, each ill-formed part of UTF-8 (a byte that cannot start a
/// character, a character cut short) becomes one U+FFFD (written as the
/// character itself), so the output is always valid JSON.
std::string jsonString(const std::string& text);

/// A number in fixed notation with `decimals` digits after the point,
/// independent of the locale; "-0.00" is written "0.00". Not-a-number and
/// infinities, which JSON cannot hold, are written as null.
std::string jsonNumber(double value, int decimals);

/// The line of a processed frame (without the newline): "time_ms" is the
/// result's own (the time the recognition step took), the objects keep the
/// result's order (best score first).
std::string frameJson(long frame, const RecognitionResult& result);

/// The line of a frame that could not be read: no step ran, `iteration` is
/// the recognizer's unchanged count, "skipped" gives the reason.
std::string skippedFrameJson(long frame, long iteration, const std::string& reason);

/// Writes `json` and a newline, flushes, and throws std::runtime_error naming
/// `destination` when the stream fails (disk full, closed pipe).
void writeJsonLine(std::ostream& out, const std::string& json, const std::string& destination);
}  // namespace offline
}  // namespace amcr
