// The verification run (see cullproof/campaign.hpp).
#include "cullproof/campaign.hpp"

#include "cullproof/case_io.hpp"
#include "cullproof/corpus.hpp"
#include "cullproof/oracle.hpp"

#include <fmt/format.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <iostream>
#include <map>
#include <mutex>
#include <set>
#include <thread>
#include <unistd.h>

namespace cullproof {

std::string_view to_string(ErrorClass e) noexcept {
  switch (e) {
    case ErrorClass::correct: return "correct";
    case ErrorClass::false_reject: return "false-reject";
    case ErrorClass::false_inside: return "false-inside";
    case ErrorClass::false_intersect: return "false-intersect";
    case ErrorClass::under_inside: return "under-inside";
  }
  return "invalid";
}

ErrorClass error_class(Visibility verdict, Visibility truth, bool three_way) noexcept {
  if (verdict == truth) return ErrorClass::correct;
  if (!three_way && verdict == Visibility::intersecting && truth == Visibility::inside) return ErrorClass::correct;
  if (verdict == Visibility::outside) return ErrorClass::false_reject;
  if (verdict == Visibility::inside) return ErrorClass::false_inside;
  return truth == Visibility::outside ? ErrorClass::false_intersect : ErrorClass::under_inside;
}

bool violates_claim(Claim claim, ErrorClass e, double distance, double tolerance, double scale, bool float_exact) noexcept {
  if (e == ErrorClass::correct) return false;
  const bool hard = e == ErrorClass::false_reject || e == ErrorClass::false_inside;
  const bool within = distance <= tolerance * scale;  // a certified band, or the rounding allowance
  const bool allowed = within && !float_exact;         // the rounding allowance: only where things round
  switch (claim) {
    case Claim::certified_conservative: return hard;
    case Claim::certified_exact: return hard || !within;
    case Claim::conservative: return hard && !allowed;
    case Claim::exact: return !allowed;
    case Claim::none: return false;
  }
  return false;
}

namespace {

// Planes in double, normalised: the float planes for plane cases; for end-to-end cases the row
// sums of the float matrix taken in double. Degenerate planes: all space is dropped, nothing
// gives an empty list and `empty`.
struct DPlanes {
  std::vector<glm::dvec4> p;
  bool empty = false;
};

DPlanes double_planes(const CaseFrustum& f) {
  DPlanes out;
  std::array<glm::dvec4, 6> raw;
  if (f.matrix) {
    glm::dvec4 r[4];
    for (int i = 0; i < 4; ++i) r[i] = glm::dvec4(matrix_row(*f.matrix, i));
    raw[kLeft] = r[3] + r[0];
    raw[kRight] = r[3] - r[0];
    raw[kBottom] = r[3] + r[1];
    raw[kTop] = r[3] - r[1];
    const glm::dvec4 lower = f.depth.range == DepthRange::negative_one_to_one ? r[3] + r[2] : r[2];
    const glm::dvec4 upper = r[3] - r[2];
    raw[kNear] = f.depth.reversed_z ? upper : lower;
    raw[kFar] = f.depth.reversed_z ? lower : upper;
  } else {
    for (int k = 0; k < 6; ++k) raw[k] = glm::dvec4(glm::dvec3(f.planes[k].n), double(f.planes[k].d));
  }
  for (const glm::dvec4& q : raw) {
    const double len = glm::length(glm::dvec3(q));
    if (len == 0.0) {
      if (q.w < 0.0) out.empty = true;
      continue;
    }
    out.p.push_back(q / len);
  }
  return out;
}

// mu = max over t in [-1,1]^3 of min_j (s_j(c) + sum_i t_i g_ji), by enumerating the vertices of
// the LP in (t, mu): every choice of 4 active constraints among the planes and the 6 bounds.
double max_min_depth(const std::vector<glm::dvec4>& planes, const glm::dvec3& c, const glm::dvec3 (&e)[3]) {
  struct Row {
    double a[4];
    double b;  // a . (t, mu) >= b
  };
  std::vector<Row> rows;
  for (const glm::dvec4& q : planes) {
    const glm::dvec3 n(q);
    // s(c) + sum t_i (n . e_i) - mu >= 0
    rows.push_back(Row{{glm::dot(n, e[0]), glm::dot(n, e[1]), glm::dot(n, e[2]), -1.0}, -(glm::dot(n, c) + q.w)});
  }
  for (int i = 0; i < 3; ++i) {
    Row lo{{0, 0, 0, 0}, -1.0}, hi{{0, 0, 0, 0}, -1.0};
    lo.a[i] = 1.0;   // t_i >= -1
    hi.a[i] = -1.0;  // -t_i >= -1
    rows.push_back(lo);
    rows.push_back(hi);
  }
  const int n = int(rows.size());
  double best = -std::numeric_limits<double>::infinity();
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b)
      for (int c2 = b + 1; c2 < n; ++c2)
        for (int d = c2 + 1; d < n; ++d) {
          const int idx[4] = {a, b, c2, d};
          glm::dmat4 m;
          glm::dvec4 rhs;
          for (int r = 0; r < 4; ++r) {
            for (int k = 0; k < 4; ++k) m[k][r] = rows[std::size_t(idx[r])].a[k];
            rhs[r] = rows[std::size_t(idx[r])].b;
          }
          const double det = glm::determinant(m);
          if (std::abs(det) < 1e-14) continue;
          const glm::dvec4 y = glm::inverse(m) * rhs;
          bool ok = true;
          for (const Row& row : rows) {
            const double lhs = row.a[0] * y.x + row.a[1] * y.y + row.a[2] * y.z + row.a[3] * y.w;
            if (lhs < row.b - 1e-9 * (1.0 + std::abs(row.b))) {
              ok = false;
              break;
            }
          }
          if (ok) best = std::max(best, y.w);
        }
  return best;
}

}  // namespace

double backward_distance(const CaseFrustum& f, const Volume& v, ErrorClass e) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  if (e == ErrorClass::correct || std::holds_alternative<Sphere>(v)) return inf;
  const DPlanes dp = double_planes(f);
  if (dp.empty) return inf;
  glm::dvec3 c;
  glm::dvec3 ax[3] = {glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};
  if (const Point* p = std::get_if<Point>(&v)) {
    c = glm::dvec3(*p);
  } else if (const Aabb* a = std::get_if<Aabb>(&v)) {  // exact centre and half-extents in double
    c = (glm::dvec3(a->min) + glm::dvec3(a->max)) * 0.5;
    for (int i = 0; i < 3; ++i) ax[i][i] = (double(a->max[i]) - double(a->min[i])) * 0.5;
  } else {
    const Obb& b = std::get<Obb>(v);
    c = glm::dvec3(b.center);
    for (int i = 0; i < 3; ++i) ax[i] = glm::dvec3(b.axes[i]) * double(b.half[i]);
  }
  // Extremes of each plane over the box: s_j(c) +- sum_i |n_j . e_i|.
  double protrusion = -inf, clearance = inf;
  for (const glm::dvec4& q : dp.p) {
    const glm::dvec3 n(q);
    const double s = glm::dot(n, c) + q.w;
    const double r = std::abs(glm::dot(n, ax[0])) + std::abs(glm::dot(n, ax[1])) + std::abs(glm::dot(n, ax[2]));
    protrusion = std::max(protrusion, -(s - r));
    clearance = std::min(clearance, s - r);
  }
  switch (e) {
    case ErrorClass::false_inside: return std::max(0.0, protrusion);
    case ErrorClass::under_inside: return std::max(0.0, clearance);
    case ErrorClass::false_reject: return std::max(0.0, max_min_depth(dp.p, c, ax));
    case ErrorClass::false_intersect: return std::max(0.0, -max_min_depth(dp.p, c, ax));
    default: return inf;
  }
}

double error_distance(const CaseFrustum& f, const Volume& v, ErrorClass e, double oracle_distance) {
  return std::min(oracle_distance, backward_distance(f, v, e));
}

bool VerifyResult::claim_broken() const noexcept {
  for (const auto& d : distributions)
    for (const auto& m : d.methods)
      if (m.origin != Origin::published && m.refuted()) return true;
  return false;
}

namespace {

// Why an answer is not one the method may give, or "" when it is.
std::string answer_problem(const Method& m, const Answer& a) {
  if (a && unsigned(*a) > unsigned(Visibility::inside))
    return fmt::format("method '{}' answered {}, which is not a verdict (0 outside, 1 intersecting, 2 inside)", m.name,
                       unsigned(*a));
  if (a && *a == Visibility::inside && !m.three_way)
    return "method '" + m.name + "' answered inside, but it is two-way (visible or outside)";
  return "";
}

// Calls into a method, turning what it throws into a runtime_error naming it.
template <class F>
void call_method(const Method& m, const char* what, F&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    throw std::runtime_error("method '" + m.name + "' threw" + what + ": " + e.what());
  } catch (...) {
    throw std::runtime_error("method '" + m.name + "' threw" + what + " something that is not a std::exception");
  }
}

// A fault on a camera path and where it happened.
struct PathFault : std::runtime_error {
  PathFault(const std::string& what, std::size_t f, std::size_t o) : std::runtime_error(what), frame(f), object(o) {}
  std::size_t frame, object;
};

// Runs method `m` over frames[first..last] of a camera path with `objects` (see the contract in
// cullproof/methods.hpp), after reset() when `reset`; sink(frame, object, answer) for each object
// it takes, every frame. Throws PathFault.
template <class Sink>
void run_path(const Method& m, const std::vector<CaseFrustum>& frames, std::size_t first, std::size_t last,
              const std::vector<Volume>& objects, Sink&& sink, bool reset = true) {
  std::vector<std::size_t> order;  // objects the method takes, in path order
  std::vector<Point> points;
  std::vector<Sphere> spheres;
  std::vector<Aabb> aabbs;
  std::vector<Obb> obbs;
  std::vector<std::size_t> of_kind[4];  // path index of each, by kind
  for (std::size_t o = 0; o < objects.size(); ++o) {
    if (!m.takes(objects[o])) continue;
    order.push_back(o);
    std::visit(
        [&](const auto& x) {
          using T = std::decay_t<decltype(x)>;
          if constexpr (std::is_same_v<T, Point>) points.push_back(x), of_kind[0].push_back(o);
          else if constexpr (std::is_same_v<T, Sphere>) spheres.push_back(x), of_kind[1].push_back(o);
          else if constexpr (std::is_same_v<T, Aabb>) aabbs.push_back(x), of_kind[2].push_back(o);
          else obbs.push_back(x), of_kind[3].push_back(o);
        },
        objects[o]);
  }
  if (order.empty()) return;
  auto guarded = [&](std::size_t f, std::size_t o, const char* what, auto&& fn) {
    try {
      call_method(m, what, fn);
    } catch (const std::runtime_error& e) {
      throw PathFault(e.what(), f, o);
    }
  };
  if (reset) guarded(first, order[0], " in reset()", [&] { m.reset(); });
  std::vector<Answer> answers;
  for (std::size_t f = first; f <= last; ++f) {
    std::unique_ptr<PreparedFrustum> p;
    guarded(f, order[0], " in prepare", [&] { p = m.prepare(frames[f]); });
    if (!p) {
      for (std::size_t o : order) sink(f, o, Answer{});
      continue;
    }
    if (m.has_batch()) {
      auto batch = [&](const auto& vols, const std::vector<std::size_t>& idx) {
        if (vols.empty()) return;
        answers.assign(vols.size(), Answer{});
        guarded(f, idx[0], " in classify_batch", [&] { p->classify_batch(vols.data(), vols.size(), answers.data()); });
        for (std::size_t j = 0; j < vols.size(); ++j) {
          const std::string problem = answer_problem(m, answers[j]);
          if (!problem.empty()) throw PathFault(problem, f, idx[j]);
          sink(f, idx[j], answers[j]);
        }
      };
      batch(points, of_kind[0]);
      batch(spheres, of_kind[1]);
      batch(aabbs, of_kind[2]);
      batch(obbs, of_kind[3]);
    } else {
      for (std::size_t o : order) {
        Answer a;
        guarded(f, o, "", [&] { a = p->classify(objects[o]); });
        const std::string problem = answer_problem(m, a);
        if (!problem.empty()) throw PathFault(problem, f, o);
        sink(f, o, a);
      }
    }
  }
}

}  // namespace

Answer checked_classify(const Method& m, const CaseFrustum& f, const Volume& v) {
  if (!m.takes(v)) return std::nullopt;
  Answer a;
  call_method(m, "", [&] { a = m.classify(f, v); });
  const std::string problem = answer_problem(m, a);
  if (!problem.empty()) throw std::runtime_error(problem);
  return a;
}

Answer checked_classify_path(const Method& m, const PathCase& p) {
  if (p.frames.empty() || p.object >= p.objects.size())
    throw std::invalid_argument("checked_classify_path: a path case needs a frame and its object among the objects");
  Answer out;
  const std::size_t last = p.frames.size() - 1;
  try {
    // A stateful method over the whole path from a reset; any other over the last frame alone.
    run_path(
        m, p.frames, m.stateful ? 0 : last, last, p.objects,
        [&](std::size_t f, std::size_t o, const Answer& a) {
          if (f == last && o == p.object) out = a;
        },
        /*reset=*/m.stateful);
  } catch (const PathFault& e) {
    throw std::runtime_error(fmt::format("{} (camera path frame {}, object {})", e.what(), e.frame, e.object));
  }
  return out;
}

nlohmann::json to_json(const PathCase& p) {
  nlohmann::json j;
  j["motion"] = p.motion;
  j["object"] = p.object;
  j["frames"] = nlohmann::json::array();
  for (const CaseFrustum& f : p.frames) j["frames"].push_back(nlohmann::json::parse(format_frustum(f)));
  j["objects"] = nlohmann::json::array();
  for (const Volume& v : p.objects) j["objects"].push_back(nlohmann::json::parse(format_volume(v)));
  return j;
}

PathCase path_from_json(const nlohmann::json& j, const std::string& where) {
  auto bad = [&](const std::string& field, const std::string& why) {
    return std::runtime_error(where + ": field 'path." + field + "': " + why);
  };
  if (!j.is_object()) throw bad("", "not an object");
  PathCase p;
  if (auto it = j.find("motion"); it != j.end() && it->is_string()) p.motion = it->get<std::string>();
  const auto fr = j.find("frames"), ob = j.find("objects"), at = j.find("object");
  if (fr == j.end() || !fr->is_array() || fr->empty()) throw bad("frames", "missing or not a non-empty array");
  if (ob == j.end() || !ob->is_array() || ob->empty()) throw bad("objects", "missing or not a non-empty array");
  if (at == j.end() || !at->is_number_unsigned()) throw bad("object", "missing or not an index");
  // Each frame and object is read by the case reader, with its checks, as a case of its own.
  const nlohmann::json any_volume = {{"point", {0, 0, 0}}};
  for (std::size_t k = 0; k < fr->size(); ++k) {
    try {
      p.frames.push_back(parse_case(nlohmann::json{{"id", "path"}, {"frustum", (*fr)[k]}, {"volume", any_volume}}.dump(), "recorded path").frustum);
    } catch (const std::exception& e) {
      throw bad(fmt::format("frames[{}]", k), e.what());
    }
  }
  for (std::size_t k = 0; k < ob->size(); ++k) {
    try {
      p.objects.push_back(parse_case(nlohmann::json{{"id", "path"}, {"frustum", (*fr)[0]}, {"volume", (*ob)[k]}}.dump(), "recorded path").volume);
    } catch (const std::exception& e) {
      throw bad(fmt::format("objects[{}]", k), e.what());
    }
  }
  p.object = at->get<std::size_t>();
  if (p.object >= p.objects.size())
    throw bad("object", fmt::format("{} is not among the {} objects", p.object, p.objects.size()));
  return p;
}

std::pair<double, double> wilson95(std::uint64_t k, std::uint64_t n) noexcept {
  if (n == 0) return {0.0, 0.0};
  const double z = 1.959963984540054, p = double(k) / double(n), nn = double(n);
  const double denom = 1 + z * z / nn, centre = (p + z * z / (2 * nn)) / denom;
  const double half = z * std::sqrt(p * (1 - p) / nn + z * z / (4 * nn * nn)) / denom;
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

namespace {

using Clock = std::chrono::steady_clock;
using gen::GenCase;

// Progress bar on stderr: a redrawn line on a terminal, a line per 10% otherwise.
class Progress {
 public:
  Progress(bool on, std::uint64_t total) : on_(on), total_(total), tty_(::isatty(2) != 0) {
    if (on_) thread_ = std::thread([this] { loop(); });
  }
  ~Progress() { finish(); }
  void add(std::uint64_t n) { done_.fetch_add(n, std::memory_order_relaxed); }
  void label(std::string s) {
    std::lock_guard<std::mutex> g(m_);
    label_ = std::move(s);
  }
  void finish() {
    if (!thread_.joinable()) return;
    {
      std::lock_guard<std::mutex> g(m_);
      stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
    draw(true);
  }

 private:
  void loop() {
    std::unique_lock<std::mutex> g(m_);
    while (!stop_) {
      cv_.wait_for(g, std::chrono::milliseconds(tty_ ? 200 : 1000));
      if (stop_) break;
      g.unlock();
      draw(false);
      g.lock();
    }
  }
  void draw(bool last) {
    const std::uint64_t d = std::min(done_.load(), total_);
    const double f = total_ ? double(d) / double(total_) : 1.0;
    const double secs = std::chrono::duration<double>(Clock::now() - start_).count();
    std::string lbl;
    {
      std::lock_guard<std::mutex> g(m_);
      lbl = label_;
    }
    if (tty_) {
      const int w = 30, filled = int(f * w);
      std::cerr << fmt::format("\r[{}{}] {:5.1f}% {}/{} cases {:.0f}s {:<24}", std::string(filled, '#'),
                               std::string(w - filled, '.'), 100 * f, d, total_, secs, lbl)
                << (last ? "\n" : "") << std::flush;
    } else {
      const int decile = int(f * 10);
      if (decile > last_decile_ || last) {
        last_decile_ = decile;
        std::cerr << fmt::format("verify: {:3.0f}% ({}/{} cases, {:.0f}s) {}\n", 100 * f, d, total_, secs, lbl);
      }
    }
  }
  bool on_;
  std::uint64_t total_;
  bool tty_;
  std::atomic<std::uint64_t> done_{0};
  std::mutex m_;
  std::condition_variable cv_;
  bool stop_ = false;
  std::string label_;
  int last_decile_ = -1;
  Clock::time_point start_ = Clock::now();
  std::thread thread_;
};

struct CaseOutcome {
  Visibility truth{};
  std::vector<std::int8_t> verdict;  // -1: method does not apply; else Visibility
  double distance = std::numeric_limits<double>::quiet_NaN();  // oracle distance, erring cases only
  double scale = 0.0;                                          // gen::case_scale, erring cases only
  bool float_exact = false;                                    // gen::float_exact
};

std::optional<Visibility> run_method(const Method& m, const GenCase& c) {
  return checked_classify(m, c.frustum, c.volume);
}

// Shrinks a mismatch: the simplest case of the Shrinkable tree on which `m` still makes an error
// of class `cls` (and, for a claim violation, still violates the claim), within `budget` steps.
GenCase shrink(const rc::Shrinkable<gen::GenCase>& start, const Method& m, ErrorClass cls, bool violation, int budget) {
  rc::Shrinkable<gen::GenCase> cur = start;
  bool progress = true;
  while (progress && budget > 0) {
    progress = false;
    auto seq = cur.shrinks();
    while (auto next = seq.next()) {
      if (--budget <= 0) break;
      const GenCase c = next->value();
      try {
        validate(c.volume);
        const auto v = run_method(m, c);
        if (!v) continue;
        if (error_class(*v, oracle::truth(c.frustum, c.volume), m.three_way) != cls) continue;
        // A claim violation must shrink to a claim violation (not to a rounding-level error).
        if (violation) {
          const oracle::Result r = oracle::classify(c.frustum, c.volume, oracle::Options{true, true, false});
          if (!violates_claim(m.claim, cls, error_distance(c.frustum, c.volume, cls, r.distance), m.tolerance,
                              gen::case_scale(c.frustum, c.volume), gen::float_exact(c.frustum, c.volume)))
            continue;
        }
        {
          cur = *next;
          progress = true;
          break;
        }
      } catch (const std::exception&) {
        continue;  // an invalid shrink (e.g. a degenerate axis): not a candidate
      }
    }
  }
  return cur.value();
}

// Shrinks a stateful method's error on a camera path: the object alone if the error stays without
// the others, then the fewest frames before the one judged that keep it (the case judged, and so
// its truth and distance, does not change).
PathCase shrink_path(PathCase p, const Method& m, ErrorClass cls, Visibility truth, int budget) {
  auto still = [&](const PathCase& c) {
    try {
      const Answer a = checked_classify_path(m, c);
      return a && error_class(*a, truth, m.three_way) == cls;
    } catch (const std::exception&) {
      return false;  // a fault is reported by the run itself, not found by shrinking
    }
  };
  if (p.objects.size() > 1 && budget-- > 0) {
    PathCase q = p;
    q.objects = {p.volume()};
    q.object = 0;
    if (still(q)) p = std::move(q);
  }
  for (std::size_t drop = p.frames.size() - 1; drop >= 1 && budget-- > 0; --drop) {
    PathCase q = p;
    q.frames.erase(q.frames.begin(), q.frames.begin() + std::ptrdiff_t(drop));
    if (still(q)) {
      p = std::move(q);
      break;
    }
  }
  return p;
}

std::string reproduce_command(std::uint64_t seed, gen::Distribution d, std::uint64_t index, const Method& m) {
  // A user's method is not in the command-line program: its test reruns the case from the
  // environment (cullproof/gtest.hpp).
  if (!m.program.empty())
    return fmt::format("cullproof verify --seed {} --distribution {} --index {} --external {} -- {}", seed, gen::to_string(d),
                       index, m.name, m.program);
  if (m.origin == Origin::user)
    return fmt::format("CULLPROOF_SEED={} CULLPROOF_DISTRIBUTION={} CULLPROOF_INDEX={} (environment of the test that verifies {})",
                       seed, gen::to_string(d), index, m.name);
  return fmt::format("cullproof verify --seed {} --distribution {} --index {} --method {}", seed, gen::to_string(d), index,
                     m.name);
}

// What write_corpus_case recorded: the case's id, whether this run wrote it (false: the same
// geometry was recorded already, by an earlier run or meanwhile by another thread), and whether
// the record breaks the method's claim (its "violates_claim").
struct CorpusRecord {
  std::string id;
  bool written = false;
  bool violates = false;
};

// Writes one corpus case unless the same geometry is already recorded.
// `path`: the camera path a stateful method's error needs to reproduce, recorded with the case
// (the other stateful methods' verdicts are taken over it too).
CorpusRecord write_corpus_case(const std::filesystem::path& dir, const GenCase& g, const Method& m, Visibility verdict,
                              gen::Distribution d, std::uint64_t seed, std::uint64_t index,
                              const std::vector<Method>& all, const PathCase* path = nullptr) {
  const oracle::Result r = oracle::classify(g.frustum, g.volume);
  const ErrorClass cls = error_class(verdict, r.truth, m.three_way);
  const std::string hash = geometry_hash(g.frustum, g.volume);
  Case c;
  c.id = fmt::format("{}-{}-{}", m.name, to_string(cls), hash);
  c.frustum = g.frustum;
  c.volume = g.volume;
  c.truth = r.truth;
  c.note = fmt::format("{} says {} where the truth is {} ({}); found by the {} distribution", m.name,
                       to_string(verdict), to_string(r.truth), to_string(cls), gen::to_string(d));
  nlohmann::json& x = c.extra;
  x["method"] = m.name;
  x["verdict"] = std::string(to_string(verdict));
  x["class"] = to_string(cls);
  x["claim"] = std::string(to_string(m.claim));
  x["origin"] = std::string(to_string(m.origin));
  if (!m.three_way) x["two_way"] = true;
  const double scale = gen::case_scale(g.frustum, g.volume);
  const double backward = backward_distance(g.frustum, g.volume, cls);
  const bool exact_case = gen::float_exact(g.frustum, g.volume);
  const bool violates = violates_claim(m.claim, cls, std::min(r.distance, backward), m.tolerance, scale, exact_case);
  x["violates_claim"] = violates;
  x["float_exact"] = exact_case;
  x["backward_distance"] = std::isfinite(backward) ? nlohmann::json(backward) : nlohmann::json(nullptr);
  x["distribution"] = std::string(gen::to_string(d));
  x["distance"] = std::isfinite(r.distance) ? nlohmann::json(r.distance) : nlohmann::json(nullptr);
  x["distance_kind"] = oracle::to_string(r.distance_kind);
  x["scale"] = scale;
  x["scene_size"] = g.scene_size;
  x["witness"] = r.witness;
  x["seed"] = seed;
  x["index"] = index;
  x["reproduce"] = reproduce_command(seed, d, index, m);
  if (path) x["path"] = to_json(*path);
  nlohmann::json verdicts = nlohmann::json::object();
  for (const Method& o : all)
    if (auto v = path ? checked_classify_path(o, *path) : run_method(o, g))
      verdicts[o.name] = std::string(to_string(*v));
  x["verdicts"] = verdicts;
  const auto file = dir / m.name / gen::to_string(d) / fmt::format("{}-{}.json", to_string(cls), hash);
  if (std::filesystem::exists(file)) return {c.id, false, violates};
  try {
    write_case_file(file, c, /*overwrite=*/false);
  } catch (const std::runtime_error&) {
    if (std::filesystem::exists(file)) return {c.id, false, violates};  // written meanwhile: the same geometry
    throw;
  }
  return {c.id, true, violates};
}

// A frame's volumes split by kind, for classify_batch.
struct KindedFrame {
  CaseFrustum frustum;
  std::vector<Point> points;
  std::vector<Sphere> spheres;
  std::vector<Aabb> aabbs;
  std::vector<Obb> obbs;
  bool continues = false;  // gen::Frame::continues
  std::size_t size() const noexcept { return points.size() + spheres.size() + aabbs.size() + obbs.size(); }
};

KindedFrame split(gen::Frame f) {
  KindedFrame k;
  k.frustum = std::move(f.frustum);
  k.continues = f.continues;
  for (const Volume& v : f.volumes)
    std::visit(
        [&](const auto& x) {
          using T = std::decay_t<decltype(x)>;
          if constexpr (std::is_same_v<T, Point>) k.points.push_back(x);
          else if constexpr (std::is_same_v<T, Sphere>) k.spheres.push_back(x);
          else if constexpr (std::is_same_v<T, Aabb>) k.aabbs.push_back(x);
          else k.obbs.push_back(x);
        },
        v);
  return k;
}

struct Timing {
  double ns_per_test = std::numeric_limits<double>::quiet_NaN();
  double ns_setup_per_frame = std::numeric_limits<double>::quiet_NaN();
  double ns_per_test_own = std::numeric_limits<double>::quiet_NaN();
};

// Classifies a frame's volumes through classify_batch, kind by kind; answers sized for it.
unsigned classify_frame(PreparedFrustum& p, const KindedFrame& f, std::vector<Answer>& answers) {
  Answer* a = answers.data();
  if (!f.points.empty()) p.classify_batch(f.points.data(), f.points.size(), a), a += f.points.size();
  if (!f.spheres.empty()) p.classify_batch(f.spheres.data(), f.spheres.size(), a), a += f.spheres.size();
  if (!f.aabbs.empty()) p.classify_batch(f.aabbs.data(), f.aabbs.size(), a), a += f.aabbs.size();
  if (!f.obbs.empty()) p.classify_batch(f.obbs.data(), f.obbs.size(), a), a += f.obbs.size();
  return (answers[0] ? unsigned(*answers[0]) : 3u) + (answers[f.size() - 1] ? unsigned(*answers[f.size() - 1]) : 3u);
}

constexpr double kMinTimingSeconds = 0.02;

// A stateful method runs as it would in an engine: frame after frame, each prepared and then
// classified (reset() where a frame does not continue the previous one's path), the two phases
// timed apart with a clock read around each (about 20 ns a read, in the set-up figure).
Timing time_stateful(const Method& m, const std::vector<KindedFrame>& frames) {
  Timing t;
  std::size_t largest = 0;
  for (const KindedFrame& f : frames) largest = std::max(largest, f.size());
  if (largest == 0) return t;
  std::vector<Answer> answers(largest);
  unsigned sink = 0;
  std::uint64_t tests = 0, prepared = 0;
  double prep_secs = 0.0, cls_secs = 0.0;
  do {
    for (const KindedFrame& f : frames) {
      if (!f.continues) m.reset();
      if (f.size() == 0) continue;
      const auto t0 = Clock::now();
      const auto p = m.prepare(f.frustum);
      const auto t1 = Clock::now();
      prep_secs += std::chrono::duration<double>(t1 - t0).count();
      if (!p) continue;
      ++prepared;
      sink += classify_frame(*p, f, answers);
      cls_secs += std::chrono::duration<double>(Clock::now() - t1).count();
      tests += f.size();
    }
  } while (prepared > 0 && prep_secs + cls_secs < kMinTimingSeconds);
  static std::atomic<unsigned> keep{0};
  keep += sink;
  if (prepared == 0) return t;
  t.ns_setup_per_frame = prep_secs * 1e9 / double(prepared);
  t.ns_per_test = cls_secs * 1e9 / double(tests);
  return t;
}

// Times prepare once per frame and classify_batch over each frame's volumes, in passes over the
// frames until each measure has run for at least 20 ms. Frames the method does not apply to
// are left out.
Timing time_classify(const Method& m, const std::vector<KindedFrame>& frames) {
  constexpr double kMinSeconds = kMinTimingSeconds;
  Timing t;
  // The frames the method applies to, each with its state for the classify passes.
  std::vector<const KindedFrame*> mine;
  std::vector<std::unique_ptr<PreparedFrustum>> states;
  std::size_t volumes = 0, largest = 0;
  for (const KindedFrame& f : frames) {
    if (f.size() == 0) continue;
    auto p = m.prepare(f.frustum);
    if (!p) continue;
    mine.push_back(&f);
    states.push_back(std::move(p));
    volumes += f.size();
    largest = std::max(largest, f.size());
  }
  if (mine.empty()) return t;
  std::size_t prepared = 0;
  const auto t0 = Clock::now();
  double secs = 0.0;
  do {
    for (const KindedFrame* f : mine) {
      const auto p = m.prepare(f->frustum);
      prepared += p != nullptr;
    }
    secs = std::chrono::duration<double>(Clock::now() - t0).count();
  } while (secs < kMinSeconds);
  t.ns_setup_per_frame = secs * 1e9 / double(prepared);

  std::vector<Answer> answers(largest);
  unsigned sink = 0;
  std::uint64_t tests = 0;
  const auto t1 = Clock::now();
  secs = 0.0;
  do {
    for (std::size_t i = 0; i < mine.size(); ++i) sink += classify_frame(*states[i], *mine[i], answers);
    tests += volumes;
    secs = std::chrono::duration<double>(Clock::now() - t1).count();
  } while (secs < kMinSeconds);
  static std::atomic<unsigned> keep{0};
  keep += sink;  // keeps the calls from being optimised away
  t.ns_per_test = secs * 1e9 / double(tests);
  return t;
}

// Both phases timed as the method runs (stateful ones frame after frame), and what the method
// reports of its own time over the same frames.
Timing time_method(const Method& m, const std::vector<KindedFrame>& frames) {
  (void)m.take_own_timing();  // what the method reported before the timed frames
  Timing t = m.stateful ? time_stateful(m, frames) : time_classify(m, frames);
  const auto [own_ns, own_volumes] = m.take_own_timing();
  if (own_volumes > 0) t.ns_per_test_own = own_ns / double(own_volumes);
  return t;
}

// Saves the case that made a method fault and builds the error. Faults are searched from the
// smallest case index, so the same seed reports the same case.
[[noreturn]] void fault(const VerifyOptions& opt, const Method& m, gen::Distribution d, std::uint64_t index,
                        const GenCase& g, const std::string& problem, const PathCase* path = nullptr) {
  Case c;
  c.id = fmt::format("{}-fault-{}", m.name, geometry_hash(g.frustum, g.volume));
  c.frustum = g.frustum;
  c.volume = g.volume;
  c.note = problem;
  c.extra["method"] = m.name;
  c.extra["fault"] = problem;
  c.extra["distribution"] = std::string(gen::to_string(d));
  c.extra["seed"] = opt.seed;
  c.extra["index"] = index;
  c.extra["reproduce"] = reproduce_command(opt.seed, d, index, m);
  if (path) c.extra["path"] = to_json(*path);
  std::optional<std::filesystem::path> dir = opt.faults;
  if (!dir && opt.corpus) dir = *opt.corpus / "faults";
  std::optional<std::filesystem::path> saved;
  std::string where = "not saved (no corpus folder)";
  if (dir) {
    const auto file = *dir / m.name / fmt::format("{}.json", geometry_hash(g.frustum, g.volume));
    try {
      if (!std::filesystem::exists(file)) write_case_file(file, c, /*overwrite=*/false);
      saved = file;
      where = "saved to " + file.string();
    } catch (const std::exception& e) {
      where = std::string("could not be saved: ") + e.what();
    }
  }
  const std::string line = format_case(c);
  const nlohmann::json j = nlohmann::json::parse(line);
  throw MethodFault(fmt::format("{}\n  on case {} of distribution {} (seed {}); the run is incomplete, no results are reported\n"
                                "  reproduce: {}\n  case {}\n  {}",
                                problem, index, gen::to_string(d), opt.seed, reproduce_command(opt.seed, d, index, m),
                                where, line),
                    m.name, j, saved);
}

}  // namespace

VerifyResult run_verify(const VerifyOptions& opt) { return run_verify(opt, builtin_methods(opt.methods)); }

VerifyResult run_verify(const VerifyOptions& opt, const std::vector<Method>& ms) {
  const auto t_start = Clock::now();
  {
    std::set<std::string> names;
    for (const Method& m : ms)
      if (!names.insert(m.name).second) throw std::invalid_argument("two methods are named '" + m.name + "'");
  }
  const int threads = opt.threads > 0 ? opt.threads : int(std::max(1u, std::thread::hardware_concurrency()));
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));

  VerifyResult result;
  result.options = opt;
  const std::uint64_t per = opt.only_index ? 1 : opt.cases;
  Progress progress(opt.progress, per * opt.distributions.size());

  for (gen::Distribution d : opt.distributions) {
    progress.label(std::string(gen::to_string(d)));
    const std::uint64_t first = opt.only_index ? *opt.only_index : 0;
    std::vector<GenCase> cases(per);
    std::vector<CaseOutcome> out(per);
    const auto st0 = oracle::stats();
    // RapidCheck's generation context is process-global (not thread-safe): cases are drawn on
    // this thread, the oracle and the methods run in parallel.
    // Camera-path cases come path by path: each path is drawn once (and kept for the stateful
    // methods, which run over it).
    const bool on_paths = d == gen::Distribution::camera_path;
    std::map<std::uint64_t, gen::CameraPath> paths;
    for (std::uint64_t i = 0; i < per; ++i) {
      if (on_paths) {
        const gen::PathIndex at = gen::path_index(first + i);
        auto it = paths.find(at.path);
        if (it == paths.end()) it = paths.emplace(at.path, gen::draw_path(opt.seed, at.path)).first;
        cases[i] = gen::path_case(it->second, at.frame, at.object);
      } else {
        cases[i] = gen::draw(d, opt.seed, first + i).value();
      }
      validate(cases[i].volume);
    }
    // The path case of a stateful method at case index `index` of this run's paths: the frames up
    // to its own, every object.
    auto path_case_at = [&](std::uint64_t index) {
      const gen::PathIndex at = gen::path_index(index);
      const gen::CameraPath& cp = paths.at(at.path);
      PathCase pc;
      pc.frames.assign(cp.frames.begin(), cp.frames.begin() + std::ptrdiff_t(at.frame + 1));
      pc.objects = cp.objects;
      pc.object = at.object;
      pc.motion = cp.motion;
      return pc;
    };
    // A fault is kept for the smallest case index it happens on (the same seed reports the same
    // case whatever the threads do). Indices are the distribution's (a stateful method on a
    // camera path may fault on a frame before the first case asked for).
    std::mutex fault_mutex;
    std::uint64_t fault_index = std::numeric_limits<std::uint64_t>::max();
    std::size_t fault_method = 0;
    std::string fault_problem;
    auto note_fault = [&](std::uint64_t index, std::size_t k, const std::string& problem) {
      std::lock_guard<std::mutex> g(fault_mutex);
      if (index < fault_index || (index == fault_index && k < fault_method)) {
        fault_index = index;
        fault_method = k;
        fault_problem = problem;
      }
    };
    auto run_one = [&](std::uint64_t i, std::size_t k) {
      try {
        const auto v = run_method(ms[k], cases[i]);
        out[i].verdict[k] = v ? std::int8_t(*v) : std::int8_t(-1);
      } catch (const std::exception& e) {
        out[i].verdict[k] = -1;
        note_fault(first + i, k, e.what());
      }
    };
    tbb::parallel_for(tbb::blocked_range<std::uint64_t>(0, per, 64), [&](const tbb::blocked_range<std::uint64_t>& r) {
      for (std::uint64_t i = r.begin(); i != r.end(); ++i) {
        out[i].truth = oracle::truth(cases[i].frustum, cases[i].volume);
        out[i].float_exact = gen::float_exact(cases[i].frustum, cases[i].volume);
        out[i].verdict.resize(ms.size(), std::int8_t(-1));
        if (!on_paths)
          for (std::size_t k = 0; k < ms.size(); ++k)
            if (!ms[k].stateful) run_one(i, k);
      }
      progress.add(r.size());
    });
    // On camera paths every method meets each frame as an engine does: prepared once, then the
    // frame's objects classified in order (so a state leaking from one volume to the next within
    // a frame is exercised); the methods that are not stateful frame by frame in parallel.
    if (on_paths) {
      std::vector<std::pair<std::uint64_t, std::size_t>> frames;  // (path, frame) of the run's cases
      for (std::uint64_t i = 0; i < per; ++i) {
        const gen::PathIndex at = gen::path_index(first + i);
        if (frames.empty() || frames.back() != std::make_pair(at.path, at.frame)) frames.emplace_back(at.path, at.frame);
      }
      tbb::parallel_for(std::size_t(0), frames.size(), [&](std::size_t u) {
        const auto [number, f] = frames[u];
        const gen::CameraPath& cp = paths.at(number);
        for (std::size_t k = 0; k < ms.size(); ++k) {
          if (ms[k].stateful) continue;
          try {
            run_path(
                ms[k], cp.frames, f, f, cp.objects,
                [&](std::size_t fr, std::size_t o, const Answer& a) {
                  const std::uint64_t index = gen::path_case_index({number, fr, o});
                  if (index >= first && index < first + per) out[index - first].verdict[k] = a ? std::int8_t(*a) : std::int8_t(-1);
                },
                /*reset=*/false);
          } catch (const PathFault& e) {
            note_fault(gen::path_case_index({number, e.frame, e.object}), k,
                       fmt::format("{} (camera path frame {}, object {}; the frame's objects classified in order)", e.what(),
                                   e.frame, e.object));
          }
        }
      });
    }
    // Stateful methods on one thread: over each camera path from its first frame to the last
    // frame a case of the run is on; elsewhere case by case, each a path of one frame.
    for (std::size_t k = 0; k < ms.size(); ++k) {
      if (!ms[k].stateful) continue;
      if (!on_paths) {
        for (std::uint64_t i = 0; i < per; ++i) run_one(i, k);
        continue;
      }
      for (const auto& [number, cp] : paths) {
        const std::uint64_t base = gen::path_case_index({number, 0, 0});
        const std::uint64_t last = std::min(base + gen::kPathFrames * gen::kPathObjects, first + per) - 1;
        try {
          run_path(ms[k], cp.frames, 0, gen::path_index(last).frame, cp.objects,
                   [&](std::size_t f, std::size_t o, const Answer& a) {
                     const std::uint64_t index = gen::path_case_index({number, f, o});
                     if (index >= first && index < first + per) out[index - first].verdict[k] = a ? std::int8_t(*a) : std::int8_t(-1);
                   });
        } catch (const PathFault& e) {
          note_fault(gen::path_case_index({number, e.frame, e.object}), k,
                     fmt::format("{} (camera path frame {}, object {})", e.what(), e.frame, e.object));
        }
      }
    }
    if (fault_index != std::numeric_limits<std::uint64_t>::max()) {
      progress.finish();
      const Method& m = ms[fault_method];
      if (on_paths) {
        PathCase pc = path_case_at(fault_index);
        if (!m.stateful) pc.frames = {pc.frames.back()};
        GenCase g = gen::path_case(paths.at(gen::path_index(fault_index).path), pc.frames.size() - 1, pc.object);
        fault(opt, m, d, fault_index, g, fault_problem, &pc);
      }
      fault(opt, m, d, fault_index, cases[fault_index - first], fault_problem);
    }
    // The oracle's distance (an exact QP for outside volumes) and the case scale, once per case
    // that some method got wrong, in parallel: they depend on the case, not on the method.
    tbb::parallel_for(tbb::blocked_range<std::uint64_t>(0, per, 16), [&](const tbb::blocked_range<std::uint64_t>& r) {
      for (std::uint64_t i = r.begin(); i != r.end(); ++i) {
        bool erred = false;
        for (std::size_t k = 0; k < ms.size(); ++k) {
          const std::int8_t v = out[i].verdict[k];
          erred = erred || (v >= 0 && error_class(Visibility(v), out[i].truth, ms[k].three_way) != ErrorClass::correct);
        }
        if (!erred) continue;
        out[i].distance = oracle::classify(cases[i].frustum, cases[i].volume, oracle::Options{true, true, false}).distance;
        out[i].scale = gen::case_scale(cases[i].frustum, cases[i].volume);
      }
    });
    const auto st1 = oracle::stats();

    // Timing frames, drawn once per set of volume kinds (methods that take the same kinds are
    // timed on the same volumes).
    std::map<unsigned, std::vector<KindedFrame>> frames;
    if (opt.timing)
      for (const Method& m : ms)
        if (!frames.count(m.volumes)) {
          std::vector<KindedFrame>& fs = frames[m.volumes];
          for (int j = 0; j < opt.timing_frames; ++j)
            fs.push_back(split(gen::draw_frame(d, opt.seed, std::uint64_t(j), opt.frame_size, m.volumes)));
        }

    DistributionResult dr;
    dr.distribution = d;
    dr.cases = per;
    dr.oracle_calls = st1.calls - st0.calls;
    dr.oracle_fallbacks = st1.fallbacks - st0.fallbacks;
    for (const CaseOutcome& o : out) dr.float_exact_cases += o.float_exact;
    for (std::size_t k = 0; k < ms.size(); ++k) {
      const Method& m = ms[k];
      MethodStats s;
      s.method = m.name;
      s.claim = m.claim;
      s.origin = m.origin;
      s.three_way = m.three_way;
      s.volumes = m.volumes;
      std::map<ErrorClass, int> written, violations_written;
      for (std::uint64_t i = 0; i < per; ++i) {
        if (out[i].verdict[k] < 0) continue;
        const Visibility v = Visibility(out[i].verdict[k]), t = out[i].truth;
        ++s.cases;
        (t == Visibility::outside ? s.truth_outside : t == Visibility::inside ? s.truth_inside : s.truth_intersecting)++;
        const ErrorClass cls = error_class(v, t, m.three_way);
        if (cls == ErrorClass::correct) continue;
        switch (cls) {
          case ErrorClass::false_reject: ++s.false_reject; break;
          case ErrorClass::false_inside: ++s.false_inside; break;
          case ErrorClass::false_intersect: ++s.false_intersect; break;
          case ErrorClass::under_inside: ++s.under_inside; break;
          default: break;
        }
        const double scale = out[i].scale;
        // The backward distance (an LP) only where it can change the answer: a claim that
        // allows this class within a tolerance, and an oracle distance beyond it.
        const bool hard = cls == ErrorClass::false_reject || cls == ErrorClass::false_inside;
        const bool tolerant = m.claim == Claim::exact || m.claim == Claim::certified_exact ||
                              (m.claim == Claim::conservative && hard);
        const bool banded = m.claim == Claim::certified_exact;  // a proven band, float-exact or not
        const double dist = tolerant && (banded || !out[i].float_exact) && out[i].distance > m.tolerance * scale
                                ? error_distance(cases[i].frustum, cases[i].volume, cls, out[i].distance)
                                : out[i].distance;
        const bool violation = violates_claim(m.claim, cls, dist, m.tolerance, scale, out[i].float_exact);
        if (violation && out[i].float_exact) ++s.float_exact_violations;
        if (violation) ++s.claim_violations;
        if (violation && !s.first_violation) s.first_violation = first + i;
        if (cls == ErrorClass::false_intersect) s.fi_distance.push_back(out[i].distance / cases[i].scene_size);
        // Corpus: up to kViolationsPerClass claim violations per (method, distribution, class),
        // and corpus_per_class of the other errors (the expected false intersects and
        // under-insides of conservative methods), counted apart.
        constexpr int kViolationsPerClass = 4;
        int& quota = violation ? violations_written[cls] : written[cls];
        if (opt.corpus && quota < (violation ? kViolationsPerClass : opt.corpus_per_class)) {
          ++quota;
          std::optional<PathCase> path;  // a stateful method's error on a camera path is kept with its path
          GenCase small;
          // On a camera path, an error that needs what came before (earlier frames for a stateful
          // method, the frame's earlier objects for any) is kept with its path.
          auto alone_shows_it = [&] {
            try {
              const Answer a = run_method(m, cases[i]);
              return a && error_class(*a, t, m.three_way) == cls;
            } catch (const std::exception&) {
              return false;
            }
          };
          if (on_paths && (m.stateful || !alone_shows_it())) {
            PathCase pc = path_case_at(first + i);
            if (!m.stateful) pc.frames = {pc.frames.back()};
            path = shrink_path(std::move(pc), m, cls, t, opt.shrink_budget);
            small = cases[i];
          } else {
            small = shrink(gen::draw(d, opt.seed, first + i), m, cls, violation, opt.shrink_budget);
          }
          Answer vs;
          try {
            vs = path ? checked_classify_path(m, *path) : run_method(m, small);
          } catch (const std::exception& e) {
            progress.finish();
            fault(opt, m, d, first + i, small, e.what(), path ? &*path : nullptr);
          }
          if (!vs) continue;
          const CorpusRecord rec =
              write_corpus_case(*opt.corpus, small, m, *vs, d, opt.seed, first + i, ms, path ? &*path : nullptr);
          if (rec.written) s.corpus_written.push_back(rec.id);
          // Evidence of a counted violation that the shrunk case still shows (shrinking keeps it).
          if (violation && rec.violates && std::find(s.violation_ids.begin(), s.violation_ids.end(), rec.id) == s.violation_ids.end())
            s.violation_ids.push_back(rec.id);
        }
      }
      if (opt.timing) {
        const Timing t = time_method(m, frames.at(m.volumes));
        s.ns_per_test = t.ns_per_test;
        s.ns_setup_per_frame = t.ns_setup_per_frame;
        s.timed_batch = m.has_batch();
        s.ns_per_test_own = t.ns_per_test_own;
      }
      dr.methods.push_back(std::move(s));
    }
    result.distributions.push_back(std::move(dr));
  }
  progress.finish();
  result.wall_seconds = std::chrono::duration<double>(Clock::now() - t_start).count();
  return result;
}

namespace {

std::string pct(double x) {
  if (x == 0.0) return "0";
  if (x < 1e-4) return fmt::format("{:.1e}", x * 100);
  return fmt::format("{:.3g}", x * 100);
}

std::string median_max(std::vector<double> v) {
  if (v.empty()) return "-";
  std::sort(v.begin(), v.end());
  return fmt::format("{:.2g} / {:.2g}", v[v.size() / 2], v.back());
}

std::string ns(double x) { return std::isfinite(x) ? fmt::format("{:.1f}", x) : "-"; }

}  // namespace

void print_tables(const VerifyResult& r, std::ostream& out) {
  for (const auto& d : r.distributions) {
    out << fmt::format("\n## {} ({} cases: {}; {} float-exact; oracle fallback to exact LP {:.1f}%)\n\n",
                       gen::to_string(d.distribution), d.cases, gen::describe(d.distribution), d.float_exact_cases,
                       d.oracle_calls ? 100.0 * double(d.oracle_fallbacks) / double(d.oracle_calls) : 0.0);
    out << "| method | origin | claim | cases | false rejects | false inside | false-intersect % (95% CI) | under-inside % "
           "| FI distance / scene (median / max) | set-up ns/frame | ns/test |\n";
    out << "|---|---|---|---:|---:|---:|---|---:|---|---:|---:|\n";
    for (const auto& m : d.methods) {
      const auto [lo, hi] = wilson95(m.false_intersect, m.truth_outside);
      std::string status = m.claim == Claim::none ? "none"
                           : m.refuted()          ? fmt::format("{} REFUTED ({}{})", to_string(m.claim), m.claim_violations,
                                                                m.float_exact_violations
                                                                    ? fmt::format("; {} float-exact", m.float_exact_violations)
                                                                    : std::string())
                                                  : fmt::format("{} held", to_string(m.claim));
      if (!m.three_way) status += ", two-way";
      out << fmt::format("| {} | {} | {} | {} | {} | {} | {} ({}-{}) | {} | {} | {} | {}{}{} |\n", m.method,
                         to_string(m.origin), status, m.cases, m.false_reject, m.false_inside,
                         pct(m.truth_outside ? double(m.false_intersect) / double(m.truth_outside) : 0.0), pct(lo),
                         pct(hi),
                         m.three_way ? pct(m.truth_inside ? double(m.under_inside) / double(m.truth_inside) : 0.0)
                                     : std::string("-"),
                         median_max(m.fi_distance), ns(m.ns_setup_per_frame), ns(m.ns_per_test),
                         m.timed_batch ? " (batch)" : "",
                         std::isfinite(m.ns_per_test_own) ? fmt::format("; own {:.1f}", m.ns_per_test_own) : std::string());
    }
  }
  out << "\norigin: published = a text under test (a refuted claim is a finding); own = cullproof's, user = yours "
         "(a refuted claim fails the run).\n";
  out << "false-intersect % = false intersects / volumes truly outside; under-inside % = / volumes truly inside "
         "(two-way methods answer visible or outside: not charged).\n";
  if (r.options.timing)
    out << fmt::format("cost: set-up = prepare, once per frame; ns/test = classify per volume, {} frames of {} volumes "
                       "per distribution (camera-path: {} consecutive frames of one path, {} volumes each), through "
                       "the method's array form where it has one (batch); own = what a program reports of its own "
                       "classification time over the same frames (docs/protocol.md).\n",
                       r.options.timing_frames, r.options.frame_size, r.options.timing_frames, gen::kPathObjects);
  out << fmt::format("wall time {:.1f} s\n", r.wall_seconds);
}

namespace {

nlohmann::json volume_names(unsigned bits) {
  nlohmann::json a = nlohmann::json::array();
  for (unsigned k : {kPointKind, kSphereKind, kAabbKind, kObbKind})
    if (bits & k) a.push_back(std::string(volume_kind_name(k)));
  return a;
}

}  // namespace

nlohmann::json fi_distance_histogram(const std::vector<double>& distances) {
  std::vector<std::uint64_t> counts(kFiHistogramLastDecade - kFiHistogramFirstDecade, 0);
  std::uint64_t below = 0, above = 0;
  for (const double x : distances) {
    // Decade k holds [10^k, 10^(k+1)); the bounds are compared with the exact powers of ten
    // as double rounds them, so a distance of exactly 10^k lands in decade k.
    if (!(x >= std::pow(10.0, kFiHistogramFirstDecade))) {
      ++below;
      continue;
    }
    if (x >= std::pow(10.0, kFiHistogramLastDecade)) {
      ++above;
      continue;
    }
    int k = int(std::floor(std::log10(x)));
    if (x < std::pow(10.0, k)) --k;  // log10 rounded up across a power of ten
    else if (x >= std::pow(10.0, k + 1)) ++k;
    k = std::clamp(k, kFiHistogramFirstDecade, kFiHistogramLastDecade - 1);
    ++counts[std::size_t(k - kFiHistogramFirstDecade)];
  }
  return {{"first_decade", kFiHistogramFirstDecade}, {"counts", counts}, {"below", below}, {"above", above}};
}

nlohmann::json to_json(const VerifyResult& r) {
  nlohmann::json j;
  j["seed"] = r.options.seed;
  j["cases_per_distribution"] = r.options.only_index ? 1 : r.options.cases;
  j["wall_seconds"] = r.wall_seconds;
  j["claim_broken"] = r.claim_broken();
  j["frame_size"] = r.options.frame_size;
  j["timing_frames"] = r.options.timing_frames;
  for (const auto& d : r.distributions) {
    nlohmann::json jd;
    jd["distribution"] = std::string(gen::to_string(d.distribution));
    jd["cases"] = d.cases;
    jd["oracle_calls"] = d.oracle_calls;
    jd["oracle_fallbacks"] = d.oracle_fallbacks;
    jd["float_exact_cases"] = d.float_exact_cases;
    for (const auto& m : d.methods) {
      const auto [lo, hi] = wilson95(m.false_intersect, m.truth_outside);
      std::vector<double> dist = m.fi_distance;
      std::sort(dist.begin(), dist.end());
      jd["methods"].push_back({{"method", m.method},
                               {"claim", std::string(to_string(m.claim))},
                               {"origin", std::string(to_string(m.origin))},
                               {"three_way", m.three_way},
                               {"refuted", m.refuted()},
                               {"claim_violations", m.claim_violations},
                               {"float_exact_violations", m.float_exact_violations},
                               {"first_violation", m.first_violation ? nlohmann::json(*m.first_violation) : nlohmann::json(nullptr)},
                               {"cases", m.cases},
                               {"truth", {{"outside", m.truth_outside}, {"intersecting", m.truth_intersecting}, {"inside", m.truth_inside}}},
                               {"false_reject", m.false_reject},
                               {"false_inside", m.false_inside},
                               {"false_intersect", m.false_intersect},
                               {"under_inside", m.under_inside},
                               {"false_intersect_rate", m.truth_outside ? double(m.false_intersect) / double(m.truth_outside) : 0.0},
                               {"false_intersect_rate_ci95", {lo, hi}},
                               {"under_inside_rate", m.truth_inside ? double(m.under_inside) / double(m.truth_inside) : 0.0},
                               {"fi_distance_median", dist.empty() ? nlohmann::json(nullptr) : nlohmann::json(dist[dist.size() / 2])},
                               {"fi_distance_max", dist.empty() ? nlohmann::json(nullptr) : nlohmann::json(dist.back())},
                               {"ns_per_test", std::isfinite(m.ns_per_test) ? nlohmann::json(m.ns_per_test) : nlohmann::json(nullptr)},
                               {"ns_setup_per_frame", std::isfinite(m.ns_setup_per_frame) ? nlohmann::json(m.ns_setup_per_frame) : nlohmann::json(nullptr)},
                               {"timed_batch", m.timed_batch},
                               {"ns_per_test_own", std::isfinite(m.ns_per_test_own) ? nlohmann::json(m.ns_per_test_own) : nlohmann::json(nullptr)},
                               {"fi_distance_histogram", fi_distance_histogram(m.fi_distance)},
                               {"volumes", volume_names(m.volumes)},
                               {"corpus_written", m.corpus_written},
                               {"violation_ids", m.violation_ids}});
    }
    j["distributions"].push_back(jd);
  }
  return j;
}

}  // namespace cullproof
