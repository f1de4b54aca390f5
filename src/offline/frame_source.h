// Where amcr_offline's frames come from: a video file, a directory of images
// (in file-name order), or one image repeated.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>

#include <opencv2/core.hpp>

namespace amcr
{
namespace offline
{
/// The input cannot be opened at all (missing, a symbolic link loop, not
/// readable, an empty directory, neither an image nor a video).
class SourceError : public std::runtime_error
{
public:
  explicit SourceError(const std::string& what) : std::runtime_error(what) {}
};

struct Frame
{
  long index = 0;       ///< 0-based position in the input
  std::string name;     ///< for messages: the file, or "frame N of VIDEO"
  cv::Mat image;        ///< as read (any depth and channel count); empty when unreadable
  std::string problem;  ///< why `image` is empty
};

class FrameSource
{
public:
  virtual ~FrameSource() = default;

  /// Opens `path`: a directory (its image files sorted by name, at most
  /// `max_frames` of them when `cap` is set), a file that reads as an image
  /// (repeated `max_frames` times), or else a video (at most `max_frames`
  /// frames when `cap` is set; opened with OpenCV's file backends only).
  /// Throws SourceError naming the path and the reason when it is missing, a
  /// symbolic link loop, unreadable (permission denied, ...), or a directory
  /// without image files.
  static std::unique_ptr<FrameSource> open(const std::string& path, long max_frames, bool cap);

  /// The next frame; false at the end. A directory file that cannot be read
  /// gives a frame with an empty image and `problem` set; a video ends at
  /// its first unreadable frame (see incomplete()).
  virtual bool next(Frame& frame) = 0;

  /// After next() returned false: why the input ended before its end, with
  /// the figures (a video that gave fewer frames than its container holds,
  /// or whose read failed); empty when it was read whole.
  virtual std::string incomplete() const { return ""; }

  /// Frames per second of a video, 0 when unknown.
  virtual double fps() const { return 0.0; }

  /// "video", "directory" or "image".
  virtual std::string kind() const = 0;
};

/// True when the file name has an image extension that OpenCV reads
/// (case-insensitive): .png, .jpg, .bmp, .tif, .pgm, ...
bool hasImageExtension(const std::string& path);
}  // namespace offline
}  // namespace amcr
