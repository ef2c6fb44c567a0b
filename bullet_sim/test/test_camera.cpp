// The panoramic camera: what each column and row sees in a room of four coloured walls, stripes,
// furniture seen over, shading, the palette of a world without colours, the seeded noise.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "bullet_sim/panoramic_camera.h"
#include "bullet_sim/robot_model.h"

#include <yaml-cpp/yaml.h>

using namespace bullet_sim;

namespace {

// A 6 x 4 m room: east wall red (with a blue poster), north green, west blue, south yellow; the
// camera in the middle facing east.
const char* kRoom = R"(name: camera_room
wall_thickness: 0.1
wall_height: 2.0
colors: {floor: [100, 90, 80], ceiling: [220, 220, 210]}
walls:
  - points: [[6, 0], [6, 4]]
    color: [200, 0, 0]
    stripes:
      - {from: 1.5, to: 2.5, bottom: 0.5, top: 1.2, color: [0, 0, 250]}
  - points: [[6, 4], [0, 4]]
    color: [0, 200, 0]
  - points: [[0, 4], [0, 0]]
    color: [0, 0, 200]
  - points: [[0, 0], [6, 0]]
    color: [200, 200, 0]
BOXES
robot:
  start: [3.0, 2.0, 0.0]
)";

World room(const std::string& boxes = "") {
  std::string text = kRoom;
  text.replace(text.find("BOXES"), 5, boxes);
  return parseWorld(text, "camera_room.yaml");
}

CameraParams noiseless() {
  CameraParams p;
  p.noise_stddev = 0.0;
  return p;
}

struct Image {
  const std::vector<uint8_t>& rgb;
  int width;
  Rgb at(int r, int c) const {
    const uint8_t* p = rgb.data() + (size_t(r) * width + c) * 3;
    return Rgb{p[0], p[1], p[2]};
  }
};

// The noiseless view from `pose`, 0.8 m high, in `world`.
struct View {
  World world;
  RayCaster2D caster;
  PanoramicCamera cam;
  std::vector<uint8_t> rgb;
  View(const World& w, const Pose2& pose = {3.0, 2.0, 0.0}) : world(w), caster(world), cam(world, caster, noiseless(), 1) {
    cam.render(pose, 0.8, &rgb);
  }
  Image image() const { return Image{rgb, cam.params().width}; }
};

// The column whose bearing (camera frame) is nearest `bearing`.
int columnAt(const PanoramicCamera& cam, double bearing) {
  int best = 0;
  for (int c = 1; c < cam.params().width; ++c)
    if (std::abs(std::remainder(cam.columnBearing(c) - bearing, 2 * M_PI)) <
        std::abs(std::remainder(cam.columnBearing(best) - bearing, 2 * M_PI)))
      best = c;
  return best;
}

// The row whose height on a surface `distance` (m) away from a camera `z` high is nearest `height`.
int rowAt(const PanoramicCamera& cam, double z, double distance, double height) {
  int best = 0;
  auto off = [&](int r) { return std::abs(z + distance * std::tan(cam.rowElevation(r)) - height); };
  for (int r = 1; r < cam.params().height; ++r)
    if (off(r) < off(best)) best = r;
  return best;
}

uint8_t shaded(uint8_t v, double shade) { return uint8_t(std::lround(v * shade)); }

}  // namespace

TEST(PanoramicCamera, ImageAxes) {
  const View v(room());
  const PanoramicCamera& cam = v.cam;
  EXPECT_NEAR(cam.columnBearing(360), -M_PI / 720, 1e-12);  // the middle column looks ahead
  EXPECT_NEAR(cam.columnBearing(180), M_PI / 2 - M_PI / 720, 1e-12);  // a quarter in: the robot's left
  EXPECT_NEAR(cam.rowElevation(0), M_PI / 6 - M_PI / 720, 1e-9);      // row 0 looks up
  EXPECT_NEAR(cam.rowElevation(119), -(M_PI / 6 - M_PI / 720), 1e-9);
}

TEST(PanoramicCamera, EachWallIsSeenWhereItIsWithItsColourShadedByItsAngle) {
  const View v(room());
  const PanoramicCamera& cam = v.cam;
  ASSERT_EQ(v.rgb.size(), 720u * 120u * 3u);
  const Image img = v.image();
  const int horizon = rowAt(cam, 0.8, 3.0, 0.8);
  // Head-on (shade ~1) ahead: red (above the poster); left: green; behind: blue; right: yellow.
  const Rgb ahead = img.at(rowAt(cam, 0.8, 3.0, 1.5), columnAt(cam, 0.0));
  EXPECT_NEAR(ahead.r, 200, 1);
  EXPECT_EQ(ahead.g, 0);
  EXPECT_EQ(img.at(horizon, columnAt(cam, M_PI / 2)).g, shaded(200, 1.0));
  EXPECT_EQ(img.at(horizon, columnAt(cam, M_PI)).b, shaded(200, 1.0));
  const Rgb right = img.at(horizon, columnAt(cam, -M_PI / 2));
  EXPECT_EQ(right.r, right.g);
  EXPECT_EQ(right.b, 0);
  // 0.5 rad off the east wall's normal: Lambert with the ambient part.
  const int c = columnAt(cam, 0.5);
  const double bearing = cam.columnBearing(c);
  const double distance = 3.0 / std::cos(bearing);
  const Rgb oblique = img.at(rowAt(cam, 0.8, distance, 0.8), c);
  EXPECT_NEAR(oblique.r, 200 * (0.4 + 0.6 * std::cos(bearing)), 1.0);
  EXPECT_LT(oblique.r, ahead.r);
}

TEST(PanoramicCamera, TheFloorBelowTheCeilingAboveAWallsFootAndTop) {
  const View v(room());
  const PanoramicCamera& cam = v.cam;
  const Image img = v.image();
  const int c = columnAt(cam, 0.0);
  // 3 m from the east wall, 30 deg up reaches 0.8 + 1.7 m: above the 2 m wall, the ceiling.
  const double up = 0.4 + 0.6 * std::abs(std::sin(cam.rowElevation(0)));
  EXPECT_EQ(img.at(0, c).r, shaded(220, up));
  EXPECT_EQ(img.at(0, c).b, shaded(210, up));
  EXPECT_EQ(img.at(119, c).r, shaded(100, up));  // the floor, symmetric
  // Just below the wall's top: the wall; just above: the ceiling.
  EXPECT_EQ(img.at(rowAt(cam, 0.8, 3.0, 1.9), c).g, 0);
  EXPECT_EQ(img.at(rowAt(cam, 0.8, 3.0, 2.1), c).g, shaded(220, 0.4 + 0.6 * std::sin(cam.rowElevation(rowAt(cam, 0.8, 3.0, 2.1)))));
  EXPECT_NEAR(img.at(rowAt(cam, 0.8, 3.0, 0.1), c).r, 200, 1);
  const int below = rowAt(cam, 0.8, 3.0, -0.1);  // the floor just before the wall's foot
  EXPECT_EQ(img.at(below, c).g, shaded(90, 0.4 + 0.6 * std::abs(std::sin(cam.rowElevation(below)))));
}

TEST(PanoramicCamera, AStripeIsSeenOnItsStretchOfWallBetweenItsHeights) {
  const View v(room());
  const PanoramicCamera& cam = v.cam;
  const Image img = v.image();
  // The poster: y 1.5-2.5 on the east wall (along = y), 0.5-1.2 m high.
  const int c = columnAt(cam, 0.0);
  EXPECT_GT(img.at(rowAt(cam, 0.8, 3.0, 0.9), c).b, 240);
  EXPECT_EQ(img.at(rowAt(cam, 0.8, 3.0, 1.4), c).b, 0);  // above it: the wall's red
  EXPECT_EQ(img.at(rowAt(cam, 0.8, 3.0, 0.3), c).b, 0);  // below it
  const int beside = columnAt(cam, std::atan2(0.8, 3.0));  // y = 2.8: past its end
  EXPECT_EQ(img.at(rowAt(cam, 0.8, std::hypot(3.0, 0.8), 0.9), beside).b, 0);
}

TEST(PanoramicCamera, ALowBoxIsSeenOverAndItsTopFromAbove) {
  // A 0.5 m high box (cyan) 1.5-2.0 m ahead, across the view.
  const View v(room("boxes:\n  - {center: [4.75, 2.0], size: [0.5, 1.0], height: 0.5, color: [0, 150, 150]}"));
  const PanoramicCamera& cam = v.cam;
  const Image img = v.image();
  const int c = columnAt(cam, 0.0);
  EXPECT_NEAR(img.at(rowAt(cam, 0.8, 3.0, 1.5), c).r, 200, 1);  // the wall, over the box
  const Rgb face = img.at(rowAt(cam, 0.8, 1.5, 0.25), c);         // the box's face
  EXPECT_EQ(face.r, 0);
  EXPECT_NEAR(face.g, 150, 1);
  // Looking down onto the box between its near and far faces: its top, lighter than its face.
  const int down = rowAt(cam, 0.8, 1.75, 0.5);
  const Rgb top = img.at(down, c);
  const double flat = 0.4 + 0.6 * std::abs(std::sin(cam.rowElevation(down)));
  EXPECT_EQ(top.g, shaded(150 + 105 / 4, flat));  // a quarter of the way to white
  EXPECT_EQ(top.r, shaded(255 / 4, flat));
}

TEST(PanoramicCamera, ALowCylinderIsSeenOverAPillarIsNot) {
  const View v(room("cylinders:\n  - {center: [4.5, 2.0], radius: 0.2, height: 0.45, color: [0, 0, 0]}\n"
                       "  - {center: [3.0, 0.8], radius: 0.2, color: [0, 0, 0]}"));
  const PanoramicCamera& cam = v.cam;
  const Image img = v.image();
  const int ahead = columnAt(cam, 0.0);
  EXPECT_EQ(img.at(rowAt(cam, 0.8, 1.3, 0.2), ahead).r, 0);       // the leg, black
  EXPECT_NEAR(img.at(rowAt(cam, 0.8, 3.0, 1.5), ahead).r, 200, 1);  // the wall over it
  EXPECT_EQ(img.at(rowAt(cam, 0.8, 1.0, 1.5), columnAt(cam, -M_PI / 2)).r, 0);  // the pillar, full height
}

TEST(PanoramicCamera, AWallsEndsAreItsDoorFrames) {
  // A door 1 m wide in the north wall (x 2.5-3.5): from south-west of it, the robot sees the
  // east jamb's face (the end of the wall piece east of the door, at x = 3.5).
  std::string text = kRoom;
  auto sub = [&](const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  };
  sub("  - points: [[6, 4], [0, 4]]\n    color: [0, 200, 0]",
      "  - points: [[6, 4], [3.5, 4]]\n    color: [0, 200, 0]\n  - points: [[2.5, 4], [0, 4]]\n    color: [0, 200, 0]");
  sub("BOXES", "");
  sub("ceiling: [220, 220, 210]", "ceiling: [220, 220, 210], wall_ends: [10, 20, 30]");
  const View v(parseWorld(text, "door.yaml"), {2.0, 2.0, 0.0});
  const PanoramicCamera& cam = v.cam;
  const Image img = v.image();
  const Rgb jamb = img.at(rowAt(cam, 0.8, 2.5, 1.0), columnAt(cam, std::atan2(2.0, 1.5)));
  EXPECT_NEAR(jamb.g, 2 * jamb.r, 1.0);  // (10, 20, 30) shaded, not the wall's green
  EXPECT_NEAR(double(jamb.b) / jamb.r, 3.0, 0.4);
  EXPECT_GT(jamb.b, 0);
}

TEST(PanoramicCamera, AWorldWithoutColoursGetsADeterministicPalettePerSurface) {
  World w = room();
  for (auto& wall : w.walls) {
    wall.color.reset();
    wall.stripes.clear();
  }
  w.floor_color.reset();
  const RayCaster2D caster(w);
  PanoramicCamera a(w, caster, noiseless(), 1), b(w, caster, noiseless(), 99);
  std::vector<uint8_t> ra, rb;
  a.render({3.0, 2.0, 0.0}, 0.8, &ra);
  b.render({3.0, 2.0, 0.0}, 0.8, &rb);
  EXPECT_EQ(ra, rb);  // no noise: the seed does not matter, the palette is the world's
  const Image img{ra, 720};
  const int horizon = 60;
  const Rgb east = img.at(horizon, columnAt(a, 0.0)), north = img.at(horizon, columnAt(a, M_PI / 2)),
            west = img.at(horizon, columnAt(a, M_PI));
  EXPECT_FALSE(east == north);
  EXPECT_FALSE(north == west);
  EXPECT_FALSE(east == west);
  EXPECT_TRUE(PanoramicCamera::paletteColor(0, 7) == PanoramicCamera::paletteColor(0, 7));
  EXPECT_FALSE(PanoramicCamera::paletteColor(0, 7) == PanoramicCamera::paletteColor(1, 7));
}

TEST(PanoramicCamera, TheNoiseIsSeededAndCentredOnTheImage) {
  const World w = room();
  const RayCaster2D caster(w);
  CameraParams p = noiseless();
  PanoramicCamera clean(w, caster, p, 1);
  p.noise_stddev = 3.0;
  PanoramicCamera a(w, caster, p, 5), b(w, caster, p, 5), c(w, caster, p, 6);
  std::vector<uint8_t> r0, ra, rb, rc;
  clean.render({3.0, 2.0, 0.3}, 0.8, &r0);
  a.render({3.0, 2.0, 0.3}, 0.8, &ra);
  b.render({3.0, 2.0, 0.3}, 0.8, &rb);
  c.render({3.0, 2.0, 0.3}, 0.8, &rc);
  EXPECT_EQ(ra, rb);
  EXPECT_NE(ra, rc);
  double sum = 0.0, sum2 = 0.0;
  int n = 0;
  for (size_t i = 0; i < r0.size(); ++i) {
    if (r0[i] < 20 || r0[i] > 235) continue;  // away from the clamps at 0 and 255
    const double d = double(ra[i]) - r0[i];
    sum += d;
    sum2 += d * d;
    ++n;
  }
  ASSERT_GT(n, 10000);
  EXPECT_NEAR(sum / n, 0.0, 0.1);
  EXPECT_NEAR(std::sqrt(sum2 / n), 3.0, 0.2);  // rounding adds 1/12 of a level's variance
}

TEST(PanoramicCamera, BadParametersAreRefused) {
  CameraParams p;
  EXPECT_TRUE(PanoramicCamera::validate(p));
  std::string why;
  p.width = 3;
  EXPECT_FALSE(PanoramicCamera::validate(p, &why));
  EXPECT_NE(why.find("width"), std::string::npos);
  p = CameraParams();
  p.vertical_fov = 3.2;
  EXPECT_FALSE(PanoramicCamera::validate(p));
  p = CameraParams();
  p.noise_stddev = -1.0;
  EXPECT_FALSE(PanoramicCamera::validate(p));
  const World w = room();
  const World other = room("boxes:\n  - {center: [4.75, 2.0], size: [0.5, 1.0]}");
  const RayCaster2D caster(other);
  EXPECT_THROW(PanoramicCamera(w, caster, CameraParams(), 1), std::invalid_argument);  // a caster of another world
}

TEST(PanoramicCamera, TheCamerasPoseIsReadFromTheUrdf) {
  std::ifstream in(URDF_PATH);
  std::stringstream s;
  s << in.rdbuf();
  const RobotModel m = robotModelFromUrdf(s.str(), "base_link", "laser", "camera");
  EXPECT_TRUE(m.has_camera);
  EXPECT_NEAR(m.camera_z, 0.8, 1e-9);
  EXPECT_NEAR(m.camera_x, -0.05, 1e-9);
  EXPECT_FALSE(robotModelFromUrdf(s.str(), "base_link", "laser").has_camera);
  EXPECT_THROW(robotModelFromUrdf(s.str(), "base_link", "laser", "no_camera"), RobotModelError);
}

TEST(PanoramicCamera, TheNoiseDefaultIsTheSharedCameraYamls) {
  // bullet_sim_node reads camera/noise_stddev (config/camera.yaml, shared with the fingerprint node).
  const std::string robot_yaml = ROBOT_YAML;
  const YAML::Node camera = YAML::LoadFile(robot_yaml.substr(0, robot_yaml.rfind('/')) + "/camera.yaml");
  EXPECT_NEAR(camera["noise_stddev"].as<double>(), CameraParams().noise_stddev, 1e-12);
}
