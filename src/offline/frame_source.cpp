#include "frame_source.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <set>
#include <system_error>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "amcr/errors.h"
#include "amcr/image_file.h"

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
  VideoSource(std::unique_ptr<cv::VideoCapture> capture, long cap, std::string path)
    : capture_(std::move(capture)), cap_(cap), path_(std::move(path))
  {
  }

  bool next(Frame& frame) override
  {
    if ((cap_ > 0 && position_ >= cap_) || !capture_)
      return false;
    cv::Mat image;
    bool ok = false;
    try
    {
      ok = capture_->read(image);
    }
    catch (const cv::Exception&)
    {
      ok = false;
    }
    if (!ok || image.empty())
    {
      capture_.reset();
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

private:
  std::unique_ptr<cv::VideoCapture> capture_;
  long cap_;
  std::string path_;
  long position_ = 0;
  double fps_ = 0.0;
};
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
    throw SourceError("input '" + path + "' does not exist");

  if (fs::is_directory(status))
  {
    std::vector<std::string> files;
    fs::directory_iterator it(path, error);
    if (error)
      throw SourceError("cannot list input directory '" + path + "': " + error.message());
    for (; it != fs::directory_iterator(); it.increment(error))
    {
      if (error)
        throw SourceError("cannot list input directory '" + path + "': " + error.message());
      std::error_code file_error;
      if (it->is_regular_file(file_error) && hasImageExtension(it->path().string()))
        files.push_back(it->path().string());
    }
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

  std::string problem;
  cv::Mat image = readImage(path, &problem);
  if (!image.empty())
    return std::make_unique<RepeatedImageSource>(image, max_frames, path);
  if (hasImageExtension(path))
    throw SourceError(problem);

  auto capture = std::make_unique<cv::VideoCapture>();
  bool opened = false;
  try
  {
    opened = capture->open(path, cv::CAP_ANY) && capture->isOpened();
  }
  catch (const cv::Exception&)
  {
    opened = false;
  }
  if (!opened)
    throw SourceError("cannot read input '" + path + "' as an image or a video");
  const double fps = capture->get(cv::CAP_PROP_FPS);
  auto source = std::make_unique<VideoSource>(std::move(capture), cap ? max_frames : 0, path);
  source->setFps(std::isfinite(fps) && fps > 0.0 && fps < 1000.0 ? fps : 0.0);
  return source;
}
}  // namespace offline
}  // namespace amcr
