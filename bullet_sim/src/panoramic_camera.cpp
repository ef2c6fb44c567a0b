#include "bullet_sim/panoramic_camera.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace bullet_sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr size_t kMaxHits = 8;          // surfaces a column meets before it stops (low boxes seen over)
constexpr double kPastSurface = 1e-6;   // m, a column's cast goes on this far past a low box's face

enum SurfaceKind : uint32_t { kWallSegment = 0, kBox = 1, kDoorLeaf = 2, kCylinder = 3 };

uint64_t splitmix(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

Rgb fromHsv(double h, double s, double v) {
  const double c = v * s, hp = h / 60.0, x = c * (1.0 - std::abs(std::fmod(hp, 2.0) - 1.0)), m = v - c;
  double r = 0, g = 0, b = 0;
  if (hp < 1) r = c, g = x;
  else if (hp < 2) r = x, g = c;
  else if (hp < 3) g = c, b = x;
  else if (hp < 4) g = x, b = c;
  else if (hp < 5) r = x, b = c;
  else r = c, b = x;
  auto byte = [](double u) { return uint8_t(std::clamp(std::lround(255.0 * u), 0L, 255L)); };
  return Rgb{byte(r + m), byte(g + m), byte(b + m)};
}

uint8_t shadeNoise(double value, float noise) {
  return uint8_t(std::clamp(std::lround(value + noise), 0L, 255L));
}

}  // namespace

bool PanoramicCamera::validate(const CameraParams& p, std::string* error) {
  auto fail = [&](const std::string& why) {
    if (error) *error = why;
    return false;
  };
  if (p.width < 4 || p.height < 2) return fail("camera width must be >= 4 and height >= 2 pixels");
  if (!(p.vertical_fov > 0.0 && p.vertical_fov < kPi - 1e-6)) return fail("camera vertical_fov must be in (0, pi) rad");
  if (!(p.max_range > 0.0)) return fail("camera max_range must be positive");
  if (!(p.noise_stddev >= 0.0)) return fail("camera noise_stddev must be >= 0");
  if (!(p.ambient >= 0.0 && p.ambient <= 1.0)) return fail("camera ambient must be in [0, 1]");
  return true;
}

Rgb PanoramicCamera::paletteColor(uint32_t kind, uint32_t index) {
  const uint64_t h = splitmix((uint64_t(kind) << 32) | index);
  const double hue = double(h % 360);
  const double saturation = 0.2 + 0.3 * double((h >> 16) % 1000) / 1000.0;
  const double value = 0.55 + 0.35 * double((h >> 32) % 1000) / 1000.0;
  return fromHsv(hue, saturation, value);
}

PanoramicCamera::PanoramicCamera(const World& world, const RayCaster2D& caster, const CameraParams& params,
                                 uint64_t seed)
    : world_(world),
      caster_(caster),
      params_(params),
      rng_state_(seed),
      noise_scale_(float(params.noise_stddev * std::sqrt(3.0))) {
  std::string why;
  if (!validate(params, &why)) throw std::invalid_argument("panoramic camera: " + why);
  solids_ = world.solidBoxes(&sources_);
  if (caster.primitiveCount() != 4 * solids_.size() + world.cylinders.size())
    throw std::invalid_argument("panoramic camera: the ray caster was not built from this world");
  for (size_t i = 0; i < solids_.size(); ++i) {
    const SolidSource& s = sources_[i];
    if (solids_[i].color) {
      solid_colors_.push_back(*solids_[i].color);
    } else if (s.kind == SolidSource::Wall) {
      solid_colors_.push_back(paletteColor(kWallSegment, uint32_t(splitmix(s.index) ^ s.segment)));
    } else {
      solid_colors_.push_back(paletteColor(s.kind == SolidSource::Box ? kBox : kDoorLeaf, uint32_t(s.index)));
    }
  }
  for (size_t i = 0; i < world.cylinders.size(); ++i)
    cylinder_colors_.push_back(world.cylinders[i].color ? *world.cylinders[i].color : paletteColor(kCylinder, uint32_t(i)));
  floor_ = world.floor_color ? *world.floor_color : Rgb{120, 110, 100};
  ceiling_ = world.ceiling_color ? *world.ceiling_color : Rgb{230, 230, 225};
  wall_ends_ = world.wall_ends_color ? *world.wall_ends_color : Rgb{110, 75, 45};
  for (int r = 0; r < params_.height; ++r) {
    tan_elevation_.push_back(std::tan(rowElevation(r)));
    // The floor and the ceiling: Lambert by the elevation (seen straight down or up, head-on).
    flat_shade_.push_back(params_.ambient + (1.0 - params_.ambient) * std::abs(std::sin(rowElevation(r))));
  }
}

float PanoramicCamera::noise() {
  // Four 16-bit uniforms of one 64-bit draw: their sum - 2 has variance 4 / 12.
  rng_state_ += 0x9E3779B97F4A7C15ull;
  const uint64_t x = splitmix(rng_state_);
  const float sum = float((x & 0xFFFF) + ((x >> 16) & 0xFFFF) + ((x >> 32) & 0xFFFF) + (x >> 48)) / 65536.0f;
  return (sum - 2.0f) * noise_scale_;
}

double PanoramicCamera::columnBearing(int c) const { return kPi - (c + 0.5) * 2.0 * kPi / params_.width; }

double PanoramicCamera::rowElevation(int r) const {
  return 0.5 * params_.vertical_fov - (r + 0.5) * params_.vertical_fov / params_.height;
}

void PanoramicCamera::castColumn(double ox, double oy, double dx, double dy, std::vector<Hit>* hits) const {
  hits->clear();
  double travelled = 0.0;
  const size_t solid_primitives = 4 * solids_.size();
  while (hits->size() < kMaxHits) {
    size_t index = 0;
    const double t = caster_.cast(ox, oy, dx, dy, params_.max_range - travelled, &index);
    if (!std::isfinite(t)) return;
    Hit h;
    h.near = h.far = travelled + t;
    h.primitive = index;
    h.hx = ox + t * dx;
    h.hy = oy + t * dy;
    const RayCaster2D::Primitive& p = caster_.primitive(index);
    double nx, ny;
    if (index < solid_primitives) {
      h.top = std::min(solids_[index / 4].height, world_.wall_height);
      nx = -(p.by - p.ay);
      ny = p.bx - p.ax;
    } else {
      h.top = std::min(world_.cylinders[index - solid_primitives].height, world_.wall_height);
      nx = h.hx - p.ax;
      ny = h.hy - p.ay;
    }
    const double n = std::hypot(nx, ny);
    const double facing = n > 0.0 ? std::abs(nx * dx + ny * dy) / n : 1.0;
    h.shade = float(params_.ambient + (1.0 - params_.ambient) * facing);
    travelled = h.near + kPastSurface;
    ox = h.hx + kPastSurface * dx;
    oy = h.hy + kPastSurface * dy;
    if (h.top >= world_.wall_height) {
      hits->push_back(h);
      return;
    }
    // A low box: where the column leaves it (its far face), then what lies behind.
    size_t far_index = 0;
    const double t2 = caster_.cast(ox, oy, dx, dy, params_.max_range - travelled, &far_index);
    if (std::isfinite(t2) && far_index < solid_primitives && far_index / 4 == index / 4) {
      h.far = travelled + t2;
      travelled = h.far + kPastSurface;
      ox += (t2 + kPastSurface) * dx;
      oy += (t2 + kPastSurface) * dy;
    }
    hits->push_back(h);
  }
}

Rgb PanoramicCamera::surfaceColor(const Hit& hit, double z) const {
  if (hit.primitive >= 4 * solids_.size()) return cylinder_colors_[hit.primitive - 4 * solids_.size()];
  const size_t solid = hit.primitive / 4;
  const SolidSource& s = sources_[solid];
  if (s.kind == SolidSource::Wall) {
    // A wall box's faces 1 and 3 are its ends (RayCaster2D: corners (-1,-1), (1,-1), (1,1), (-1,1)).
    if (hit.primitive % 4 == 1 || hit.primitive % 4 == 3) return wall_ends_;
    const WallPolyline& wall = world_.walls[s.index];
    if (!wall.stripes.empty()) {
      const Vec2& a = wall.points[s.segment];
      const Vec2& b = wall.points[s.segment + 1];
      const double len = std::hypot(b.x - a.x, b.y - a.y);
      const double u = ((hit.hx - a.x) * (b.x - a.x) + (hit.hy - a.y) * (b.y - a.y)) / len;
      const double along = s.along + std::clamp(u, 0.0, len);
      for (auto it = wall.stripes.rbegin(); it != wall.stripes.rend(); ++it) {
        if (along >= it->from && along <= it->to && z >= it->bottom && z <= it->top) return it->color;
      }
    }
  }
  return solid_colors_[solid];
}

Rgb PanoramicCamera::topColor(const Hit& hit) const {
  // A box's top: its colour, a little lighter (lit from the ceiling).
  const Rgb c = surfaceColor(hit, hit.top);
  auto lift = [](uint8_t v) { return uint8_t(std::min(255, int(v) + (255 - int(v)) / 4)); };
  return Rgb{lift(c.r), lift(c.g), lift(c.b)};
}

void PanoramicCamera::render(const Pose2& pose, double z, std::vector<uint8_t>* rgb) {
  const int W = params_.width, H = params_.height;
  rgb->resize(size_t(W) * H * 3);
  const double cz = std::clamp(z, 1e-3, world_.wall_height - 1e-3);
  const double sigma = params_.noise_stddev;
  auto put = [&](int r, int c, const Rgb& color, double shade) {
    uint8_t* px = rgb->data() + (size_t(r) * W + c) * 3;
    const float n0 = sigma > 0 ? noise() : 0.0f, n1 = sigma > 0 ? noise() : 0.0f, n2 = sigma > 0 ? noise() : 0.0f;
    px[0] = shadeNoise(color.r * shade, n0);
    px[1] = shadeNoise(color.g * shade, n1);
    px[2] = shadeNoise(color.b * shade, n2);
  };
  for (int c = 0; c < W; ++c) {
    const double bearing = pose.yaw + columnBearing(c);
    castColumn(pose.x, pose.y, std::cos(bearing), std::sin(bearing), &hits_);
    for (int r = 0; r < H; ++r) {
      const double t = tan_elevation_[r];
      const double flat = flat_shade_[r];
      bool drawn = false;
      for (const Hit& h : hits_) {
        const double z_near = cz + h.near * t;
        if (z_near < 0.0) break;                      // the floor, before this surface
        if (z_near > world_.wall_height) break;       // the ceiling, before it
        if (z_near <= h.top) {
          put(r, c, surfaceColor(h, z_near), h.shade);
          drawn = true;
          break;
        }
        if (cz + h.far * t <= h.top) {              // over its face, down onto its top
          put(r, c, topColor(h), flat);
          drawn = true;
          break;
        }
      }
      if (!drawn) put(r, c, t < 0.0 ? floor_ : ceiling_, flat);
    }
  }
}

}  // namespace bullet_sim
