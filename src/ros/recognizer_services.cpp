// RecognizerRos's calls that rebuild (recognizer_ros.h): ~load_prototypes, ~teach, ~remove_prototype and
// the reconfiguration, each a request turned into a call of the session, its answer into the response.
#include <exception>
#include <vector>

#include "amcr/memory/region_shape.h"
#include "recognizer_ros.h"
#include "reconfigure.h"

namespace amcr_ros
{
namespace
{
/// The server's configuration over the parameters in effect, and what it changes.
amcr::RecognizerSession::ReconfigurationFrom fromServer(const amcr::AMCRConfig& config)
{
  return [config](const amcr::Params& in_effect) {
    amcr::Params changed = fromConfig(config, in_effect);  // refuses a value out of range, naming it
    return amcr::RecognizerSession::Reconfiguration{changed, describeChanges(in_effect, changed)};
  };
}
}  // namespace

amcr::LoadPrototypes::Response RecognizerRos::loadPrototypes(const std::string& directory)
{
  const amcr::RecognizerSession::Loaded loaded = session_->load(directory);
  amcr::LoadPrototypes::Response response;
  response.success = loaded.error.empty();
  response.message = loaded.error;
  response.num_prototypes = static_cast<int>(loaded.prototypes);
  if (!response.success)
  {
    ROS_ERROR("%s (the previous memory stays in use)", response.message.c_str());
    if (!session_->labelTable().memory)
      stats_.setPrototypes(0, response.message);
  }
  return response;
}

amcr::TeachPrototype::Response RecognizerRos::teach(const amcr::TeachPrototype::Request& request)
{
  std::vector<cv::Point2f> region;  // the polygon, or the rectangle when the polygon has no points
  for (const auto& p : request.region.points)
    region.emplace_back(p.x, p.y);
  if (region.empty())
    region = amcr::rectangleRegion(request.rectangle.x_offset, request.rectangle.y_offset, request.rectangle.width,
                                   request.rectangle.height);
  const amcr::RecognizerSession::Taught taught = session_->teach(request.label, region, request.save);
  amcr::TeachPrototype::Response response;
  response.success = taught.error.empty();
  response.message = taught.error;
  response.prototype_id = taught.prototype_id;
  response.saved_path = taught.saved_path;
  response.table_version = taught.table_version;
  if (!response.success)
    ROS_ERROR("~teach '%s' refused, nothing changed: %s", request.label.c_str(), response.message.c_str());
  return response;
}

amcr::RemovePrototype::Response RecognizerRos::removePrototype(const std::string& label)
{
  const amcr::RecognizerSession::Removed removed = session_->remove(label);
  amcr::RemovePrototype::Response response;
  response.success = removed.error.empty();
  response.message = removed.error;
  response.num_removed = removed.removed;
  response.table_version = removed.table_version;
  if (!response.success)
    ROS_ERROR("~remove_prototype '%s' refused, nothing changed: %s", label.c_str(), response.message.c_str());
  return response;
}

std::string RecognizerRos::reconfigure(amcr::AMCRConfig& config, std::uint32_t level)
{
  const std::string error = session_->reconfigure(fromServer(config), level & kReconfigureTables);
  if (!error.empty())
    ROS_ERROR("reconfiguration refused, the previous parameters stay: %s", error.c_str());
  try
  {
    config = toConfig(params());  // what is in effect is what the server keeps and the clients see
  }
  catch (const std::exception& e)
  {
    ROS_ERROR("cannot show the parameters in effect: %s", e.what());
  }
  return error;
}

RecognizerRos::PreparedSwap RecognizerRos::prepareReconfigure(const amcr::AMCRConfig& config, std::uint32_t level)
{
  return session_->prepareReconfigure(fromServer(config), level & kReconfigureTables);
}
}  // namespace amcr_ros
