#include "frame_source.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <set>
#include <system_error>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "amcr/base/errors.h"
#include "amcr/io/image_file.h"

namespace amcr
{
namespace offline
{
namespace fs = std::filesystem;

namespace
{
/// amcr::readImageFile that reports failure as an empty image and the reason
/// in `problem` instead of an exception (a damaged JPEG or PNG is refused).
cv::Mat readImage(const std::string& path, std::string* problem = nullptr)
{
  try
  {
    return readImageFile(path, cv::IMREAD_UNCHANGED);
  }
  catch (const Error& e)
  {
    if (problem)
      *problem = e.what();
    return cv::Mat();
  }
}

/// Why `path` cannot be opened for reading ("Permission denied", ...); empty when it can.
std::string openProblem(const std::string& path)
{
  errno = 0;
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file)
  {
    std::fclose(file);
    return "";
  }
  return errno != 0 ? std::strerror(errno) : "cannot be opened";
}

/// What `error` (from std::filesystem on `path`) means for the user.
std::string accessProblem(const std::string& path, const std::error_code& error)
{
  if (error == std::errc::too_many_symbolic_link_levels)
    return "input '" + path + "' is a symbolic link loop (" + error.message() + ")";
  if (error == std::errc::permission_denied)
    return "cannot access input '" + path + "': permission denied";
  if (!error || error == std::errc::no_such_file_or_directory || error == std::errc::not_a_directory)
    return "input '" + path + "' does not exist";
  return "cannot access input '" + path + "': " + error.message();
}

class DirectorySource : public FrameSource
{
public:
  explicit DirectorySource(std::vector<std::string> files) : files_(std::move(files)) {}

  bool next(Frame& frame) override
  {
    if (position_ >= files_.size())
      return false;
    frame.index = static_cast<long>(position_);
    const std::string& file = files_[position_++];
    frame.name = file;
    frame.problem.clear();
    frame.image = readImage(file, &frame.problem);
    return true;
  }

  std::string kind() const override { return "directory"; }

private:
  std::vector<std::string> files_;
  std::size_t position_ = 0;
};

class RepeatedImageSource : public FrameSource
{
public:
  RepeatedImageSource(cv::Mat image, long count, std::string path)
    : image_(std::move(image)), count_(count), path_(std::move(path))
  {
  }

  bool next(Frame& frame) override
  {
    if (position_ >= count_)
      return false;
    frame.index = position_++;
    frame.name = path_;
    frame.image = image_;
    frame.problem.clear();
    return true;
  }

  std::string kind() const override { return "image"; }

private:
  cv::Mat image_;
  long count_;
  std::string path_;
  long position_ = 0;
};

class VideoSource : public FrameSource
{
public:
  /// `frame_count`: the container's count, 0 when unknown; `cap`: the most frames to read, 0 for all.
  VideoSource(std::unique_ptr<cv::VideoCapture> capture, long frame_count, long cap, std::string path)
    : capture_(std::move(capture)), frame_count_(frame_count), cap_(cap), path_(std::move(path))
  {
  }

  bool next(Frame& frame) override
  {
    if ((cap_ > 0 && position_ >= cap_) || !capture_)
      return false;
    cv::Mat image;
    std::string failure;
    try
    {
      if (!capture_->read(image) || image.empty())
        image.release();
    }
    catch (const cv::Exception& e)
    {
      image.release();
      failure = e.err;
    }
    if (image.empty())
    {
      capture_.reset();
      noteEnd(failure);
      return false;
    }
    frame.index = position_++;
    frame.name = "frame " + std::to_string(frame.index) + " of '" + path_ + "'";
    frame.image = image;
    frame.problem.clear();
    return true;
  }

  double fps() const override { return fps_; }
  void setFps(double fps) { fps_ = fps; }
  std::string kind() const override { return "video"; }
  std::string incomplete() const override { return incomplete_; }

private:
  /// The video ended at frame position_: early when the container holds more frames (that were asked
  /// for), or when the read failed with an error.
  void noteEnd(const std::string& failure)
  {
    const long expected = cap_ > 0 && frame_count_ > 0 ? std::min(cap_, frame_count_) : frame_count_;
    const std::string read = std::to_string(position_) + (position_ == 1 ? " frame" : " frames");
    if (expected > 0 && position_ < expected)
      incomplete_ = "video '" + path_ + "' ended after " + read + " of the " + std::to_string(frame_count_) +
                    " its container holds: frame " + std::to_string(position_) +
                    " cannot be read (truncated or corrupt?)" + (failure.empty() ? "" : ": " + failure);
    else if (!failure.empty())
      incomplete_ = "video '" + path_ + "': frame " + std::to_string(position_) + " cannot be read after " + read +
                    ": " + failure;
  }

  std::unique_ptr<cv::VideoCapture> capture_;
  long frame_count_;
  long cap_;
  std::string path_;
  long position_ = 0;
  double fps_ = 0.0;
  std::string incomplete_;
};

/// Opens a video file with OpenCV's file backends only: FFmpeg, then the built-in Motion JPEG reader.
/// (cv::CAP_ANY would also offer a file to camera backends: gphoto2 leaks and prints on a garbage file.)
std::unique_ptr<cv::VideoCapture> openVideoFile(const std::string& path)
{
  for (const int backend : {cv::CAP_FFMPEG, cv::CAP_OPENCV_MJPEG})
  {
    auto capture = std::make_unique<cv::VideoCapture>();
    try
    {
      if (capture->open(path, backend) && capture->isOpened())
        return capture;
    }
    catch (const cv::Exception&)
    {
    }
  }
  return nullptr;
}

/// The image files of a directory; an entry with an image extension that cannot be examined (a symbolic
/// link loop, a dangling link) is kept, so that it becomes a frame skipped with a warning.
std::vector<std::string> listImageFiles(const std::string& path)
{
  std::error_code error;
  std::vector<std::string> files;
  fs::directory_iterator it(path, error);
  if (error)
    throw SourceError("cannot list input directory '" + path + "': " + error.message());
  for (; it != fs::directory_iterator(); it.increment(error))
  {
    if (error)
      throw SourceError("cannot list input directory '" + path + "': " + error.message());
    std::error_code file_error;
    const bool regular = it->is_regular_file(file_error);
    if ((regular || file_error) && hasImageExtension(it->path().string()))
      files.push_back(it->path().string());
  }
  return files;
}
}  // namespace

bool hasImageExtension(const std::string& path)
{
  static const std::set<std::string> kExtensions = {".bmp", ".dib", ".jpeg", ".jpg", ".jpe", ".jp2", ".png",
                                                    ".webp", ".pbm", ".pgm", ".ppm", ".pxm", ".pnm", ".pfm",
                                                    ".sr",   ".ras", ".tiff", ".tif", ".exr", ".hdr", ".pic"};
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return kExtensions.count(ext) > 0;
}

std::unique_ptr<FrameSource> FrameSource::open(const std::string& path, long max_frames, bool cap)
{
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (error || !fs::exists(status))
    throw SourceError(accessProblem(path, error));

  if (fs::is_directory(status))
  {
    std::vector<std::string> files = listImageFiles(path);
    if (files.empty())
      throw SourceError("input directory '" + path + "' holds no image files");
    std::sort(files.begin(), files.end(), [](const std::string& a, const std::string& b) {
      return fs::path(a).filename().string() < fs::path(b).filename().string();
    });
    if (cap && static_cast<long>(files.size()) > max_frames)
      files.resize(static_cast<std::size_t>(max_frames));
    return std::make_unique<DirectorySource>(std::move(files));
  }

  if (!fs::is_regular_file(status))
    throw SourceError("input '" + path + "' is neither a file nor a directory");
  const std::string unreadable = openProblem(path);
  if (!unreadable.empty())
    throw SourceError("cannot read input '" + path + "': " + unreadable);

  std::string problem;
  cv::Mat image = readImage(path, &problem);
  if (!image.empty())
    return std::make_unique<RepeatedImageSource>(image, max_frames, path);
  if (hasImageExtension(path))
    throw SourceError(problem);

  std::unique_ptr<cv::VideoCapture> capture = openVideoFile(path);
  if (!capture)
    throw SourceError("cannot read input '" + path + "' as an image or a video");
  const double fps = capture->get(cv::CAP_PROP_FPS);
  const double count = capture->get(cv::CAP_PROP_FRAME_COUNT);
  const long frame_count = std::isfinite(count) && count >= 1.0 && count < 1e12 ? std::lround(count) : 0;
  auto source = std::make_unique<VideoSource>(std::move(capture), frame_count, cap ? max_frames : 0, path);
  source->setFps(std::isfinite(fps) && fps > 0.0 && fps < 1000.0 ? fps : 0.0);
  return source;
}
}  // namespace offline
}  // namespace amcr
