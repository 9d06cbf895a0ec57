// The viewer's scripts (tools/view_script.h): drags and held keys expand into their parts at the documented
// times, UI actions carry their values, and a bad event is refused with the file, its index and what was
// expected.
#include <string>

#include <gtest/gtest.h>

#include "core/error.h"
#include "tools/view_script.h"

namespace ropecast::tools {
namespace {

TEST(ViewScript, ADragIsAPressStepMovesAndARelease) {
  const ViewScript s = parseViewScript(
      R"([{"event": "drag", "at": 1, "from": [10, 20], "to": [50, 40], "steps": 4, "seconds": 2,
           "button": "middle", "shift": true}])",
      "t.json");
  ASSERT_EQ(s.events.size(), 6u);
  EXPECT_EQ(s.events[0].kind, ViewEventKind::MouseDown);
  EXPECT_EQ(s.events[0].pos, glm::dvec2(10, 20));
  EXPECT_EQ(s.events[0].button, MouseButton::Middle);
  EXPECT_TRUE(s.events[0].shift);
  for (int i = 1; i <= 4; ++i) {
    EXPECT_EQ(s.events[i].kind, ViewEventKind::MouseMove);
    EXPECT_DOUBLE_EQ(s.events[i].atSeconds, 1.0 + 0.5 * i);
    EXPECT_EQ(s.events[i].pos, glm::dvec2(10 + 10 * i, 20 + 5 * i));
  }
  EXPECT_EQ(s.events[5].kind, ViewEventKind::MouseUp);
  EXPECT_EQ(s.events[5].pos, glm::dvec2(50, 40));
  EXPECT_DOUBLE_EQ(s.events[5].atSeconds, 3.0);
}

TEST(ViewScript, AHeldKeyIsReleasedSecondsLaterAndLaterEventsFollowIt) {
  const ViewScript s = parseViewScript(
      R"({"events": [{"event": "key", "key": "W", "seconds": 0.5}, {"event": "quit"}]})", "t");
  ASSERT_EQ(s.events.size(), 3u);
  EXPECT_EQ(s.events[0].kind, ViewEventKind::KeyDown);
  EXPECT_EQ(s.events[0].key, 'w');
  EXPECT_EQ(s.events[1].kind, ViewEventKind::KeyUp);
  EXPECT_DOUBLE_EQ(s.events[1].atSeconds, 0.5);
  EXPECT_EQ(s.events[2].kind, ViewEventKind::Quit);
  EXPECT_DOUBLE_EQ(s.events[2].atSeconds, 0.5);
}

TEST(ViewScript, UiActionsCarryTheirValues) {
  const ViewScript s = parseViewScript(
      R"([{"event": "set_iso", "value": 0.25}, {"event": "set_mode", "mode": "dvr"},
          {"event": "load_tf", "tf": "ct-bone"}, {"event": "screenshot", "file": "a.png", "panels": true},
          {"event": "save_camera", "file": "c.json"}, {"event": "wheel", "clicks": -2},
          {"event": "reset_camera"}, {"event": "wait_converged"}, {"event": "set_crop", "crop": "2:9, :,4:"},
          {"event": "set_clip_plane", "plane": [1, 2, 3, 0, 0, -1]}, {"event": "set_clip_plane", "plane": []},
          {"event": "set_mode", "mode": "mip"}, {"event": "set_mode", "mode": "minip"},
          {"event": "set_tf_range", "range": [-160, 240]}, {"event": "set_caps", "caps": false},
          {"event": "set_caps", "caps": true}, {"event": "set_view", "view": "superior"},
          {"event": "probe", "pos": [120, 80.5]}, {"event": "center_at", "pos": [3, 4]},
          {"event": "measure", "from": [1, 2], "to": [30, 40]}, {"event": "set_mode", "mode": "aip"},
          {"event": "set_time_point", "time_point": 3}, {"event": "play", "playing": true},
          {"event": "play", "playing": false, "seconds_each": 0.25},
          {"event": "set_lighting", "iso_color": [1, 0.5, 0], "shading": false, "material": [0.1, 0.8, 0, 4]},
          {"event": "set_lighting", "shading": true}, {"event": "set_channel", "channel": 2},
          {"event": "set_mode", "mode": "slice"}, {"event": "wheel", "clicks": 3, "shift": true},
          {"event": "set_clip_plane", "plane": [1, 2, 3, 0, 0, 1], "slab": 4.5}])",
      "t");
  ASSERT_EQ(s.events.size(), 30u);
  EXPECT_EQ(s.events[0].value, 0.25);
  EXPECT_EQ(s.events[1].mode, RenderMode::Dvr);
  EXPECT_EQ(s.events[2].tf, "ct-bone");
  EXPECT_EQ(s.events[3].file, "a.png");
  EXPECT_TRUE(s.events[3].panels);
  EXPECT_EQ(s.events[4].kind, ViewEventKind::SaveCamera);
  EXPECT_EQ(s.events[5].clicks, -2.0);
  EXPECT_FALSE(s.events[5].shift);
  EXPECT_EQ(s.events[6].kind, ViewEventKind::ResetCamera);
  EXPECT_EQ(s.events[7].kind, ViewEventKind::WaitConverged);
  EXPECT_EQ(s.events[8].kind, ViewEventKind::SetCrop);
  EXPECT_EQ(s.events[8].crop, (std::vector<std::string>{"2:9", ":", "4:"}));
  EXPECT_EQ(s.events[9].kind, ViewEventKind::SetClipPlane);
  EXPECT_EQ(s.events[9].plane, (std::vector<double>{1, 2, 3, 0, 0, -1}));
  EXPECT_TRUE(s.events[10].plane.empty());
  EXPECT_EQ(s.events[11].mode, RenderMode::Mip);
  EXPECT_EQ(s.events[12].mode, RenderMode::MinIp);
  EXPECT_EQ(s.events[13].kind, ViewEventKind::SetTfRange);
  EXPECT_EQ(s.events[13].range, glm::dvec2(-160, 240));
  EXPECT_EQ(s.events[14].kind, ViewEventKind::SetCaps);
  EXPECT_FALSE(s.events[14].caps);
  EXPECT_TRUE(s.events[15].caps);
  EXPECT_EQ(s.events[16].kind, ViewEventKind::SetView);
  EXPECT_EQ(s.events[16].view, AnatomicalView::Superior);
  EXPECT_EQ(s.events[17].kind, ViewEventKind::Probe);
  EXPECT_EQ(s.events[17].pos, glm::dvec2(120, 80.5));
  EXPECT_EQ(s.events[18].kind, ViewEventKind::CenterAt);
  EXPECT_EQ(s.events[18].pos, glm::dvec2(3, 4));
  EXPECT_EQ(s.events[19].kind, ViewEventKind::Measure);
  EXPECT_EQ(s.events[19].pos, glm::dvec2(1, 2));
  EXPECT_EQ(s.events[19].to, glm::dvec2(30, 40));
  EXPECT_EQ(s.events[20].mode, RenderMode::Aip);
  EXPECT_EQ(s.events[21].kind, ViewEventKind::SetTimePoint);
  EXPECT_EQ(s.events[21].timePoint, 3u);
  EXPECT_EQ(s.events[22].kind, ViewEventKind::Play);
  EXPECT_TRUE(s.events[22].playing);
  EXPECT_EQ(s.events[22].secondsEach, -1.0);
  EXPECT_FALSE(s.events[23].playing);
  EXPECT_EQ(s.events[23].secondsEach, 0.25);
  EXPECT_EQ(s.events[24].kind, ViewEventKind::SetLighting);
  EXPECT_EQ(s.events[24].isoColor, glm::dvec3(1, 0.5, 0));
  EXPECT_EQ(s.events[24].shading, false);
  EXPECT_EQ(s.events[24].material, (std::vector<double>{0.1, 0.8, 0, 4}));
  EXPECT_FALSE(s.events[25].isoColor);
  EXPECT_EQ(s.events[25].shading, true);
  EXPECT_TRUE(s.events[25].material.empty());
  EXPECT_EQ(s.events[26].kind, ViewEventKind::SetChannel);
  EXPECT_EQ(s.events[26].channel, 2u);
  EXPECT_EQ(s.events[27].mode, RenderMode::Slice);
  EXPECT_EQ(s.events[28].kind, ViewEventKind::Wheel);
  EXPECT_EQ(s.events[28].clicks, 3.0);
  EXPECT_TRUE(s.events[28].shift);
  EXPECT_EQ(s.events[29].slab, 4.5);
  EXPECT_EQ(s.events[9].slab, 0.0);  // none unless given
}

void expectRefused(const std::string& text, const std::string& expected) {
  try {
    parseViewScript(text, "s.json");
    FAIL() << "accepted " << text;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
  }
}

TEST(ViewScript, BadEventsAreRefusedNamingTheFileAndTheEvent) {
  expectRefused("[1,", "s.json: not JSON");
  expectRefused(R"([{"event": "quit", "secs": 1}])",
                "s.json: event 0 (quit): unknown key \"secs\"; this event takes");
  expectRefused(R"([{"event": "key", "key": "w", "second": 1}])", "event 0 (key): unknown key \"second\"");
  expectRefused(R"({"events": [], "speed": 2})", "s.json: unknown key \"speed\"");
  expectRefused(R"([{"event": "set_iso", "value": 1e999}])", "s.json: not JSON");
  expectRefused(R"({"cameras": []})", "s.json: expected an array of events");
  expectRefused(R"([{"event": "spin"}])", "s.json: event 0 (spin): unknown event");
  expectRefused(R"([{"event": "spin"}])", "set_time_point, set_channel, play, set_lighting, load_tf");
  expectRefused(R"([{"event": "quit"}, {"event": "set_iso"}])", "event 1 (set_iso): \"value\" is required");
  expectRefused(R"([{"event": "drag", "from": [0, 0], "to": [1]}])", "\"to\" must be [x, y]");
  expectRefused(R"([{"event": "set_mode", "mode": "average"}])",
                "\"mode\" must be iso, dvr, mip, minip, aip or slice");
  expectRefused(R"([{"event": "key", "key": "x"}])", "\"key\" must be one of w a s d q e r");
  expectRefused(R"([{"event": "quit", "at": -1}])", "\"at\" must not be negative");
  expectRefused(R"([{"event": "set_crop", "crop": "0:4,:"}])",
                "event 0 (set_crop): \"crop\" must be three voxel ranges X0:X1,Y0:Y1,Z0:Z1");
  expectRefused(R"([{"event": "set_crop", "crop": "0:4,:,:,:"}])", "\"crop\" must be three voxel ranges");
  expectRefused(R"([{"event": "set_crop", "crop": "5:4,:,:"}])", "got \"5:4,:,:\"");
  expectRefused(R"([{"event": "set_clip_plane", "plane": [1, 2, 3, 0, 1]}])",
                "event 0 (set_clip_plane): \"plane\" must be [x, y, z, nx, ny, nz]");
  expectRefused(R"([{"event": "set_clip_plane", "plane": "0,0,0,0,0,1"}])", "\"plane\" must be");
  for (const char* range : {"[5, 5]", "[6, 5]", "[1]", "\"1,2\"", "[0, null]"})
    expectRefused(std::string(R"([{"event": "set_tf_range", "range": )") + range + "}]",
                  "event 0 (set_tf_range): \"range\" must be [lo, hi] in data units, lo < hi");
  expectRefused(R"([{"event": "set_clip_plane"}])", "\"plane\" is required");
  expectRefused(R"([{"event": "set_clip_plane", "plane": [1, 2, 3, 0, 0, 1], "slab": -1}])",
                "\"slab\" must be a thickness from 0 (none) to 1e15");
  expectRefused(R"([{"event": "set_clip_plane", "plane": [], "slab": 2}])", "\"slab\" is about a plane");
  expectRefused(R"([{"event": "set_caps"}])", "event 0 (set_caps): \"caps\" is required");
  expectRefused(
      R"([{"event": "set_view", "view": "front"}])",
      "event 0 (set_view): \"view\" must be anterior, posterior, left, right, superior or inferior, got "
      "\"front\"");
  expectRefused(R"([{"event": "set_view"}])", "event 0 (set_view): \"view\" is required");
  expectRefused(R"([{"event": "probe"}])", "event 0 (probe): \"pos\" is required");
  expectRefused(R"([{"event": "center_at"}])", "event 0 (center_at): \"pos\" is required");
  expectRefused(R"([{"event": "measure", "from": [1, 2]}])", "event 0 (measure): \"to\" is required");
  expectRefused(R"([{"event": "probe", "pos": [1, 2], "file": "p.txt"}])",
                "event 0 (probe): unknown key \"file\"");
  expectRefused(R"([{"event": "set_caps", "caps": "off"}])", "\"caps\" must be true or false");
  expectRefused(R"([{"event": "set_time_point"}])", "event 0 (set_time_point): \"time_point\" is required");
  for (const char* t : {"-1", "1.5", "1e10", "\"2\""})
    expectRefused(std::string(R"([{"event": "set_time_point", "time_point": )") + t + "}]",
                  "event 0 (set_time_point): \"time_point\" must be");
  expectRefused(
      R"([{"event": "set_channel", "channel": 0.5}])",
      "event 0 (set_channel): \"channel\" must be a whole number from 0, counted as --channel counts them");
  expectRefused(R"([{"event": "play"}])", "event 0 (play): \"playing\" is required");
  expectRefused(R"([{"event": "set_lighting"}])",
                "event 0 (set_lighting): give \"iso_color\", \"shading\" or \"material\"");
  expectRefused(R"([{"event": "set_lighting", "iso_color": [1, 2, 0]}])",
                "\"iso_color\" must be [r, g, b], each in [0, 1], as --iso-color takes it");
  expectRefused(R"([{"event": "set_lighting", "material": [0.1, 0.2, 0.3]}])",
                "\"material\" must be [ka, kd, ks, shininess], as --material takes them");
  expectRefused(R"([{"event": "set_lighting", "material": [0.1, 0.2, 0.3, 0]}])",
                "\"material\": SHININESS must lie in [1, 1024], got 0, as --material takes them");
  expectRefused(R"([{"event": "set_lighting", "shading": "off"}])", "\"shading\" must be true or false");
  expectRefused(R"([{"event": "set_lighting", "shading": true, "color": [1, 0, 0]}])",
                "unknown key \"color\"");
  expectRefused(R"([{"event": "play", "playing": 1}])", "\"playing\" must be true or false");
  expectRefused(R"([{"event": "play", "playing": true, "seconds_each": -1}])",
                "event 0 (play): \"seconds_each\" must be seconds from 0 to 1e6");
}

TEST(ViewScript, HugeCoordinatesAndTimesAreRefusedAtLoad) {
  // Finite, but a drag between them moves by inf pixels.
  expectRefused(R"([{"event": "drag", "from": [-1e308, 0], "to": [1e308, 0], "steps": 1}])",
                "s.json: event 0 (drag): \"from\" must be [x, y] in window pixels, each within +-1e6");
  expectRefused(R"([{"event": "mouse_down", "pos": [0, 2e6]}])", "event 0 (mouse_down): \"pos\" must be");
  expectRefused(R"([{"event": "quit", "at": 1e308}])", "event 0 (quit): \"at\" must be at most 1e6 seconds");
  expectRefused(R"([{"event": "key", "key": "w", "seconds": 1e308}])",
                "event 0 (key): \"seconds\" must be at most 1e6 seconds");
  const ViewScript s = parseViewScript(R"([{"event": "mouse_move", "pos": [-1e6, 1e6], "at": 1e6}])", "t");
  EXPECT_EQ(s.events[0].pos, glm::dvec2(-1e6, 1e6));
}

TEST(ViewScript, AMouseMoveTakesNoButton) {
  // A move drags with the buttons held since mouse_down: a button of its own would be ignored.
  expectRefused(R"([{"event": "mouse_move", "pos": [1, 2], "button": "left"}])",
                "event 0 (mouse_move): unknown key \"button\"");
}

TEST(ViewScript, AScreenshotWithPanelsIsAPng) {
  expectRefused(R"([{"event": "screenshot", "file": "a.exr", "panels": true}])",
                "s.json: event 0 (screenshot): \"panels\": true writes a PNG of the window");
  expectRefused(R"([{"event": "screenshot", "file": "a.EXR", "panels": true}])",
                "s.json: event 0 (screenshot): \"panels\": true writes a PNG of the window");
  EXPECT_NO_THROW(parseViewScript(R"([{"event": "screenshot", "file": "a.exr"}])", "t"));
}

TEST(ViewScript, EveryEventKnowsWhereItCameFrom) {
  const ViewScript s = parseViewScript(
      R"([{"event": "quit"}, {"event": "drag", "from": [0, 0], "to": [1, 1], "steps": 1}])", "s.json");
  ASSERT_EQ(s.events.size(), 4u);
  EXPECT_EQ(s.events[0].where, "s.json: event 0 (quit)");
  for (size_t i = 1; i < 4; ++i) EXPECT_EQ(s.events[i].where, "s.json: event 1 (drag)");
}

}  // namespace
}  // namespace ropecast::tools
