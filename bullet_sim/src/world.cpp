#include "bullet_sim/world.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

namespace bullet_sim {
namespace {

// Builds "<file>:<line>: <key>: <problem>" (yaml-cpp marks are 0-based).
class ErrorContext {
 public:
  explicit ErrorContext(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(const YAML::Node& node, const std::string& key, const std::string& problem) const {
    std::ostringstream s;
    s << source_ << ":";
    if (node.IsDefined() && node.Mark().line >= 0) s << node.Mark().line + 1 << ":";
    s << " " << key << ": " << problem;
    throw WorldError(s.str());
  }

  void requireMap(const YAML::Node& node, const std::string& key) const {
    if (!node.IsMap()) fail(node, key, "must be a mapping");
  }

  void allowKeys(const YAML::Node& node, const std::string& key, const std::set<std::string>& allowed) const {
    requireMap(node, key);
    for (const auto& kv : node) {
      const std::string k = kv.first.as<std::string>();
      if (!allowed.count(k)) {
        std::string list;
        for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
        fail(kv.first, key.empty() ? k : key + "." + k, "unknown key (allowed: " + list + ")");
      }
    }
  }

  YAML::Node required(const YAML::Node& parent, const std::string& parent_key, const std::string& key) const {
    const YAML::Node n = parent[key];
    if (!n.IsDefined() || n.IsNull()) fail(parent, join(parent_key, key), "missing required key");
    return n;
  }

  double number(const YAML::Node& node, const std::string& key) const {
    if (!node.IsScalar()) fail(node, key, "must be a number");
    double v = 0.0;
    try {
      v = node.as<double>();
    } catch (const YAML::Exception&) {
      fail(node, key, "must be a number, got '" + node.Scalar() + "'");
    }
    if (!std::isfinite(v)) fail(node, key, "must be finite");
    return v;
  }

  double positive(const YAML::Node& node, const std::string& key) const {
    const double v = number(node, key);
    if (v <= 0.0) fail(node, key, "must be positive, got " + node.Scalar());
    return v;
  }

  bool boolean(const YAML::Node& node, const std::string& key) const {
    if (!node.IsScalar()) fail(node, key, "must be true or false");
    try {
      return node.as<bool>();
    } catch (const YAML::Exception&) {
      fail(node, key, "must be true or false, got '" + node.Scalar() + "'");
    }
    return false;
  }

  std::string text(const YAML::Node& node, const std::string& key) const {
    if (!node.IsScalar()) fail(node, key, "must be a string");
    return node.Scalar();
  }

  std::vector<double> numbers(const YAML::Node& node, const std::string& key, size_t count) const {
    if (!node.IsSequence() || node.size() != count)
      fail(node, key, "must be a list of " + std::to_string(count) + " numbers");
    std::vector<double> out;
    for (size_t i = 0; i < count; ++i) out.push_back(number(node[i], key));
    return out;
  }

  Rgb color(const YAML::Node& node, const std::string& key) const {
    if (!node.IsSequence() || node.size() != 3) fail(node, key, "must be a colour [r, g, b], each 0-255");
    int c[3];
    for (size_t i = 0; i < 3; ++i) {
      const double v = number(node[i], key);
      if (v < 0.0 || v > 255.0 || v != std::floor(v))
        fail(node[i], key, "colour components are whole numbers 0-255, got " + node[i].Scalar());
      c[i] = static_cast<int>(v);
    }
    return Rgb{uint8_t(c[0]), uint8_t(c[1]), uint8_t(c[2])};
  }

  Vec2 point(const YAML::Node& node, const std::string& key) const {
    const auto v = numbers(node, key, 2);
    return {v[0], v[1]};
  }

  std::vector<Vec2> points(const YAML::Node& node, const std::string& key) const {
    if (!node.IsSequence()) fail(node, key, "must be a list of [x, y] points");
    std::vector<Vec2> out;
    for (const auto& p : node) out.push_back(point(p, key));
    return out;
  }

  static std::string join(const std::string& a, const std::string& b) { return a.empty() ? b : a + "." + b; }

 private:
  std::string source_;
};

std::string indexed(const std::string& key, size_t i) { return key + "[" + std::to_string(i) + "]"; }

// A wall's coloured stretches: along the polyline within its length, between the floor and the
// wall's top (`top` defaults to wall_height, `bottom` to 0).
std::vector<WallStripe> parseStripes(const ErrorContext& ctx, const YAML::Node& node, const std::string& key,
                                     const WallPolyline& wall, const World& w) {
  if (!node.IsSequence()) ctx.fail(node, key, "must be a list");
  const double length = wall.length();
  std::vector<WallStripe> out;
  for (size_t j = 0; j < node.size(); ++j) {
    const std::string k = indexed(key, j);
    ctx.allowKeys(node[j], k, {"from", "to", "bottom", "top", "color"});
    WallStripe s;
    s.from = ctx.number(ctx.required(node[j], k, "from"), k + ".from");
    s.to = ctx.number(ctx.required(node[j], k, "to"), k + ".to");
    s.bottom = node[j]["bottom"] ? ctx.number(node[j]["bottom"], k + ".bottom") : 0.0;
    s.top = node[j]["top"] ? ctx.number(node[j]["top"], k + ".top") : w.wall_height;
    s.color = ctx.color(ctx.required(node[j], k, "color"), k + ".color");
    if (!(s.from >= 0.0 && s.from < s.to && s.to <= length + 1e-9))
      ctx.fail(node[j], k, "needs 0 <= from < to <= the wall's length (" + std::to_string(length) + " m)");
    if (!(s.bottom >= 0.0 && s.bottom < s.top && s.top <= w.wall_height + 1e-9))
      ctx.fail(node[j], k, "needs 0 <= bottom < top <= wall_height (" + std::to_string(w.wall_height) + " m)");
    out.push_back(s);
  }
  return out;
}

double distanceToBox(const OrientedBox& b, const Vec2& p) {
  const double c = std::cos(b.yaw), s = std::sin(b.yaw);
  const double dx = p.x - b.center.x, dy = p.y - b.center.y;
  const double lx = std::abs(c * dx + s * dy) - b.half_x;
  const double ly = std::abs(-s * dx + c * dy) - b.half_y;
  const double outside = std::hypot(std::max(lx, 0.0), std::max(ly, 0.0));
  return outside > 0.0 ? outside : std::max(lx, ly);
}

bool polygonContains(const std::vector<Vec2>& poly, const Vec2& p) {
  bool inside = false;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Vec2& a = poly[i];
    const Vec2& b = poly[j];
    if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) inside = !inside;
  }
  return inside;
}

}  // namespace

std::vector<OrientedBox> World::solidBoxes(std::vector<SolidSource>* sources) const {
  std::vector<OrientedBox> out;
  auto add = [&](const OrientedBox& box, SolidSource::Kind kind, size_t index, size_t segment, double along) {
    out.push_back(box);
    if (sources) sources->push_back(SolidSource{kind, index, segment, along});
  };
  if (sources) sources->clear();
  for (size_t k = 0; k < walls.size(); ++k) {
    const WallPolyline& w = walls[k];
    double along = 0.0;
    for (size_t i = 0; i + 1 < w.points.size(); ++i) {
      const Vec2& a = w.points[i];
      const Vec2& b = w.points[i + 1];
      OrientedBox box;
      box.center = {(a.x + b.x) / 2, (a.y + b.y) / 2};
      box.half_x = std::hypot(b.x - a.x, b.y - a.y) / 2;
      box.half_y = w.thickness / 2;
      box.yaw = std::atan2(b.y - a.y, b.x - a.x);
      box.height = wall_height;
      box.color = w.color;
      if (box.half_x > 0.0) add(box, SolidSource::Wall, k, i, along);
      along += 2.0 * box.half_x;
    }
  }
  for (size_t k = 0; k < boxes.size(); ++k) add(boxes[k], SolidSource::Box, k, 0, 0.0);
  for (size_t k = 0; k < doors.size(); ++k) {
    if (doors[k].closed) add(doorLeaf(doors[k]), SolidSource::DoorLeaf, k, 0, 0.0);
  }
  return out;
}

double WallPolyline::length() const {
  double l = 0.0;
  for (size_t i = 0; i + 1 < points.size(); ++i) l += std::hypot(points[i + 1].x - points[i].x, points[i + 1].y - points[i].y);
  return l;
}

OrientedBox World::doorLeaf(const Door& door) const {
  double best = 0.3;  // m: a door centre lies on its regions' shared boundary
  double yaw = 0.0;
  bool found = false;
  for (const auto& r : regions) {
    if (r.name != door.between[0] && r.name != door.between[1]) continue;
    for (size_t i = 0; i < r.polygon.size(); ++i) {
      const Vec2& a = r.polygon[i];
      const Vec2& b = r.polygon[(i + 1) % r.polygon.size()];
      const double dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
      if (len2 <= 0.0) continue;
      const double t = std::clamp(((door.center.x - a.x) * dx + (door.center.y - a.y) * dy) / len2, 0.0, 1.0);
      const double d = std::hypot(a.x + t * dx - door.center.x, a.y + t * dy - door.center.y);
      if (d < best) {
        best = d;
        yaw = std::atan2(dy, dx);
        found = true;
      }
    }
  }
  if (!found) {
    throw WorldError(source + ": door between '" + door.between[0] + "' and '" + door.between[1] +
                     "': no edge of either region passes within 0.3 m of its centre, cannot close it");
  }
  OrientedBox leaf;
  leaf.center = door.center;
  leaf.half_x = (door.width + wall_thickness) / 2;
  leaf.half_y = wall_thickness / 4;
  leaf.yaw = yaw;
  leaf.height = wall_height;
  return leaf;
}

void World::closeDoors(const std::vector<std::string>& names) {
  for (const std::string& name : names) {
    const size_t slash = name.find('/');
    const std::string a = name.substr(0, slash);
    const std::string b = slash == std::string::npos ? "" : name.substr(slash + 1);
    bool matched = false;
    for (auto& d : doors) {
      const bool hit = b.empty() ? (d.between[0] == a || d.between[1] == a)
                                 : ((d.between[0] == a && d.between[1] == b) || (d.between[0] == b && d.between[1] == a));
      if (hit) {
        doorLeaf(d);  // throws when the leaf's direction is unknown
        d.closed = true;
        matched = true;
      }
    }
    if (!matched) {
      std::string known;
      for (const auto& d : doors) known += (known.empty() ? "" : ", ") + d.between[0] + "/" + d.between[1];
      throw WorldError(source + ": cannot close door '" + name + "': no such door (doors: " + known + ")");
    }
  }
}

void World::bounds(Vec2* min, Vec2* max) const {
  double inf = std::numeric_limits<double>::infinity();
  *min = {inf, inf};
  *max = {-inf, -inf};
  auto grow = [&](double x, double y, double pad) {
    min->x = std::min(min->x, x - pad);
    min->y = std::min(min->y, y - pad);
    max->x = std::max(max->x, x + pad);
    max->y = std::max(max->y, y + pad);
  };
  for (const auto& b : solidBoxes()) {
    const double c = std::cos(b.yaw), s = std::sin(b.yaw);
    const double ex = std::abs(c) * b.half_x + std::abs(s) * b.half_y;  // half extents of the rotated box
    const double ey = std::abs(s) * b.half_x + std::abs(c) * b.half_y;
    min->x = std::min(min->x, b.center.x - ex);
    min->y = std::min(min->y, b.center.y - ey);
    max->x = std::max(max->x, b.center.x + ex);
    max->y = std::max(max->y, b.center.y + ey);
  }
  for (const auto& c : cylinders) grow(c.center.x, c.center.y, c.radius);
  if (min->x > max->x) *min = *max = {0.0, 0.0};
}

int World::regionAt(const Vec2& p) const {
  for (size_t i = 0; i < regions.size(); ++i)
    if (polygonContains(regions[i].polygon, p)) return static_cast<int>(i);
  return -1;
}

double distanceToObstacles(const World& world, const Vec2& p) {
  double d = std::numeric_limits<double>::infinity();
  for (const auto& b : world.solidBoxes()) d = std::min(d, distanceToBox(b, p));
  for (const auto& c : world.cylinders) d = std::min(d, std::hypot(p.x - c.center.x, p.y - c.center.y) - c.radius);
  return d;
}

namespace {

// The lists of a world file, each into `world` (its defaults, such as wall_thickness, already read).
void parseWalls(const ErrorContext& ctx, const YAML::Node& walls, World* world) {
  World& w = *world;
  if (!walls.IsSequence()) ctx.fail(walls, "walls", "must be a list");
  for (size_t i = 0; i < walls.size(); ++i) {
    const std::string key = indexed("walls", i);
    ctx.allowKeys(walls[i], key, {"points", "thickness", "color", "stripes"});
    WallPolyline poly;
    const YAML::Node pts = ctx.required(walls[i], key, "points");
    poly.points = ctx.points(pts, key + ".points");
    if (poly.points.size() < 2) ctx.fail(pts, key + ".points", "a wall polyline needs at least two points");
    poly.thickness = walls[i]["thickness"] ? ctx.positive(walls[i]["thickness"], key + ".thickness") : w.wall_thickness;
    if (walls[i]["color"]) poly.color = ctx.color(walls[i]["color"], key + ".color");
    if (const YAML::Node stripes = walls[i]["stripes"]) poly.stripes = parseStripes(ctx, stripes, key + ".stripes", poly, w);
    w.walls.push_back(poly);
  }
}

void parseBoxes(const ErrorContext& ctx, const YAML::Node& boxes, World* world) {
  World& w = *world;
  if (!boxes.IsSequence()) ctx.fail(boxes, "boxes", "must be a list");
  for (size_t i = 0; i < boxes.size(); ++i) {
    const std::string key = indexed("boxes", i);
    ctx.allowKeys(boxes[i], key, {"center", "size", "yaw", "height", "color"});
    OrientedBox b;
    b.center = ctx.point(ctx.required(boxes[i], key, "center"), key + ".center");
    const YAML::Node size = ctx.required(boxes[i], key, "size");
    const auto sz = ctx.numbers(size, key + ".size", 2);
    if (sz[0] <= 0.0 || sz[1] <= 0.0) ctx.fail(size, key + ".size", "sizes must be positive");
    b.half_x = sz[0] / 2;
    b.half_y = sz[1] / 2;
    if (boxes[i]["yaw"]) b.yaw = ctx.number(boxes[i]["yaw"], key + ".yaw");
    b.height = boxes[i]["height"] ? ctx.positive(boxes[i]["height"], key + ".height") : kFurnitureHeight;
    if (boxes[i]["color"]) b.color = ctx.color(boxes[i]["color"], key + ".color");
    w.boxes.push_back(b);
  }
}

void parseCylinders(const ErrorContext& ctx, const YAML::Node& cyls, World* world) {
  World& w = *world;
  if (!cyls.IsSequence()) ctx.fail(cyls, "cylinders", "must be a list");
  for (size_t i = 0; i < cyls.size(); ++i) {
    const std::string key = indexed("cylinders", i);
    ctx.allowKeys(cyls[i], key, {"center", "radius", "height", "color"});
    Cylinder c;
    c.center = ctx.point(ctx.required(cyls[i], key, "center"), key + ".center");
    c.radius = ctx.positive(ctx.required(cyls[i], key, "radius"), key + ".radius");
    c.height = cyls[i]["height"] ? ctx.positive(cyls[i]["height"], key + ".height") : w.wall_height;
    if (cyls[i]["color"]) c.color = ctx.color(cyls[i]["color"], key + ".color");
    w.cylinders.push_back(c);
  }
}

// Ground truth: the regions (names unique) and the doors between them.
void parseRegions(const ErrorContext& ctx, const YAML::Node& regions, std::set<std::string>* names, World* world) {
  World& w = *world;
  std::set<std::string>& region_names = *names;
  if (!regions.IsSequence()) ctx.fail(regions, "regions", "must be a list");
  for (size_t i = 0; i < regions.size(); ++i) {
    const std::string key = indexed("regions", i);
    ctx.allowKeys(regions[i], key, {"name", "kind", "polygon"});
    Region r;
    r.name = ctx.text(ctx.required(regions[i], key, "name"), key + ".name");
    const YAML::Node kind = ctx.required(regions[i], key, "kind");
    const std::string k = ctx.text(kind, key + ".kind");
    if (k != "room" && k != "hallway") ctx.fail(kind, key + ".kind", "must be 'room' or 'hallway', got '" + k + "'");
    r.hallway = k == "hallway";
    const YAML::Node poly = ctx.required(regions[i], key, "polygon");
    r.polygon = ctx.points(poly, key + ".polygon");
    if (r.polygon.size() < 3) ctx.fail(poly, key + ".polygon", "a polygon needs at least three points");
    if (!region_names.insert(r.name).second) ctx.fail(regions[i], key + ".name", "duplicate region name '" + r.name + "'");
    w.regions.push_back(r);
  }
}

void parseDoors(const ErrorContext& ctx, const YAML::Node& doors, const std::set<std::string>& region_names,
                World* world) {
  World& w = *world;
  if (!doors.IsSequence()) ctx.fail(doors, "doors", "must be a list");
  for (size_t i = 0; i < doors.size(); ++i) {
    const std::string key = indexed("doors", i);
    ctx.allowKeys(doors[i], key, {"between", "center", "width", "closed"});
    Door d;
    const YAML::Node between = ctx.required(doors[i], key, "between");
    if (!between.IsSequence() || between.size() != 2) ctx.fail(between, key + ".between", "must name two regions");
    for (size_t j = 0; j < 2; ++j) {
      d.between[j] = ctx.text(between[j], key + ".between");
      if (!region_names.count(d.between[j])) ctx.fail(between[j], key + ".between", "unknown region '" + d.between[j] + "'");
    }
    d.center = ctx.point(ctx.required(doors[i], key, "center"), key + ".center");
    d.width = ctx.positive(ctx.required(doors[i], key, "width"), key + ".width");
    if (const YAML::Node closed = doors[i]["closed"]) d.closed = ctx.boolean(closed, key + ".closed");
    w.doors.push_back(d);
    if (d.closed) {
      try {
        w.doorLeaf(d);  // fail at load time, with the line, if the door cannot be closed
      } catch (const WorldError&) {
        ctx.fail(doors[i], key + ".closed", "cannot close this door: no edge of its regions passes within 0.3 m of its centre");
      }
    }
  }
}

}  // namespace

World parseWorld(const std::string& yaml_text, const std::string& source) {
  const ErrorContext ctx(source);
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    std::ostringstream s;
    s << source << ":" << e.mark.line + 1 << ": not valid YAML: " << e.msg;
    throw WorldError(s.str());
  }
  if (!root.IsMap()) {
    throw WorldError(source + ":1: (document): not a world file: expected a YAML mapping with at least 'name'");
  }
  ctx.allowKeys(root, "", {"name", "wall_thickness", "wall_height", "colors", "walls", "boxes", "cylinders", "robot",
                           "regions", "doors"});

  World w;
  w.source = source;
  w.name = ctx.text(ctx.required(root, "", "name"), "name");
  if (root["wall_thickness"]) w.wall_thickness = ctx.positive(root["wall_thickness"], "wall_thickness");
  if (root["wall_height"]) w.wall_height = ctx.positive(root["wall_height"], "wall_height");
  if (const YAML::Node colors = root["colors"]) {
    ctx.allowKeys(colors, "colors", {"floor", "ceiling", "wall_ends"});
    if (colors["floor"]) w.floor_color = ctx.color(colors["floor"], "colors.floor");
    if (colors["ceiling"]) w.ceiling_color = ctx.color(colors["ceiling"], "colors.ceiling");
    if (colors["wall_ends"]) w.wall_ends_color = ctx.color(colors["wall_ends"], "colors.wall_ends");
  }

  if (const YAML::Node walls = root["walls"]) parseWalls(ctx, walls, &w);
  if (const YAML::Node boxes = root["boxes"]) parseBoxes(ctx, boxes, &w);
  if (const YAML::Node cyls = root["cylinders"]) parseCylinders(ctx, cyls, &w);
  const YAML::Node robot = ctx.required(root, "", "robot");
  ctx.allowKeys(robot, "robot", {"start"});
  const YAML::Node start = ctx.required(robot, "robot", "start");
  const auto s = ctx.numbers(start, "robot.start", 3);
  w.start = {s[0], s[1], s[2]};
  if (distanceToObstacles(w, {w.start.x, w.start.y}) <= 0.0)
    ctx.fail(start, "robot.start", "start pose is inside an obstacle");

  std::set<std::string> region_names;
  if (const YAML::Node regions = root["regions"]) parseRegions(ctx, regions, &region_names, &w);
  if (const YAML::Node doors = root["doors"]) parseDoors(ctx, doors, region_names, &w);
  return w;
}

World loadWorldFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw WorldError(path + ": cannot read the world file (missing or unreadable)");
  std::stringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw WorldError(path + ": cannot read the world file");
  return parseWorld(buffer.str(), path);
}

}  // namespace bullet_sim
