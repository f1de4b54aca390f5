// RecognizerSession (recognizer_session.h): the images, the reset, the state
// copied for a rebuild and the swap under the frame lock. The rebuilds are in
// recognizer_session_rebuilds.cpp (load, reconfigure) and
// recognizer_session_edits.cpp (teach, remove).
#include "amcr/recognizer_session.h"

#include <exception>
#include <utility>

#include "amcr/overlay.h"

namespace amcr
{
RecognizerSession::RecognizerSession(Params params, SessionHooks hooks)
  : hooks_(std::move(hooks)), params_(std::make_shared<const Params>(std::move(params)))
{
}

RecognizerSession::~RecognizerSession() = default;

RecognizedFrame RecognizerSession::recognize(const FrameInput& input)
{
  RecognizedFrame frame;
  try
  {
    std::lock_guard<std::mutex> lock(frame_mutex_);
    last_image_ = {input.image, input.pixels_owner};  // what teach() cuts from, also before any prototype is there
    if (!recognizer_)
      return frame;
    if (input.restart_unless_fresh && !fresh_)
    {
      restart();
      frame.input_restart = true;
    }
    followSize(input.image.size());
    frame.result = recognizer_->step(input.image);
    frame.recognized = true;
    frame.memory = memory_;
    frame.table_version = table_version_;
    frame.params = params_;
    frame.restarted = fresh_;
    fresh_ = false;
    if (input.draw_overlay)
    {
      try
      {
        frame.overlay = drawOverlay(input.image, *recognizer_, frame.result);
      }
      catch (const std::exception& e)  // the recognitions stand
      {
        frame.overlay_error = e.what();
      }
    }
  }
  catch (const std::exception& e)
  {
    frame.recognized = false;
    frame.error = e.what();
  }
  catch (...)
  {
    frame.recognized = false;
    frame.error = "unknown error";
  }
  return frame;
}

void RecognizerSession::followSize(const cv::Size& size)
{
  if (last_size_ == size)
    return;
  if (!last_size_.empty())  // the recognizer re-seeds its V-particles itself
    inform("image size changed from " + std::to_string(last_size_.width) + " x " + std::to_string(last_size_.height) +
           " to " + std::to_string(size.width) + " x " + std::to_string(size.height) + ": V-particles re-seeded");
  last_size_ = size;
}

std::string RecognizerSession::reset()
{
  try
  {
    std::lock_guard<std::mutex> lock(frame_mutex_);
    restart();
    return recognizer_ ? "filter reset: it starts again from the next image"
                       : "no prototypes loaded: the filter starts once they are";
  }
  catch (const std::exception& e)
  {
    return std::string("reset failed: ") + e.what();
  }
}

std::unique_ptr<Recognizer> RecognizerSession::restart(std::unique_ptr<Recognizer> replacement)
{
  if (replacement)
    std::swap(recognizer_, replacement);
  else if (recognizer_)
    recognizer_->reset();
  fresh_ = true;
  if (hooks_.restarted)
    hooks_.restarted();
  return replacement;
}

Params RecognizerSession::params() const
{
  std::lock_guard<std::mutex> lock(frame_mutex_);
  return *params_;
}

LabelTable RecognizerSession::labelTable() const
{
  std::lock_guard<std::mutex> lock(frame_mutex_);
  return {memory_, edits_.directory(), table_version_};
}

std::uint32_t RecognizerSession::tableVersion() const
{
  std::lock_guard<std::mutex> lock(frame_mutex_);
  return table_version_;
}

RecognizerSession::EditState RecognizerSession::editState() const
{
  std::lock_guard<std::mutex> lock(frame_mutex_);
  return {generation_, *params_, memory_, edits_, last_image_};
}

std::string RecognizerSession::commit(PreparedSwap& prepared)
{
  if (!prepared.error.empty())
    return prepared.error;
  // Destroyed after the lock is released, with whatever the swap replaced and left in its captures.
  const std::function<std::string()> swap = std::move(prepared.swap);
  prepared.swap = nullptr;
  if (!swap)
    return "";
  try
  {
    std::lock_guard<std::mutex> lock(frame_mutex_);
    if (generation_ != prepared.generation)
      return kMemoryChanged;
    const std::string error = swap();
    if (error.empty())
      ++generation_;
    return error;
  }
  catch (const std::exception& e)
  {
    return e.what();
  }
}

void RecognizerSession::warn(const std::string& text) const
{
  if (hooks_.warning)
    hooks_.warning(text);
}

void RecognizerSession::inform(const std::string& text) const
{
  if (hooks_.info)
    hooks_.info(text);
}

void RecognizerSession::tableChanged()
{
  ++table_version_;
  if (hooks_.table_changed)
    hooks_.table_changed({memory_, edits_.directory(), table_version_});
}

void RecognizerSession::indexWarnings()
{
  if (recognizer_)
    for (const std::string& w : recognizer_->filter().indexWarnings())
      warn("proposal index: " + w);
}
}  // namespace amcr
