// Scene files ("cullproof-scene/1"): parsing and validation. Every error names the file and the
// field (a JSON path such as "camera.frames" or "layout[2].model"); unknown keys are errors, so
// a misspelt field is never silently ignored. The format is documented in corpus/scenes/README.md.
#include "cullproof/sim/scene.hpp"

#include "cullproof/io/case_io.hpp"
#include "cullproof/io/limits.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <system_error>

namespace cullproof::sim {

using nlohmann::json;

// The field (keys of the file) and the problem (which may quote its strings) are written through
// printable_text: a NUL in them would cut the message short.
SceneError::SceneError(std::string file, std::string field, const std::string& problem)
    : std::runtime_error(printable_text(file) + ": " + printable_text(field) + ": " + printable_text(problem)),
      file_(std::move(file)),
      field_(std::move(field)) {}

std::string_view to_string(ProjectionKind k) noexcept {
  switch (k) {
    case ProjectionKind::perspective: return "perspective";
    case ProjectionKind::off_axis: return "off-axis";
    case ProjectionKind::stereo: return "stereo";
    case ProjectionKind::orthographic: return "orthographic";
  }
  return "?";
}

std::string_view to_string(PathKind k) noexcept {
  switch (k) {
    case PathKind::navigation: return "navigation";
    case PathKind::translation_rotation: return "translation-rotation";
    case PathKind::rotation: return "rotation";
    case PathKind::translation: return "translation";
    case PathKind::keyframes: return "keyframes";
  }
  return "?";
}

std::optional<PathKind> path_kind_from_string(const std::string& s) {
  for (PathKind k : {PathKind::navigation, PathKind::translation_rotation, PathKind::rotation, PathKind::translation,
                     PathKind::keyframes})
    if (s == to_string(k)) return k;
  return std::nullopt;
}

std::string_view to_string(FrameMotion m) noexcept {
  switch (m) {
    case FrameMotion::first: return "first";
    case FrameMotion::still: return "still";
    case FrameMotion::translation: return "translation";
    case FrameMotion::rotation: return "rotation";
    case FrameMotion::general: return "general";
  }
  return "?";
}

namespace {

// A JSON object being read: remembers its path for messages and rejects unknown keys.
class Obj {
 public:
  Obj(const json& j, std::string path, const std::string& src) : j_(j), path_(std::move(path)), src_(src) {
    if (!j_.is_object()) fail("", "must be an object");
  }
  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw SceneError(src_, field(key), what);
  }
  std::string field(const std::string& key) const {
    if (key.empty()) return path_.empty() ? "<top>" : path_;
    if (key[0] == '[') return path_ + key;
    return path_.empty() ? key : path_ + "." + key;
  }
  void allow(std::initializer_list<const char*> keys) const {
    for (auto it = j_.begin(); it != j_.end(); ++it) {
      bool ok = false;
      for (const char* k : keys) ok = ok || it.key() == k;
      if (!ok) {
        std::string known;
        for (const char* k : keys) known += (known.empty() ? "" : ", ") + std::string(k);
        fail(it.key(), "unknown field (known: " + known + ")");
      }
    }
  }
  bool has(const char* key) const { return j_.contains(key) && !j_.at(key).is_null(); }
  const json& at(const char* key) const {
    if (!has(key)) fail(key, "missing");
    return j_.at(key);
  }
  double num(const char* key) const {
    const json& v = at(key);
    if (!v.is_number()) fail(key, "must be a number");
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(key, "must be finite");
    return d;
  }
  double num(const char* key, double dflt) const { return has(key) ? num(key) : dflt; }
  double positive(const char* key, double dflt) const {
    const double d = num(key, dflt);
    if (!(d > 0.0)) fail(key, "must be > 0");
    return d;
  }
  long long integer(const char* key) const {
    const json& v = at(key);
    if (!v.is_number_integer()) fail(key, "must be an integer");
    return v.get<long long>();
  }
  long long integer(const char* key, long long dflt) const { return has(key) ? integer(key) : dflt; }
  int count(const char* key, long long dflt, long long lo = 1, long long hi = 100000000) const {
    const long long v = integer(key, dflt);
    if (v < lo || v > hi) fail(key, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return static_cast<int>(v);
  }
  std::string str(const char* key) const {
    const json& v = at(key);
    if (!v.is_string()) fail(key, "must be a string");
    return v.get<std::string>();
  }
  std::string str(const char* key, const std::string& dflt) const { return has(key) ? str(key) : dflt; }
  bool boolean(const char* key, bool dflt) const {
    if (!has(key)) return dflt;
    if (!at(key).is_boolean()) fail(key, "must be true or false");
    return at(key).get<bool>();
  }
  template <std::size_t N>
  std::array<double, N> vec(const char* key) const {
    const json& v = at(key);
    if (!v.is_array() || v.size() != N) fail(key, "must be an array of " + std::to_string(N) + " numbers");
    std::array<double, N> out{};
    for (std::size_t i = 0; i < N; ++i) {
      if (!v[i].is_number() || !std::isfinite(v[i].get<double>()))
        fail(std::string(key) + "[" + std::to_string(i) + "]", "must be a finite number");
      out[i] = v[i].get<double>();
    }
    return out;
  }
  glm::dvec3 vec3(const char* key, glm::dvec3 dflt) const {
    if (!has(key)) return dflt;
    const auto a = vec<3>(key);
    return {a[0], a[1], a[2]};
  }
  Obj child(const char* key) const { return Obj(at(key), field(key), src_); }
  const json& raw() const { return j_; }
  const std::string& path() const { return path_; }

 private:
  const json& j_;
  std::string path_;
  const std::string& src_;
};

int axis_from(const Obj& o, const char* key) {
  const std::string s = o.str(key, "y");
  if (s == "x") return 0;
  if (s == "y") return 1;
  if (s == "z") return 2;
  o.fail(key, "must be \"x\", \"y\" or \"z\"");
}

// The scene file's sections, each read into `s` (`top`: the whole file's object).
void read_models(const Obj& top, SceneDesc& s, const std::string& source) {
  if (top.has("models")) {
    const json& ms = top.at("models");
    if (!ms.is_object()) top.fail("models", "must be an object {id: {mesh, size, up}}");
    for (auto it = ms.begin(); it != ms.end(); ++it) {
      const Obj m(it.value(), "models." + it.key(), source);
      m.allow({"mesh", "size", "up"});
      ModelDesc d;
      d.id = it.key();
      d.mesh = m.str("mesh");
      if (d.mesh.empty() || d.mesh.find('/') != std::string::npos || d.mesh.find("..") != std::string::npos)
        m.fail("mesh", "must be a plain file name in the mesh directory (e.g. \"turbine.off\")");
      d.size = m.positive("size", 1.0);
      d.up_axis = axis_from(m, "up");
      s.models.push_back(d);
    }
  }
}

void read_floor(const Obj& top, SceneDesc& s) {
  if (top.has("floor")) {
    const Obj f = top.child("floor");
    f.allow({"size", "tiles", "center"});
    FloorDesc fl;
    const auto size = f.vec<2>("size");
    if (!(size[0] > 0 && size[1] > 0)) f.fail("size", "both extents must be > 0");
    fl.size_x = size[0];
    fl.size_z = size[1];
    if (f.has("tiles")) {
      const auto t = f.vec<2>("tiles");
      if (!(t[0] >= 1 && t[1] >= 1 && t[0] <= 4096 && t[1] <= 4096 && t[0] == std::floor(t[0]) && t[1] == std::floor(t[1])))
        f.fail("tiles", "must be two integers in [1, 4096]");
      fl.tiles_x = static_cast<int>(t[0]);
      fl.tiles_z = static_cast<int>(t[1]);
    }
    fl.center = f.vec3("center", glm::dvec3(0.0));
    s.floor = fl;
  }
}

void read_layout(const Obj& top, SceneDesc& s, const std::string& source) {
  auto find_model = [&](const std::string& id) {
    for (const ModelDesc& m : s.models)
      if (m.id == id) return true;
    return false;
  };
  if (top.has("layout")) {
    const json& ls = top.at("layout");
    if (!ls.is_array()) top.fail("layout", "must be an array of instance groups");
    for (std::size_t i = 0; i < ls.size(); ++i) {
      const Obj g(ls[i], "layout[" + std::to_string(i) + "]", source);
      g.allow({"model", "pattern", "count", "columns", "spacing", "origin", "area", "yaw", "random_yaw", "seed"});
      InstanceGroup d;
      d.model = g.str("model");
      if (!find_model(d.model)) g.fail("model", "unknown model '" + d.model + "' (declare it under \"models\")");
      d.pattern = g.str("pattern", "single");
      if (d.pattern != "single" && d.pattern != "row" && d.pattern != "grid" && d.pattern != "scatter")
        g.fail("pattern", "unknown pattern '" + d.pattern + "' (single, row, grid, scatter)");
      d.count = g.count("count", 1, 1, 100000);
      if (d.pattern == "single" && d.count != 1) g.fail("count", "pattern single places exactly 1 instance");
      d.columns = g.count("columns", d.pattern == "grid" ? static_cast<long long>(std::ceil(std::sqrt(double(d.count)))) : 1, 1, 100000);
      d.spacing = g.positive("spacing", 1.0);
      d.origin = g.vec3("origin", glm::dvec3(0.0));
      if (d.pattern == "scatter") {
        d.area = g.vec<4>("area");
        if (!(d.area[2] > d.area[0] && d.area[3] > d.area[1])) g.fail("area", "must be [x0, z0, x1, z1] with x1 > x0, z1 > z0");
      }
      d.yaw_deg = g.num("yaw", 0.0);
      d.random_yaw = g.boolean("random_yaw", false);
      d.seed = static_cast<std::uint64_t>(g.count("seed", 1, 0, 1ll << 40));
      s.groups.push_back(d);
    }
  }
}

void read_hierarchy(const Obj& top, SceneDesc& s) {
  if (top.has("hierarchy")) {
    const Obj h = top.child("hierarchy");
    h.allow({"target_nodes", "leaf_triangles"});
    if (h.has("target_nodes") == h.has("leaf_triangles")) h.fail("", "give exactly one of target_nodes, leaf_triangles");
    s.hierarchy.target_nodes = h.has("target_nodes") ? h.count("target_nodes", 0, 1, 10000000) : 0;
    s.hierarchy.leaf_triangles = h.has("leaf_triangles") ? h.count("leaf_triangles", 0, 1, 10000000) : 0;
  } else {
    s.hierarchy.leaf_triangles = 256;
  }
}

void read_projection(const Obj& top, SceneDesc& s) {
  const Obj p = top.child("projection");
  p.allow({"kind", "fovy", "aspect", "near", "far", "window", "eye_separation", "convergence", "zoom"});
  const std::string kind = p.str("kind");
  ProjectionDesc& d = s.projection;
  if (kind == "perspective") d.kind = ProjectionKind::perspective;
  else if (kind == "off-axis") d.kind = ProjectionKind::off_axis;
  else if (kind == "stereo") d.kind = ProjectionKind::stereo;
  else if (kind == "orthographic") d.kind = ProjectionKind::orthographic;
  else p.fail("kind", "unknown projection '" + kind + "' (perspective, off-axis, stereo, orthographic)");
  const bool fov_kind = d.kind == ProjectionKind::perspective || d.kind == ProjectionKind::stereo;
  const bool window_kind = !fov_kind;
  if (fov_kind) {
    d.fovy_deg = p.num("fovy", 60.0);
    if (!(d.fovy_deg > 0.0 && d.fovy_deg < 180.0)) p.fail("fovy", "must be in (0, 180) degrees");
    d.aspect = p.positive("aspect", 4.0 / 3.0);
    if (p.has("window")) p.fail("window", "only for off-axis and orthographic projections");
  } else {
    const auto w = p.vec<4>("window");
    d.left = w[0]; d.right = w[1]; d.bottom = w[2]; d.top = w[3];
    if (!(d.right > d.left && d.top > d.bottom)) p.fail("window", "must be [left, right, bottom, top] with right > left, top > bottom");
    if (p.has("fovy")) p.fail("fovy", "not used by a window projection (give \"window\")");
  }
  (void)window_kind;
  d.near_dist = p.num("near", 0.1);
  d.far_dist = p.num("far", 200.0);
  if (d.kind != ProjectionKind::orthographic && !(d.near_dist > 0.0)) p.fail("near", "must be > 0");
  if (!(d.far_dist > d.near_dist)) p.fail("far", "must be greater than near");
  if (d.kind == ProjectionKind::stereo) {
    d.eye_separation = p.num("eye_separation", 0.065);
    if (!(d.eye_separation >= 0.0)) p.fail("eye_separation", "must be >= 0");
    d.convergence = p.positive("convergence", 2.0);
  } else {
    if (p.has("eye_separation")) p.fail("eye_separation", "only for a stereo projection");
    if (p.has("convergence")) p.fail("convergence", "only for a stereo projection");
  }
  if (p.has("zoom")) {
    if (!fov_kind) p.fail("zoom", "a zoom changes fovy: only for perspective and stereo projections");
    const Obj z = p.child("zoom");
    z.allow({"fovy_end"});
    const double e = z.num("fovy_end");
    if (!(e > 0.0 && e < 180.0)) z.fail("fovy_end", "must be in (0, 180) degrees");
    d.zoom_fovy_end = e;
  }
}

void read_camera(const Obj& top, SceneDesc& s, const std::string& source) {
  const Obj c = top.child("camera");
  c.allow({"path", "frames", "speed", "turn", "seed", "eye", "yaw", "pitch", "bounds", "keyframes"});
  CameraPathDesc& d = s.camera;
  const std::string kind = c.str("path");
  const auto k = path_kind_from_string(kind);
  if (!k) c.fail("path", "unknown path kind '" + kind + "' (navigation, translation-rotation, rotation, translation, keyframes)");
  d.kind = *k;
  d.speed = c.num("speed", 0.1);
  if (!(d.speed >= 0.0)) c.fail("speed", "must be >= 0");
  d.turn_deg = c.num("turn", 1.0);
  if (!(d.turn_deg >= 0.0 && d.turn_deg < 90.0)) c.fail("turn", "must be in [0, 90) degrees per frame");
  d.seed = static_cast<std::uint64_t>(c.count("seed", 1, 0, 1ll << 40));
  d.eye = c.vec3("eye", d.eye);
  d.yaw_deg = c.num("yaw", 0.0);
  d.pitch_deg = c.num("pitch", 0.0);
  if (!(std::abs(d.pitch_deg) < 89.0)) c.fail("pitch", "must be in (-89, 89) degrees");
  if (c.has("bounds")) {
    const auto b = c.vec<4>("bounds");
    if (!(b[2] > b[0] && b[3] > b[1])) c.fail("bounds", "must be [x0, z0, x1, z1] with x1 > x0, z1 > z0");
    d.bounds = b;
  }
  if (d.kind == PathKind::keyframes) {
    const json& ks = c.at("keyframes");
    if (!ks.is_array() || ks.size() < 2) c.fail("keyframes", "must be an array of at least 2 keyframes");
    for (std::size_t i = 0; i < ks.size(); ++i) {
      const Obj kf(ks[i], c.field("keyframes") + "[" + std::to_string(i) + "]", source);
      kf.allow({"frame", "eye", "yaw", "pitch"});
      Keyframe f;
      f.frame = kf.count("frame", 0, 0, 10000000);
      f.eye = kf.vec3("eye", glm::dvec3(0.0));
      if (!kf.has("eye")) kf.fail("eye", "missing");
      f.yaw_deg = kf.num("yaw", 0.0);
      f.pitch_deg = kf.num("pitch", 0.0);
      if (!(std::abs(f.pitch_deg) < 89.0)) kf.fail("pitch", "must be in (-89, 89) degrees");
      if (i == 0 && f.frame != 0) kf.fail("frame", "the first keyframe must be frame 0");
      if (i > 0 && f.frame <= d.keyframes.back().frame) kf.fail("frame", "keyframes must have increasing frames");
      d.keyframes.push_back(f);
    }
    d.frames = d.keyframes.back().frame + 1;
    if (c.has("frames") && c.count("frames", 1) != d.frames)
      c.fail("frames", "keyframes end at frame " + std::to_string(d.frames - 1) + "; frames must be " + std::to_string(d.frames));
  } else {
    if (c.has("keyframes")) c.fail("keyframes", "only for path \"keyframes\"");
    d.frames = c.count("frames", 100, 1, 10000000);
  }
}

void read_moving(const Obj& top, SceneDesc& s, const std::string& source) {
  if (top.has("moving")) {
    const json& ms = top.at("moving");
    if (!ms.is_array()) top.fail("moving", "must be an array");
    for (std::size_t i = 0; i < ms.size(); ++i) {
      const Obj m(ms[i], "moving[" + std::to_string(i) + "]", source);
      m.allow({"group", "instances", "motion", "rate", "velocity", "center"});
      MovingDesc d;
      d.group = m.count("group", 0, 0, 1000000);
      if (d.group >= static_cast<int>(s.groups.size()))
        m.fail("group", "no layout group " + std::to_string(d.group) + " (the layout has " + std::to_string(s.groups.size()) + ")");
      const int n = s.groups[static_cast<std::size_t>(d.group)].count;
      if (m.has("instances")) {
        const json& is = m.at("instances");
        if (!is.is_array() || is.empty()) m.fail("instances", "must be a non-empty array of instance indices");
        for (std::size_t k = 0; k < is.size(); ++k) {
          if (!is[k].is_number_integer() || is[k].get<long long>() < 0 || is[k].get<long long>() >= n)
            m.fail("instances[" + std::to_string(k) + "]", "must be an instance index in [0, " + std::to_string(n) + ")");
          d.instances.push_back(is[k].get<int>());
        }
      }
      d.motion = m.str("motion");
      if (d.motion != "spin" && d.motion != "translate" && d.motion != "orbit")
        m.fail("motion", "unknown motion '" + d.motion + "' (spin, translate, orbit)");
      if (d.motion == "translate") {
        if (!m.has("velocity")) m.fail("velocity", "missing (translate needs a velocity per frame)");
        d.velocity = m.vec3("velocity", glm::dvec3(0.0));
        if (m.has("rate")) m.fail("rate", "translate uses velocity, not rate");
      } else {
        d.rate = m.num("rate");
        if (d.rate == 0.0) m.fail("rate", "must not be 0 (an object that does not move is not moving)");
        if (m.has("velocity")) m.fail("velocity", "only for motion translate");
      }
      d.center = m.vec3("center", glm::dvec3(0.0));
      s.moving.push_back(d);
    }
  }
}

}  // namespace

SceneDesc parse_scene(const json& j, const std::string& source) {
  SceneDesc s;
  s.file = source;
  const Obj top(j, "", source);
  top.allow({"format", "name", "description", "models", "floor", "layout", "hierarchy", "projection", "camera",
             "moving", "reference"});
  if (!top.has("format")) top.fail("format", std::string("missing (expected \"") + kSceneFormat + "\")");
  if (top.str("format") != kSceneFormat)
    top.fail("format", "is \"" + top.str("format") + "\"; this reader knows \"" + kSceneFormat + "\"");
  s.name = top.str("name");
  if (s.name.empty()) top.fail("name", "must not be empty");
  s.description = top.str("description", "");
  if (top.has("reference")) s.reference = top.at("reference");

  read_models(top, s, source);
  read_floor(top, s);
  read_layout(top, s, source);
  if (s.groups.empty() && !s.floor) top.fail("layout", "the scene has no geometry (no layout and no floor)");
  read_hierarchy(top, s);
  read_projection(top, s);
  read_camera(top, s, source);
  read_moving(top, s, source);
  return s;
}

namespace {

std::string limit_where(const InputLimitError& e) {
  return e.line() > 0 ? "line " + std::to_string(e.line()) + ": " : std::string();
}

}  // namespace

SceneDesc parse_scene_text(std::string_view text, const std::string& source) {
  json j;
  try {
    if (text.size() > kMaxSceneFileBytes)
      throw InputLimitError(0, "a text of " + std::to_string(text.size()) + " bytes, over the limit of " +
                                   byte_count_text(kMaxSceneFileBytes) + " for a scene file");
    check_line_lengths(text, kMaxSceneLineBytes, "a scene file");
    j = parse_json_limited(text, kMaxSceneDepth, "a scene file");
  } catch (const InputLimitError& e) {
    throw SceneError(source, "<json>", limit_where(e) + e.what());
  } catch (const json::parse_error& e) {
    int line = 1;
    for (std::size_t i = 0; i < std::min<std::size_t>(e.byte, text.size()); ++i) line += text[i] == '\n';
    throw SceneError(source, "<json>", "line " + std::to_string(line) + ": " + e.what());
  }
  return parse_scene(j, source);
}

SceneDesc load_scene(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::string text;
  try {
    text = read_file_limited(file, kMaxSceneFileBytes, "a scene file");
  } catch (const InputLimitError& e) {
    throw SceneError(name, "<file>", limit_where(e) + e.what());
  } catch (const std::system_error& e) {
    throw SceneError(name, "<file>", "cannot read the scene file: " + e.code().message());
  }
  return parse_scene_text(text, name);
}

}  // namespace cullproof::sim
