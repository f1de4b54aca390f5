// The objects' life cycle (track_registry.h), on objects made in
// code: tentative -> confirmed -> held -> lost, coasting between, the image
// border, the bound on objects, and the message's string names.
#include <vector>

#include <gtest/gtest.h>

#include "amcr/extraction/track_registry.h"
#include "scene_drawing.h"

namespace
{
using amcr::ObjectState;

const cv::Size kImage(640, 480);

amcr::RecognizedObject starAt(double x, double y, double score = 0.9)
{
  const amcr::Affine pose = amcr_test::makeAffine(amcr_test::prototypeCentre(), {x, y}, 0.0, 0.5, 0.5, 0.0);
  amcr::RecognizedObject o;
  o.prototype_id = 0;
  o.score = score;
  o.prototype_to_image = pose;
  o.outline = amcr_test::transformPoints(pose, amcr_test::shapePolygon(amcr_test::ShapeId::kStar));
  return o;
}

amcr::LifecycleRule rule()
{
  amcr::LifecycleRule r;
  r.confirm_frames = 3;
  r.lost_frames = 2;
  r.recall_frames = 3;
  r.max_objects = 3;
  r.hold_score = 0.75;
  return r;
}

/// One frame: the tracker follows every track (a static scene), then the
/// objects are assigned; returns the tracks that ended.
std::vector<amcr::RecognizedObject> frame(amcr::TrackRegistry& registry, std::vector<amcr::RecognizedObject>& objects)
{
  registry.followAll();
  std::vector<amcr::RecognizedObject> ended;
  registry.assign(objects, kImage, ended);
  return ended;
}
}  // namespace

// Reported in confirm_frames frames: confirmed, held while followed and its
// score reaches hold_score; unreported, it coasts with its id and is lost
// after lost_frames frames, listed once.
TEST(ObjectLifecycle, TentativeConfirmedHeldLost)
{
  amcr::TrackRegistry registry(rule());
  std::vector<ObjectState> states;
  int id = 0;
  for (int k = 0; k < 4; ++k)
  {
    std::vector<amcr::RecognizedObject> objects = {starAt(200 + k, 200)};
    EXPECT_TRUE(frame(registry, objects).empty());
    states.push_back(objects[0].state);
    id = objects[0].track_id;
  }
  EXPECT_EQ(states, (std::vector<ObjectState>{ObjectState::kTentative, ObjectState::kTentative,
                                              ObjectState::kHeld, ObjectState::kHeld}));
  EXPECT_EQ(id, 1);

  // Kept by the hysteresis only (below hold_score): confirmed, not held.
  std::vector<amcr::RecognizedObject> weak = {starAt(204, 200, 0.6)};
  frame(registry, weak);
  EXPECT_EQ(weak[0].state, ObjectState::kConfirmed);
  EXPECT_EQ(weak[0].track_id, id);

  // Not reported for one frame: it coasts, and keeps its id when found.
  std::vector<amcr::RecognizedObject> none;
  EXPECT_TRUE(frame(registry, none).empty());
  ASSERT_EQ(registry.tracks().size(), 1u);
  EXPECT_EQ(registry.tracks()[0].misses, 1);
  std::vector<amcr::RecognizedObject> again = {starAt(205, 200)};
  frame(registry, again);
  EXPECT_EQ(again[0].track_id, id);
  EXPECT_EQ(again[0].state, ObjectState::kHeld);

  // Not reported for lost_frames frames: lost, once, as last reported.
  EXPECT_TRUE(frame(registry, none).empty());
  const std::vector<amcr::RecognizedObject> ended = frame(registry, none);
  ASSERT_EQ(ended.size(), 1u);
  EXPECT_EQ(ended[0].track_id, id);
  EXPECT_EQ(ended[0].state, ObjectState::kLost);
  EXPECT_NEAR(ended[0].prototype_to_image(0, 2), again[0].prototype_to_image(0, 2), 1e-9);
  EXPECT_TRUE(registry.tracks().empty());
  EXPECT_TRUE(frame(registry, none).empty());

  // Found again where it was lost, within recall_frames: the same track,
  // under its id and confirmed at once (it was; the tracker has not
  // followed it into this frame, so it is not held yet).
  std::vector<amcr::RecognizedObject> later = {starAt(205, 200)};
  frame(registry, later);
  EXPECT_EQ(later[0].track_id, id);
  EXPECT_EQ(later[0].state, ObjectState::kConfirmed);
  EXPECT_TRUE(registry.ended().empty());
}

// An ended track is given back only to an object of its label, where it was
// last, within recall_frames; anything else starts a new track.
TEST(ObjectLifecycle, AnEndedTrackIsRecalledOnlyByItsLabelAtItsPlaceInTime)
{
  const auto endedTrack = [](amcr::TrackRegistry& registry) {
    std::vector<amcr::RecognizedObject> seen = {starAt(200, 200)};
    frame(registry, seen);
    std::vector<amcr::RecognizedObject> none;
    for (int k = 0; k < rule().lost_frames; ++k)
      frame(registry, none);
    EXPECT_EQ(registry.ended().size(), 1u);
    return seen[0].track_id;
  };
  {
    amcr::TrackRegistry registry(rule());
    const int id = endedTrack(registry);
    std::vector<amcr::RecognizedObject> other_label = {starAt(200, 200)};
    other_label[0].label = "another";
    frame(registry, other_label);
    EXPECT_NE(other_label[0].track_id, id) << "another label at the place";
    std::vector<amcr::RecognizedObject> elsewhere = {starAt(400, 300)};
    frame(registry, elsewhere);
    EXPECT_NE(elsewhere[0].track_id, id) << "the label elsewhere";
    std::vector<amcr::RecognizedObject> back = {starAt(202, 201)};
    frame(registry, back);
    EXPECT_EQ(back[0].track_id, id) << "the label at the place, 3 frames after the end";
  }
  {
    amcr::TrackRegistry registry(rule());
    const int id = endedTrack(registry);
    std::vector<amcr::RecognizedObject> none;
    for (int k = 0; k < rule().recall_frames; ++k)
      frame(registry, none);
    std::vector<amcr::RecognizedObject> late = {starAt(200, 200)};
    frame(registry, late);  // recall_frames + 1 frames after the end
    EXPECT_TRUE(registry.ended().empty()) << "forgotten after recall_frames";
    EXPECT_EQ(late[0].track_id, id + 1);
    EXPECT_EQ(late[0].state, ObjectState::kTentative);
  }
  {
    amcr::LifecycleRule never = rule();
    never.recall_frames = 0;
    amcr::TrackRegistry registry(never);
    std::vector<amcr::RecognizedObject> seen = {starAt(200, 200)}, none;
    frame(registry, seen);
    for (int k = 0; k < never.lost_frames; ++k)
      frame(registry, none);
    std::vector<amcr::RecognizedObject> back = {starAt(200, 200)};
    frame(registry, back);
    EXPECT_EQ(back[0].track_id, seen[0].track_id + 1) << "recall_frames 0: never recalled";
  }
}

// A confirmed object the tracker did not follow into the frame is
// confirmed, not held.
TEST(ObjectLifecycle, HeldOnlyWhenFollowed)
{
  amcr::TrackRegistry registry(rule());
  std::vector<amcr::RecognizedObject> ended;
  for (int k = 0; k < 3; ++k)
  {
    std::vector<amcr::RecognizedObject> objects = {starAt(200, 200)};
    registry.assign(objects, kImage, ended);  // nothing follows it
    EXPECT_EQ(objects[0].state, k < 2 ? ObjectState::kTentative : ObjectState::kConfirmed) << "frame " << k;
  }
  registry.move(0, amcr::Affine(1, 0, 3, 0, 1, 0));  // the flow moved it
  std::vector<amcr::RecognizedObject> moved = {starAt(203, 200)};
  registry.assign(moved, kImage, ended);
  EXPECT_EQ(moved[0].state, ObjectState::kHeld);
  EXPECT_TRUE(ended.empty());
}

// A coasting track whose centre the flow moved out of the image is lost at
// once; a track moved by the flow carries its whole pose along.
TEST(ObjectLifecycle, LeavingTheImageEndsTheTrack)
{
  amcr::TrackRegistry registry(rule());
  std::vector<amcr::RecognizedObject> objects = {starAt(600, 200), starAt(200, 200)};
  frame(registry, objects);
  registry.move(0, amcr::Affine(1, 0, 60, 0, 1, 0));
  EXPECT_NEAR(registry.tracks()[0].object.prototype_to_image(0, 2), objects[0].prototype_to_image(0, 2) + 60, 1e-9);
  EXPECT_NEAR(registry.tracks()[0].object.image_to_prototype(0, 2),
              objects[0].image_to_prototype(0, 2) - 60 * objects[0].image_to_prototype(0, 0), 1e-9);
  std::vector<amcr::RecognizedObject> only_left = {starAt(200, 200)};
  std::vector<amcr::RecognizedObject> ended;
  registry.assign(only_left, kImage, ended);
  ASSERT_EQ(ended.size(), 1u);
  EXPECT_EQ(ended[0].track_id, objects[0].track_id);
  EXPECT_EQ(only_left[0].track_id, objects[1].track_id);
}

// max_objects bounds the tracks, coasting ones included.
TEST(ObjectLifecycle, RoomForMaxObjects)
{
  amcr::TrackRegistry registry(rule());
  EXPECT_TRUE(registry.hasRoom());
  std::vector<amcr::RecognizedObject> objects = {starAt(100, 100), starAt(300, 100)};
  frame(registry, objects);
  EXPECT_TRUE(registry.hasRoom());
  EXPECT_FALSE(registry.hasRoom(1));
  std::vector<amcr::RecognizedObject> one = {starAt(100, 100), starAt(500, 300)};
  frame(registry, one);  // the second track coasts: three tracks
  EXPECT_EQ(registry.tracks().size(), 3u);
  EXPECT_FALSE(registry.hasRoom());
}

TEST(ObjectLifecycle, StateNames)
{
  EXPECT_EQ(amcr::toString(ObjectState::kTentative), "tentative");
  EXPECT_EQ(amcr::toString(ObjectState::kConfirmed), "confirmed");
  EXPECT_EQ(amcr::toString(ObjectState::kHeld), "held");
  EXPECT_EQ(amcr::toString(ObjectState::kLost), "lost");
}
