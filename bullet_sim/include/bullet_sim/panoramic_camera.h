// The simulated panoramic colour camera: an equirectangular image, 360 deg around and vertical_fov
// up and down, of the world's surface colours (the visual seed: Tapus & Siegwart's omnidirectional
// camera, whose colour patches and vertical edges make a place's fingerprint).
//
// The world is made of vertical extrusions on a flat floor under a flat ceiling at wall_height, so a
// pixel's ray is exact from ONE 2D ray per column: the column's cast (RayCaster2D) gives the surfaces
// it meets in order, and each row's elevation says at which height it meets each of them, or the
// floor or the ceiling before. A low box (furniture, `height` below wall_height) is seen over: the
// column's cast goes on behind it, and its top is seen from above (a low cylinder's - a chair or
// table leg - is not: the legs are thin). 720 casts a frame instead of one
// per pixel.
//
// Image: column c looks at bearing pi - (c + 0.5) 2 pi / width in the camera frame (the middle
// column ahead, the left half of the image to the robot's left, as a camera facing ahead shows it);
// row r at elevation vertical_fov / 2 - (r + 0.5) vertical_fov / height (row 0 up). A surface's
// colour is the world file's (a wall's stripe where one covers the point), else a palette colour
// chosen per surface from its index (deterministic); a wall's end faces - the jambs where a door cuts
// it - take colors.wall_ends (default: a wooden frame's brown), so every door shows its frame; shaded by the angle between the ray and the
// surface (Lambert with an ambient part: a wall seen at a grazing angle is darker), plus noise per
// channel from the camera's own seeded generator (the same seed and poses give the same images):
// the sum of four uniform draws (Irwin-Hall), scaled to noise_stddev - near enough to a Gaussian for
// a sensor's noise, and a fifth of the cost of std::normal_distribution on 259,200 channels a frame.
//
// ROS-free: the world, the ray caster and the standard library.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "bullet_sim/ray_caster.h"
#include "bullet_sim/world.h"

namespace bullet_sim {

/// Parameters of the camera (config/bullet_sim.yaml's camera_* keys; each with its unit and default).
struct CameraParams {
  int width = 720;                     // px, 360 deg around
  int height = 120;                    // px
  double vertical_fov = 1.0471975512;  // rad (60 deg), half above and half below the horizon
  double max_range = 30.0;             // m, farther surfaces are not seen (the floor and ceiling meet there)
  double noise_stddev = 2.0;           // intensity levels (0-255) of Gaussian noise per channel; 0: none
  double ambient = 0.4;                // -, a surface's brightness seen edge-on; 1 seen head-on
};

class PanoramicCamera {
 public:
  /// `caster` must be built from `world` and outlive the camera. Throws std::invalid_argument when
  /// validate() refuses `params`.
  PanoramicCamera(const World& world, const RayCaster2D& caster, const CameraParams& params, uint64_t seed);
  static bool validate(const CameraParams& params, std::string* error = nullptr);
  const CameraParams& params() const { return params_; }

  /// Renders the view from the camera at `pose` (world frame; its yaw is the image's middle column)
  /// and `z` (m above the floor, inside (0, wall_height)) into `rgb` (rgb8, row-major, width *
  /// height * 3 bytes; resized).
  void render(const Pose2& pose, double z, std::vector<uint8_t>* rgb);

  /// rad, camera frame: the bearing of column `c`, the elevation of row `r`.
  double columnBearing(int c) const;
  double rowElevation(int r) const;

  /// The colour of the palette for surface `index` (walls' segments, boxes, cylinders, door leaves
  /// are numbered apart): muted, as painted walls and furniture are.
  static Rgb paletteColor(uint32_t kind, uint32_t index);
  Rgb floorColor() const { return floor_; }
  Rgb ceilingColor() const { return ceiling_; }

 private:
  // What one column meets, in order: surfaces with their distance and height; the last one may be
  // full height (a wall, a pillar, a closed door) and ends the column.
  struct Hit {
    double near = 0.0, far = 0.0;  // m, where the ray enters it and (a low box) leaves it
    double top = 0.0;              // m, its height
    float shade = 1.0f;            // Lambert factor of the face hit
    size_t primitive = 0;
    double hx = 0.0, hy = 0.0;     // the point hit (world frame)
  };
  void castColumn(double ox, double oy, double dx, double dy, std::vector<Hit>* hits) const;
  /// The colour of the face hit at height `z` (a wall's stripe, else its colour), unshaded.
  Rgb surfaceColor(const Hit& hit, double z) const;
  Rgb topColor(const Hit& hit) const;

  const World& world_;
  const RayCaster2D& caster_;
  CameraParams params_;
  std::vector<SolidSource> sources_;  // per solid box of world_.solidBoxes(): 4 primitives each
  std::vector<OrientedBox> solids_;
  std::vector<Rgb> solid_colors_;     // the world file's colour or the palette's, per solid box
  std::vector<Rgb> cylinder_colors_;
  Rgb floor_, ceiling_, wall_ends_;
  std::vector<double> tan_elevation_;  // per row
  std::vector<double> flat_shade_;     // per row: the floor's or the ceiling's shading
  /// One draw of the noise (intensity levels): mean 0, standard deviation noise_stddev.
  float noise();

  uint64_t rng_state_;  // splitmix64's
  float noise_scale_;   // noise_stddev / the standard deviation of a sum of four uniforms in [0, 1)
  std::vector<Hit> hits_;  // scratch, one column's
};

}  // namespace bullet_sim
