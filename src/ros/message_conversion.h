// Core results -> amcr messages. No ROS node needed: plain functions, used by
// the nodelet and testable on their own.
#pragma once

#include <cstdint>
#include <string>

#include <std_msgs/Header.h>

#include "amcr/extraction/recognition_result.h"
#include "amcr/memory/prototype_memory.h"
#include <amcr/PrototypeTable.h>
#include <amcr/Recognition.h>
#include <amcr/Recognitions.h>

namespace amcr_ros
{
/// One object; pose_valid false and the identity pose (the pose is filled elsewhere).
amcr::Recognition toMsg(const amcr::RecognizedObject& object);

/// A whole result, with the input image's header: the objects in the core's order (best score first),
/// processing_ms the core's time_ms.
amcr::Recognitions toMsg(const amcr::RecognitionResult& result, const std_msgs::Header& header);

/// The name of a Recognition.state constant ("tentative", ..., amcr::toString's), "unknown" for another value.
std::string stateName(std::uint8_t state);

/// The label table of a memory (empty when `memory` is null), as version `version`.
amcr::PrototypeTable toMsg(const amcr::PrototypeMemory* memory, const std::string& directory, std::uint32_t version,
                           const ros::Time& stamp);
}  // namespace amcr_ros
