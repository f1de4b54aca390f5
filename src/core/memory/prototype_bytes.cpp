// A prototype as bytes for the table cache (table_cache.h). The layout is
// the order of the fields below; kTableFormatVersion (table_cache.h) must
// change with it. fromBytes() checks every size against the others even
// though the cache has already checked the checksum: a file written by a
// faulty build must not become an out-of-bounds read.
#include "amcr/memory/prototype.h"

#include <cstring>

#include "amcr/base/errors.h"
#include "io/byte_stream.h"

namespace amcr
{
namespace
{
// The largest table side fromBytes() accepts: prototype_size 512 and its margin, with room.
constexpr int kLargestSide = 4096;
}  // namespace

std::vector<std::uint8_t> Prototype::toBytes() const
{
  ByteWriter out;
  out.put<std::int32_t>(placement_.original_size.width);
  out.put<std::int32_t>(placement_.original_size.height);
  out.put(blur_sigma_);
  out.put<std::int32_t>(table_.stride());
  out.put<std::int32_t>(mask_.cols);
  out.put<std::int32_t>(mask_.rows);
  const cv::Mat mask = mask_.isContinuous() ? mask_ : mask_.clone();
  out.putBytes(mask.data, mask.total());
  out.put<std::int32_t>(isTemplate() ? (keep_polarity_ ? 2 : 1) : 0);  // 2: a template that keeps its polarity
  if (isTemplate())
  {
    const cv::Mat scan = template_scan_.isContinuous() ? template_scan_ : template_scan_.clone();
    out.putBytes(scan.data, scan.total());
  }
  putMatx(out, placement_.original_to_table);
  putMatx(out, placement_.table_to_original);
  out.put<std::uint64_t>(table_.bytes());
  out.putBytes(table_.data(), table_.bytes());
  out.put<std::uint64_t>(interior_.size());
  for (const cv::Point& p : interior_)
  {
    out.put<std::int32_t>(p.x);
    out.put<std::int32_t>(p.y);
  }
  out.put<std::uint64_t>(outline_.size());
  for (const OutlinePoint& p : outline_)
  {
    out.put(p.position.x);
    out.put(p.position.y);
    out.put(p.normal.x);
    out.put(p.normal.y);
  }
  return out.take();
}

std::shared_ptr<const Prototype> Prototype::fromBytes(const std::string& label, const std::uint8_t* data,
                                                      std::size_t size, const std::string& instance)
{
  ByteReader in(data, size);
  std::shared_ptr<Prototype> p(new Prototype());
  p->label_ = label;
  p->instance_ = instance.empty() ? label : instance;
  p->placement_.original_size.width = in.get<std::int32_t>("the original size");
  p->placement_.original_size.height = in.get<std::int32_t>("the original size");
  p->blur_sigma_ = in.get<double>("the blur");
  const auto stride = in.get<std::int32_t>("the table stride");
  if (stride < 1 || stride > kMaxTableStride)
    throw MemoryError("a table stride of " + std::to_string(stride));
  const auto cols = in.get<std::int32_t>("the table size");
  const auto rows = in.get<std::int32_t>("the table size");
  if (cols < 1 || rows < 1 || cols > kLargestSide || rows > kLargestSide)
    throw MemoryError("a table of " + std::to_string(cols) + " x " + std::to_string(rows) + " px");
  p->mask_.create(rows, cols, CV_8UC1);
  in.getBytes(p->mask_.data, p->mask_.total(), "the mask");
  const auto kind = in.get<std::int32_t>("the kind");
  if (kind < 0 || kind > 2)
    throw MemoryError("a prototype kind of " + std::to_string(kind));
  if (kind > 0)
  {
    p->kind_ = PrototypeKind::kTemplate;
    p->keep_polarity_ = kind == 2;
    p->template_scan_.create(rows, cols, CV_8UC1);
    in.getBytes(p->template_scan_.data, p->template_scan_.total(), "the template");
  }
  p->placement_.original_to_table = getMatx(in, "the affine to the table");
  p->placement_.table_to_original = getMatx(in, "the affine from the table");
  p->table_ = RadialTable(cv::Size(cols, rows), stride);
  const std::size_t table_size = in.count(1, "the table");
  if (table_size != p->table_.bytes())
    throw MemoryError("a table of " + std::to_string(table_size) + " bytes for " + std::to_string(cols) + " x " +
                      std::to_string(rows) + " px at stride " + std::to_string(stride));
  in.getBytes(p->table_.data(), table_size, "the table");
  p->interior_.resize(in.count(8, "the interior"));
  for (cv::Point& at : p->interior_)
  {
    at.x = in.get<std::int32_t>("the interior");
    at.y = in.get<std::int32_t>("the interior");
    if (at.x < 0 || at.y < 0 || at.x >= cols || at.y >= rows)
      throw MemoryError("an interior point outside the table");
  }
  if (p->interior_.empty())
    throw MemoryError("no interior point");
  p->outline_.resize(in.count(16, "the outline"));
  for (OutlinePoint& o : p->outline_)
  {
    o.position.x = in.get<float>("the outline");
    o.position.y = in.get<float>("the outline");
    o.normal.x = in.get<float>("the outline");
    o.normal.y = in.get<float>("the outline");
  }
  if (in.left() != 0)
    throw MemoryError(std::to_string(in.left()) + " bytes after the outline");
  return p;
}
}  // namespace amcr
