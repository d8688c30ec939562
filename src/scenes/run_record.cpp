// Runs in JSON and system records in the corpus (cullproof/scenes/scenes.hpp).
#include "cullproof/scenes/scenes.hpp"

#include "cullproof/io/files.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>

namespace cullproof::scenes {

namespace {

using json = nlohmann::json;

// A float as the case format writes it: a JSON number whose shortest decimal reads back to it.
json number(float x) { return json::parse(format_float(x)); }

json floats(const float* x, int n) {
  json a = json::array();
  for (int i = 0; i < n; ++i) a.push_back(number(x[i]));
  return a;
}

json object_json(const SceneObject& o) {
  return {{"id", o.id},
          {"world", json::parse(format_volume(o.world))},
          {"local", json::parse(format_volume(o.local))},
          {"transform", floats(&o.transform[0][0], 16)}};
}

struct Reader {
  std::string where;

  [[noreturn]] void fail(const std::string& field, const std::string& why) const {
    throw std::runtime_error(where + ": field '" + field + "': " + why);
  }
  const json& at(const json& j, const char* key, const std::string& field) const {
    const auto it = j.find(key);
    if (it == j.end()) fail(field + key, "missing");
    return *it;
  }
  void floats_into(const json& a, float* out, int n, const std::string& field) const {
    if (!a.is_array() || int(a.size()) != n) fail(field, "not an array of " + std::to_string(n) + " numbers");
    for (int i = 0; i < n; ++i) {
      const json& x = a[std::size_t(i)];
      try {
        if (!x.is_number()) throw std::invalid_argument("not a number");
        out[i] = parse_case_float(x.dump(), false);
      } catch (const std::exception& e) {
        fail(field + "[" + std::to_string(i) + "]", e.what());
      }
    }
  }
  // A volume or frustum through the case reader, with its checks, as a case of its own.
  Volume volume(const json& v, const std::string& field) const {
    try {
      return parse_case(json{{"id", "run"}, {"frustum", {{"planes", json::array({{1, 0, 0, 1}, {-1, 0, 0, 1}, {0, 1, 0, 1}, {0, -1, 0, 1}, {0, 0, 1, 1}, {0, 0, -1, 1}})}}}, {"volume", v}}.dump(), "run")
          .volume;
    } catch (const std::exception& e) {
      fail(field, e.what());
    }
  }
  CaseFrustum frustum(const json& f, const std::string& field) const {
    try {
      return parse_case(json{{"id", "run"}, {"frustum", f}, {"volume", {{"point", {0, 0, 0}}}}}.dump(), "run").frustum;
    } catch (const std::exception& e) {
      fail(field, e.what());
    }
  }
  SceneObject object(const json& o, const std::string& field) const {
    if (!o.is_object()) fail(field, "not an object");
    SceneObject out;
    const json& id = at(o, "id", field + ".");
    if (!id.is_number_unsigned() || id.get<std::uint64_t>() > 0xffffffffull) fail(field + ".id", "not an id (0 to 2^32 - 1)");
    out.id = id.get<std::uint32_t>();
    out.world = volume(at(o, "world", field + "."), field + ".world");
    out.local = volume(at(o, "local", field + "."), field + ".local");
    floats_into(at(o, "transform", field + "."), &out.transform[0][0], 16, field + ".transform");
    return out;
  }
};

}  // namespace

nlohmann::json to_json(const SceneRun& run) {
  json j;
  j["family"] = run.family;
  j["seed"] = run.seed;
  j["index"] = run.index;
  j["motion"] = run.motion;
  j["scene"] = run.scene.name;
  j["objects"] = json::array();
  for (const SceneObject& o : run.scene.objects) j["objects"].push_back(object_json(o));
  j["frames"] = json::array();
  for (const RunFrame& f : run.frames) {
    json fr = {{"frustum", json::parse(format_frustum(f.view.frustum))},
               {"view", floats(&f.view.view[0][0], 16)},
               {"projection", floats(&f.view.projection[0][0], 16)},
               {"eye", floats(&f.view.eye[0], 3)},
               {"axes", floats(&f.view.axes[0][0], 9)},
               {"perspective", f.view.perspective},
               {"camera", f.camera},
               {"moved", json::array()}};
    for (const SceneObject& m : f.moved) fr["moved"].push_back(object_json(m));
    j["frames"].push_back(std::move(fr));
  }
  return j;
}

SceneRun run_from_json(const nlohmann::json& j, const std::string& where) {
  const Reader r{where};
  if (!j.is_object()) r.fail("run", "not an object");
  SceneRun run;
  auto text = [&](const char* key) {
    const json& v = r.at(j, key, "run.");
    if (!v.is_string()) r.fail(std::string("run.") + key, "not a string");
    return v.get<std::string>();
  };
  auto count = [&](const char* key) {
    const json& v = r.at(j, key, "run.");
    if (!v.is_number_unsigned()) r.fail(std::string("run.") + key, "not a non-negative integer");
    return v.get<std::uint64_t>();
  };
  run.family = text("family");
  run.motion = text("motion");
  run.scene.name = text("scene");
  run.seed = count("seed");
  run.index = count("index");
  const json& objects = r.at(j, "objects", "run.");
  if (!objects.is_array()) r.fail("run.objects", "not an array");
  if (objects.size() > kMaxObjects) r.fail("run.objects", "more than " + std::to_string(kMaxObjects) + " objects");
  std::unordered_map<std::uint32_t, bool> ids;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    run.scene.objects.push_back(r.object(objects[i], "run.objects[" + std::to_string(i) + "]"));
    if (!ids.emplace(run.scene.objects.back().id, true).second)
      r.fail("run.objects[" + std::to_string(i) + "].id", std::to_string(run.scene.objects.back().id) + " twice");
  }
  const json& frames = r.at(j, "frames", "run.");
  if (!frames.is_array() || frames.empty()) r.fail("run.frames", "not a non-empty array");
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const std::string field = "run.frames[" + std::to_string(k) + "]";
    const json& f = frames[k];
    if (!f.is_object()) r.fail(field, "not an object");
    RunFrame fr;
    fr.view.frustum = r.frustum(r.at(f, "frustum", field + "."), field + ".frustum");
    r.floats_into(r.at(f, "view", field + "."), &fr.view.view[0][0], 16, field + ".view");
    r.floats_into(r.at(f, "projection", field + "."), &fr.view.projection[0][0], 16, field + ".projection");
    r.floats_into(r.at(f, "eye", field + "."), &fr.view.eye[0], 3, field + ".eye");
    r.floats_into(r.at(f, "axes", field + "."), &fr.view.axes[0][0], 9, field + ".axes");
    const json& persp = r.at(f, "perspective", field + ".");
    if (!persp.is_boolean()) r.fail(field + ".perspective", "not true or false");
    fr.view.perspective = persp.get<bool>();
    const json& camera = r.at(f, "camera", field + ".");
    if (!camera.is_string()) r.fail(field + ".camera", "not a string");
    fr.camera = camera.get<std::string>();
    const json& moved = r.at(f, "moved", field + ".");
    if (!moved.is_array()) r.fail(field + ".moved", "not an array");
    for (std::size_t i = 0; i < moved.size(); ++i) {
      const std::string mf = field + ".moved[" + std::to_string(i) + "]";
      fr.moved.push_back(r.object(moved[i], mf));
      if (!ids.count(fr.moved.back().id)) r.fail(mf + ".id", std::to_string(fr.moved.back().id) + " is not in the scene");
    }
    run.frames.push_back(std::move(fr));
  }
  return run;
}

std::filesystem::path write_system_record(const std::filesystem::path& dir, const System& system, const SceneRun& run,
                                          const Finding& failure, const std::string& reproduce) {
  json rec;
  rec["system"] = system.name;
  rec["claim"] = std::string(to_string(system.claim));
  rec["tolerance"] = system.tolerance;
  rec["origin"] = std::string(to_string(system.origin));
  rec["frame"] = failure.frame;
  rec["object"] = failure.id;
  rec["verdict"] = std::string(to_string(failure.verdict));
  rec["truth"] = std::string(to_string(failure.truth));
  rec["error"] = std::string(to_string(failure.error));
  rec["distance"] = failure.distance;
  rec["reproduce"] = reproduce;
  rec["run"] = to_json(run);
  const std::string text = rec.dump(1) + "\n";
  // The name: the error class and a hash of the record (FNV-1a 64), so the same failure found
  // again is the same file.
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char c : text) h = (h ^ c) * 0x100000001b3ull;
  char hash[17];
  std::snprintf(hash, sizeof hash, "%012llx", static_cast<unsigned long long>(h & 0xffffffffffffull));
  const std::filesystem::path file =
      dir / system.name / run.family / (std::string(to_string(failure.error)) + "-" + hash + ".json");
  write_file_atomic(file, text);
  return file;
}

SystemRecord read_system_record(const std::filesystem::path& file) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(file, ec);
  if (ec) throw std::runtime_error(file.string() + ": cannot read: " + ec.message());
  if (size > kMaxCaseFileBytes)
    throw std::runtime_error(file.string() + ": " + std::to_string(size) + " bytes, past the limit of " +
                             std::to_string(kMaxCaseFileBytes) + " (kMaxCaseFileBytes)");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(file.string() + ": cannot read");
  std::ostringstream text;
  text << in.rdbuf();
  json rec;
  try {
    rec = json::parse(text.str());
  } catch (const std::exception& e) {
    throw std::runtime_error(file.string() + ": not JSON: " + e.what());
  }
  SystemRecord out;
  const Reader r{file.string()};
  if (!rec.is_object()) r.fail("", "not an object");
  const json& name = r.at(rec, "system", "");
  if (!name.is_string()) r.fail("system", "not a string");
  out.system = name.get<std::string>();
  out.run = run_from_json(r.at(rec, "run", ""), file.string());
  const json& frame = r.at(rec, "frame", "");
  if (!frame.is_number_unsigned() || frame.get<std::uint64_t>() >= out.run.frames.size())
    r.fail("frame", "not a frame of the run (" + std::to_string(out.run.frames.size()) + " frames)");
  out.failure.frame = frame.get<std::size_t>();
  const json& object = r.at(rec, "object", "");
  if (!object.is_number_unsigned()) r.fail("object", "not an id");
  out.failure.id = object.get<std::uint32_t>();
  bool found = false;
  for (std::size_t i = 0; i < out.run.scene.objects.size(); ++i)
    if (out.run.scene.objects[i].id == out.failure.id) out.failure.object = i, found = true;
  if (!found) r.fail("object", std::to_string(out.failure.id) + " is not in the run's scene");
  auto verdict = [&](const char* key) {
    const json& v = r.at(rec, key, "");
    try {
      return visibility_from_string(v.is_string() ? v.get<std::string>() : std::string());
    } catch (const std::exception& e) {
      r.fail(key, e.what());
    }
  };
  out.failure.verdict = verdict("verdict");
  out.failure.truth = verdict("truth");
  const json& error = r.at(rec, "error", "");
  bool known = false;
  for (int c = 0; c < 5 && error.is_string(); ++c)
    if (error.get<std::string>() == to_string(ErrorClass(c))) out.failure.error = ErrorClass(c), known = true;
  if (!known) r.fail("error", "not an error class (correct, false-reject, false-inside, false-intersect, under-inside)");
  if (out.failure.error != error_class(out.failure.verdict, out.failure.truth, true) &&
      out.failure.error != error_class(out.failure.verdict, out.failure.truth, false))
    r.fail("error", error.get<std::string>() + " is not the error of verdict " + std::string(to_string(out.failure.verdict)) +
                        " where the truth is " + std::string(to_string(out.failure.truth)));
  out.failure.breaks_claim = true;  // a record is written for an object-frame that broke the claim
  if (rec.contains("distance") && rec["distance"].is_number()) out.failure.distance = rec["distance"].get<double>();
  out.record = std::move(rec);
  return out;
}

}  // namespace cullproof::scenes
