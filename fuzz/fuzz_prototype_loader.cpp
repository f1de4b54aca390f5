// Prototype loading: bytes -> cv::imdecode -> PrototypeMemory::add (amcr::Prototype: the
// silhouette mask, the outline and the radial-scan table), as PrototypeMemory::loadDirectory does
// for each file, with the smallest table (prototype_size 32: the same code, 16 times fewer table
// pixels than the default 128, so that the fuzzer runs many inputs a second). amcr::Error is an
// accepted answer; any other exception or a sanitizer report is a finding.
#include <cstddef>
#include <cstdint>

#include <opencv2/imgcodecs.hpp>

#include "amcr/base/errors.h"
#include "amcr/base/params.h"
#include "amcr/memory/prototype_memory.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
  amcr_fuzz::setUpOpenCv();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  static const amcr::Params params = [] {
    amcr::Params p;
    p.prototype_size = 32;
    return p;
  }();
  cv::Mat image;
  try
  {
    image = cv::imdecode(cv::Mat(1, static_cast<int>(size), CV_8U, const_cast<std::uint8_t*>(data)),
                         cv::IMREAD_UNCHANGED);
  }
  catch (const cv::Exception&)  // a decoder's own refusal, as loadDirectory treats it
  {
    return 0;
  }
  if (image.empty())
    return 0;
  amcr::PrototypeMemory memory;
  try
  {
    memory.add("fuzzed", image, params);
  }
  catch (const amcr::Error&)
  {
    return 0;
  }
  // Read back what the filter reads: the table at every interior pixel, the outline's points.
  const amcr::Prototype& prototype = memory[0];
  unsigned sum = 0;
  for (const cv::Point& p : prototype.interior())
    sum += prototype.rawDistances(p.x, p.y)[0];
  for (const amcr::OutlinePoint& p : prototype.outline())
    sum += static_cast<unsigned>(p.position.x >= 0.f);
  return sum == 0xFFFFFFFFu ? 1 : 0;  // keeps the reads
}
