// The overlay of paper figures 2, 5 and 7: input with V-particles and outlines,
// prototypes with M-particles, correspondence lines between them.
#include "amcr/overlay.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "amcr/base/errors.h"
#include "amcr/scan/radial_scan.h"

namespace amcr
{
namespace
{
const cv::Scalar kPanelBackground(40, 40, 40);
const cv::Scalar kPanelShape(115, 115, 115);
const cv::Scalar kUndecided(170, 170, 170);
const cv::Scalar kTextBackground(20, 20, 20);
const cv::Scalar kCoveredColour(150, 150, 150);  // a covered part of an outline, over the outline's colour
const int kFont = cv::FONT_HERSHEY_SIMPLEX;

/// An evenly spread hue sequence (golden ratio), as BGR.
cv::Scalar hueColour(double position, int saturation)
{
  const double hue = std::fmod(position * 0.6180339887498949, 1.0);
  cv::Mat hsv(1, 1, CV_8UC3, cv::Scalar(hue * 180.0, saturation, 255));
  cv::Mat bgr;
  cv::cvtColor(hsv, bgr, cv::COLOR_HSV2BGR);
  const cv::Vec3b c = bgr.at<cv::Vec3b>(0, 0);
  return cv::Scalar(c[0], c[1], c[2]);
}

cv::Scalar trackColour(int track_id) { return hueColour(track_id + 0.37, 150); }

/// The input as 8-bit BGR: 8-bit images keep their colour, any other type
/// goes through the library's grey conversion (which names unsupported types).
cv::Mat toBgr8(const cv::Mat& input)
{
  if (input.empty())
    throw InputError("drawOverlay: the input image is empty");
  cv::Mat bgr;
  if (input.depth() == CV_8U && input.channels() == 3)
    bgr = input.clone();
  else if (input.depth() == CV_8U && input.channels() == 4)
    cv::cvtColor(input, bgr, cv::COLOR_BGRA2BGR);
  else if (input.depth() == CV_8U && input.channels() == 1)
    cv::cvtColor(input, bgr, cv::COLOR_GRAY2BGR);
  else
    cv::cvtColor(toGray8(input), bgr, cv::COLOR_GRAY2BGR);
  return bgr;
}

/// Text on a dark box so it reads over any background; `origin` is the
/// top-left corner of the box. The box is kept inside `canvas`.
void drawText(cv::Mat& canvas, const std::string& text, cv::Point origin, const cv::Scalar& colour,
              double scale = 0.4)
{
  int baseline = 0;
  const cv::Size size = cv::getTextSize(text, kFont, scale, 1, &baseline);
  cv::Rect box(origin.x, origin.y, size.width + 4, size.height + baseline + 4);
  box.x = std::max(0, std::min(box.x, canvas.cols - box.width));
  box.y = std::max(0, std::min(box.y, canvas.rows - box.height));
  cv::rectangle(canvas, box, kTextBackground, cv::FILLED);
  cv::putText(canvas, text, cv::Point(box.x + 2, box.y + 2 + size.height), kFont, scale, colour, 1, cv::LINE_AA);
}

std::string format(const char* pattern, double value)
{
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), pattern, value);
  return buffer;
}

/// Where a prototype's table is drawn inside its cell: panel = offset + scale * table.
struct PanelMap
{
  cv::Rect cell;
  cv::Rect picture;  // the scaled mask
  double scale = 1.0;
  cv::Point2d offset;

  /// Table px (pixel centres) -> overlay px, consistent with cv::resize.
  cv::Point2d toOverlay(const cv::Point2d& table) const
  {
    return {offset.x + (table.x + 0.5) * scale - 0.5, offset.y + (table.y + 0.5) * scale - 0.5};
  }
};

int labelStripHeight(int cell) { return std::max(12, std::min(18, cell / 8)); }

PanelMap panelMap(const OverlayLayout& layout, int index, const Prototype& prototype)
{
  PanelMap map;
  map.cell = layout.cellRect(index);
  const int pad = 3;
  const int strip = labelStripHeight(layout.cell);
  const int avail_w = std::max(1, map.cell.width - 2 * pad);
  const int avail_h = std::max(1, map.cell.height - strip - 2 * pad);
  const int w = std::max(1, prototype.width());
  const int h = std::max(1, prototype.height());
  map.scale = std::min(static_cast<double>(avail_w) / w, static_cast<double>(avail_h) / h);
  const int pw = std::max(1, static_cast<int>(std::lround(w * map.scale)));
  const int ph = std::max(1, static_cast<int>(std::lround(h * map.scale)));
  map.picture = cv::Rect(map.cell.x + pad + (avail_w - pw) / 2, map.cell.y + strip + pad + (avail_h - ph) / 2, pw, ph);
  map.offset = cv::Point2d(map.picture.x, map.picture.y);
  return map;
}

cv::Point toPixel(const cv::Point2d& p) { return cv::Point(cvRound(p.x), cvRound(p.y)); }

bool finite(const cv::Point2d& p) { return std::isfinite(p.x) && std::isfinite(p.y); }

void drawPanel(cv::Mat& canvas, const PanelMap& map, const Prototype& prototype, int index, bool recognized)
{
  cv::Mat cell = canvas(map.cell);
  cell.setTo(kPanelBackground);
  if (!prototype.mask().empty())
  {
    cv::Mat scaled;
    cv::resize(prototype.mask(), scaled, map.picture.size(), 0, 0, cv::INTER_AREA);
    cv::Mat picture = canvas(map.picture);
    picture.setTo(kPanelShape, scaled > 127);
  }
  const cv::Scalar colour = prototypeColour(index);
  cv::rectangle(canvas, map.cell, colour, recognized ? 3 : 1);
  const int strip = labelStripHeight(map.cell.height);
  const double scale = std::min(0.45, std::max(0.3, strip / 36.0));
  std::string label = prototype.label();
  // Shorten labels that do not fit the cell.
  while (label.size() > 3 && cv::getTextSize(label, kFont, scale, 1, nullptr).width > map.cell.width - 12)
    label = label.substr(0, label.size() - 3) + "..";
  cv::putText(canvas, label, cv::Point(map.cell.x + 6, map.cell.y + strip - 1), kFont, scale, colour, 1, cv::LINE_AA);
}
}  // namespace

cv::Scalar prototypeColour(int index) { return hueColour(index, 230); }

std::vector<std::string> objectLabel(const RecognizedObject& object)
{
  std::string view = "view " + format("%.0f", object.viewing_angle_deg) + "deg " + format("%.2f:1", object.anisotropy);
  if (object.homography_valid)
    view += " persp";
  std::string first = object.label + " #" + std::to_string(object.track_id) + " " + format("%.2f", object.score) +
                      " (" + std::to_string(object.support) + ") " + toString(object.state);
  // How much of it shows, when something covers a part.
  if (object.visible_share < 1.0)
    first += " vis " + format("%.0f%%", 100.0 * object.visible_share);
  return {first, view};
}

cv::Scalar vParticleColour(int index) { return hueColour(index + 0.5, 255); }

cv::Rect OverlayLayout::cellRect(int index) const
{
  const int columns = std::max(1, grid_columns);
  return cv::Rect(column.x + (index % columns) * cell, column.y + (index / columns) * cell, cell, cell);
}

OverlayLayout overlayLayout(const cv::Size& input_size, std::size_t num_prototypes, const OverlayOptions& options)
{
  const int r = static_cast<int>(std::max<std::size_t>(1, num_prototypes));
  const int min_cell = std::max(16, options.min_panel_size);
  const int height = std::max(input_size.height, min_cell);
  const double fraction = std::min(4.0, std::max(0.05, options.max_column_fraction));
  const int max_width = std::max(min_cell, static_cast<int>(fraction * input_size.width));

  // The grid with the largest square cells that fits the height and the width budget.
  OverlayLayout layout;
  for (int c = 1; c <= r; ++c)
  {
    const int rows = (r + c - 1) / c;
    const int cell = std::min(height / rows, max_width / c);
    if (cell > layout.cell)
    {
      layout.cell = cell;
      layout.grid_columns = c;
      layout.grid_rows = rows;
    }
  }
  // Too many prototypes for the budget: keep the cells readable, widen the column.
  if (layout.cell < min_cell)
  {
    const int rows_max = std::max(1, height / min_cell);
    layout.grid_columns = (r + rows_max - 1) / rows_max;
    layout.grid_rows = (r + layout.grid_columns - 1) / layout.grid_columns;
    layout.cell = height / layout.grid_rows;
  }
  layout.image = cv::Rect(0, 0, input_size.width, input_size.height);
  layout.column = cv::Rect(input_size.width, 0, layout.grid_columns * layout.cell, height);
  // Even sides: some video codecs (mp4v, H.264) refuse odd frame sizes.
  layout.size = cv::Size((input_size.width + layout.column.width + 1) / 2 * 2, (height + 1) / 2 * 2);
  return layout;
}

namespace
{
/// M-particles in the panels, one colour per owning V-particle.
void drawMParticles(cv::Mat& canvas, const std::vector<PanelMap>& panels, const FilterView& view,
                    const OverlayOptions& options)
{
  const std::size_t r = std::min(panels.size(), view.m_by_prototype.size());
  for (std::size_t k = 0; options.draw_m_particles && k < r; ++k)
    for (const MParticleDot& dot : view.m_by_prototype[k])
    {
      const cv::Point2d p = panels[k].toOverlay(cv::Point2d(dot.table));
      if (finite(p) && panels[k].picture.contains(toPixel(p)))
        cv::circle(canvas, toPixel(p), options.m_dot_radius, vParticleColour(dot.v), cv::FILLED);
    }
}

/// The covered part of an object's outline (covered_outline.h): each covered
/// point's stretch to the next one dotted in grey over the outline's colour,
/// so that what the object is taken to be behind the occluder shows.
void drawCovered(cv::Mat& image, const RecognizedObject& object)
{
  const std::size_t n = object.outline.size();
  if (object.covered.size() != n)
    return;
  for (std::size_t i = 0; i < n; ++i)
  {
    const cv::Point2d& a = object.outline[i];
    const cv::Point2d& b = object.outline[(i + 1) % n];
    if (object.covered[i] == 0 || !finite(a) || !finite(b) || i % 2 != 0)
      continue;
    cv::line(image, toPixel(a), toPixel(b), kCoveredColour, 2, cv::LINE_AA);
  }
}

/// A recognized object: outline and text in the input, correspondence lines
/// from the V-particles to the cluster means in the panel.
void drawObject(cv::Mat& canvas, cv::Mat& image, const std::vector<PanelMap>& panels, const PrototypeMemory& memory,
                const RecognizedObject& object, const OverlayOptions& options)
{
  const int r = static_cast<int>(memory.size());
  const cv::Scalar colour = trackColour(object.track_id);
  std::vector<cv::Point> outline;
  outline.reserve(object.outline.size());
  for (const cv::Point2d& p : object.outline)
    if (finite(p))
      outline.push_back(toPixel(p));
  if (outline.size() >= 2)
    cv::polylines(image, outline, true, colour, 2, cv::LINE_AA);
  drawCovered(image, object);

  if (options.draw_correspondences && object.prototype_id >= 0 && object.prototype_id < r)
  {
    const Prototype& prototype = memory[object.prototype_id];
    const PanelMap& panel = panels[object.prototype_id];
    for (const Correspondence& c : object.correspondences)
    {
      const cv::Point2d target = panel.toOverlay(applyAffine(prototype.originalToTable(), c.prototype));
      if (!finite(c.image) || !finite(target))
        continue;
      cv::line(canvas, toPixel(c.image), toPixel(target), colour, 1, cv::LINE_AA);
      // The cluster mean, ringed in black so it stands out of the M-particle dots.
      cv::circle(canvas, toPixel(target), 4, cv::Scalar(0, 0, 0), 3, cv::LINE_AA);
      cv::circle(canvas, toPixel(target), 4, colour, 1, cv::LINE_AA);
    }
  }

  const std::vector<std::string> lines = objectLabel(object);
  // The lines stacked above the outline's box, the last just above it.
  constexpr int kLineHeight = 16;
  cv::Point anchor(0, 0);
  if (!outline.empty())
  {
    const cv::Rect box = cv::boundingRect(outline);
    anchor = cv::Point(box.x, box.y - 2 - kLineHeight * static_cast<int>(lines.size()));
  }
  for (std::size_t i = 0; i < lines.size(); ++i)
    drawText(image, lines[i], anchor + cv::Point(0, kLineHeight * static_cast<int>(i)), colour);
}

/// A V-particle deciding between look-alike clusters (discriminative_attention.h):
/// the outline of each competing interpretation, in its prototype's colour,
/// thin and dashed by sampling every other segment (none when none compete).
void drawCompeting(cv::Mat& image, const PrototypeMemory& memory, const VParticleView& particle)
{
  for (const CompetingView& c : particle.competing)
  {
    if (c.prototype < 0 || c.prototype >= static_cast<int>(memory.size()))
      continue;
    const std::vector<OutlinePoint>& outline = memory[c.prototype].outline();
    for (std::size_t i = 0; i + 1 < outline.size(); i += 2)
    {
      const cv::Point2d a = applyAffine(c.table_to_input, cv::Point2d(outline[i].position));
      const cv::Point2d b = applyAffine(c.table_to_input, cv::Point2d(outline[i + 1].position));
      if (finite(a) && finite(b))
        cv::line(image, toPixel(a), toPixel(b), prototypeColour(c.prototype), 1, cv::LINE_AA);
    }
  }
}

/// V-particles on top: circle in the dominant prototype's colour, heading
/// tick in the V-particle's own colour, and a white trail from where the
/// optical flow took it in this frame. A V-particle deciding between
/// look-alike clusters has (draw_competing) their outlines drawn, and a
/// white ring when its move was chosen to decide between them.
void drawVParticles(cv::Mat& image, const PrototypeMemory& memory, const FilterView& view,
                    const OverlayOptions& options)
{
  for (std::size_t v = 0; options.draw_v_particles && options.draw_competing && v < view.v.size(); ++v)
    drawCompeting(image, memory, view.v[v]);
  for (std::size_t v = 0; options.draw_v_particles && v < view.v.size(); ++v)
  {
    const VParticleView& particle = view.v[v];
    const cv::Point2d p(particle.position);
    if (!finite(p) || !std::isfinite(particle.theta))
      continue;
    if (particle.trail.valid)
      cv::line(image, toPixel(cv::Point2d(particle.trail.from)), toPixel(p), cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
    const cv::Scalar circle_colour =
        particle.dominant_prototype >= 0 ? prototypeColour(particle.dominant_prototype) : kUndecided;
    const cv::Point2d tip(p.x + options.heading_length * std::cos(particle.theta),
                          p.y + options.heading_length * std::sin(particle.theta));
    cv::line(image, toPixel(p), toPixel(tip), vParticleColour(static_cast<int>(v)), 2, cv::LINE_AA);
    cv::circle(image, toPixel(p), options.v_radius, circle_colour, 2, cv::LINE_AA);
    if (particle.discriminating)
      cv::circle(image, toPixel(p), options.v_radius + 2, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
  }
}

void drawStatus(cv::Mat& image, const FilterView& view, const RecognitionResult& result)
{
  const std::string status = "iteration " + std::to_string(result.iteration) + "  " +
                             format("%.1f ms", result.time_ms) + "  converged V " +
                             std::to_string(result.converged_v_particles) + "/" + std::to_string(view.v.size()) +
                             format("  M/V %.0f", result.mean_m_particles) + "  objects " + std::to_string(result.objects.size()) +
                             (result.iterations < 1.0 ? format("  %.2f of an iteration", result.iterations) : "");
  drawText(image, status, cv::Point(0, 0), cv::Scalar(255, 255, 255));
}
}  // namespace

cv::Mat drawOverlay(const cv::Mat& input, const PrototypeMemory& memory, const FilterView& view,
                    const RecognitionResult& result, const OverlayOptions& options)
{
  const cv::Mat bgr = toBgr8(input);
  const int r = static_cast<int>(memory.size());
  const OverlayLayout layout = overlayLayout(bgr.size(), memory.size(), options);

  cv::Mat canvas(layout.size, CV_8UC3, cv::Scalar(0, 0, 0));
  bgr.copyTo(canvas(layout.image));

  // Prototype panels; a recognized prototype gets a thick frame.
  std::vector<bool> recognized(r, false);
  for (const RecognizedObject& object : result.objects)
    if (object.prototype_id >= 0 && object.prototype_id < r)
      recognized[object.prototype_id] = true;
  std::vector<PanelMap> panels;
  panels.reserve(r);
  for (int k = 0; k < r; ++k)
  {
    panels.push_back(panelMap(layout, k, memory[k]));
    drawPanel(canvas, panels.back(), memory[k], k, recognized[k]);
  }
  drawMParticles(canvas, panels, view, options);

  cv::Mat image = canvas(layout.image);
  for (const RecognizedObject& object : result.objects)
    drawObject(canvas, image, panels, memory, object, options);
  drawVParticles(image, memory, view, options);
  if (options.draw_status)
    drawStatus(image, view, result);
  return canvas;
}

cv::Mat drawOverlay(const cv::Mat& input, const Recognizer& recognizer, const RecognitionResult& result,
                    const OverlayOptions& options)
{
  return drawOverlay(input, recognizer.memory(), recognizer.view(), result, options);
}
}  // namespace amcr
