// The offline runner's frame source: bytes -> a file with an image or video extension ->
// amcr::offline::FrameSource::open, then every frame (at most 4). Byte 0 picks the extension
// from kExtensions, the rest is the file. SourceError is an accepted answer; any other exception,
// a frame out of order or a sanitizer report is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "fuzz_input.h"
#include "frame_source.h"

namespace
{
const char* const kExtensions[] = {".png", ".jpg", ".bmp", ".pgm", ".ppm", ".tif", ".webp", ".pfm", ".hdr",
                                   ".avi", ".mp4", ".mkv", ".mov", ".y4m", ".mjpeg", ".gif", ".bin", ""};
constexpr std::size_t kExtensionCount = sizeof(kExtensions) / sizeof(kExtensions[0]);
constexpr long kMaxFrames = 4;
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
  amcr_fuzz::setUpOpenCv();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  static const amcr_fuzz::ScratchDirectory scratch;
  if (size == 0)
    return 0;
  const std::string path = scratch.write(std::string("input") + kExtensions[data[0] % kExtensionCount], data + 1,
                                         size - 1);
  try
  {
    auto source = amcr::offline::FrameSource::open(path, kMaxFrames, true);
    amcr::offline::Frame frame;
    long count = 0;
    while (source->next(frame))
    {
      if (frame.index != count || ++count > kMaxFrames || (frame.image.empty() && frame.problem.empty()))
        std::abort();  // out of order, past the cap, or an empty frame without a reason
    }
  }
  catch (const amcr::offline::SourceError&)
  {
  }
  return 0;
}
