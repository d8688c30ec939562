// Calling a method as the campaign does: one case, or a camera path frame after frame, with
// every answer checked and every exception turned into a fault naming the method.
#include "cullproof/judge/judge.hpp"

#include <fmt/format.h>

namespace cullproof {

namespace {

// Why an answer is not one the method may give, or "" when it is.
std::string answer_problem(const Method& m, const Volume& v, const Answer& a) {
  if (a && unsigned(*a) > unsigned(Visibility::inside))
    return fmt::format("method '{}' answered {}, which is not a verdict (0 outside, 1 intersecting, 2 inside)", m.name,
                       unsigned(*a));
  if (a && *a == Visibility::inside && !m.three_way_on(v))
    return m.three_way ? "method '" + m.name + "' answered inside for a " + std::string(volume_kind_name(volume_kind(v))) +
                             ", but it is two-way on those (visible or outside)"
                       : "method '" + m.name + "' answered inside, but it is two-way (visible or outside)";
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

}  // namespace

namespace detail {

namespace {

// run_path's working arrays, kept per thread so that a frame costs no allocation once they have
// grown; a nested call (a sink that runs a method again) gets its own.
struct PathScratch {
  std::vector<std::size_t> order;  // objects the method takes, in path order
  std::vector<Point> points;
  std::vector<Sphere> spheres;
  std::vector<Aabb> aabbs;
  std::vector<Obb> obbs;
  std::vector<std::size_t> of_kind[4];  // path index of each, by kind
  std::vector<Answer> answers;
  bool busy = false;
  void clear() {
    order.clear();
    points.clear();
    spheres.clear();
    aabbs.clear();
    obbs.clear();
    for (auto& k : of_kind) k.clear();
  }
};

}  // namespace

void run_path(const Method& m, const std::vector<CaseFrustum>& frames, std::size_t first, std::size_t last,
              const std::vector<Volume>& objects, const PathSink& sink, bool reset) {
  thread_local PathScratch shared;
  PathScratch own;
  PathScratch& s = shared.busy ? own : shared;
  s.clear();
  struct Busy {
    bool& b;
    explicit Busy(bool& x) : b(x) { b = true; }
    ~Busy() { b = false; }
  } busy(s.busy);
  auto& order = s.order;
  auto& points = s.points;
  auto& spheres = s.spheres;
  auto& aabbs = s.aabbs;
  auto& obbs = s.obbs;
  auto& of_kind = s.of_kind;
  auto& answers = s.answers;
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
          const std::string problem = answer_problem(m, objects[idx[j]], answers[j]);
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
        const std::string problem = answer_problem(m, objects[o], a);
        if (!problem.empty()) throw PathFault(problem, f, o);
        sink(f, o, a);
      }
    }
  }
}

void run_frames(const Method& m, const std::vector<FrameRequest>& frames, std::vector<Answer>& answers) {
  // The volumes it takes, frame by frame and within a frame kind by kind (where each came from in
  // `at`), asked as frames of one kind each.
  std::size_t total = 0;
  bool as_given = true;  // every volume taken, each frame's kinds in order: asked as they are
  for (const FrameRequest& f : frames) {
    total += f.count;
    for (std::size_t i = 0; i < f.count && as_given; ++i)
      as_given = m.takes(f.volumes[i]) && (i == 0 || f.volumes[i].index() >= f.volumes[i - 1].index());
  }
  if (as_given) {
    answers.assign(total, Answer{});
    if (total == 0) return;
    call_method(m, " on frames", [&] { m.classify_frames(frames.data(), frames.size(), answers.data()); });
    std::size_t i = 0;
    for (const FrameRequest& f : frames)
      for (std::size_t j = 0; j < f.count; ++j, ++i) {
        const std::string problem = answer_problem(m, f.volumes[j], answers[i]);
        if (!problem.empty()) throw std::runtime_error(problem);
      }
    return;
  }
  std::vector<Volume> asked;
  std::vector<std::size_t> at;
  std::vector<std::pair<std::size_t, std::size_t>> spans;  // per request: [begin, end) of `asked`
  std::vector<const CaseFrustum*> of;
  asked.reserve(total);
  at.reserve(total);
  total = 0;
  for (const FrameRequest& f : frames) {
    for (std::size_t kind = 0; kind < 4; ++kind) {
      const std::size_t begin = asked.size();
      for (std::size_t i = 0; i < f.count; ++i)
        if (f.volumes[i].index() == kind && m.takes(f.volumes[i])) asked.push_back(f.volumes[i]), at.push_back(total + i);
      if (asked.size() > begin) spans.emplace_back(begin, asked.size()), of.push_back(f.frustum);
    }
    total += f.count;
  }
  answers.assign(total, Answer{});
  if (asked.empty()) return;
  std::vector<FrameRequest> requests(spans.size());
  for (std::size_t j = 0; j < spans.size(); ++j)
    requests[j] = FrameRequest{of[j], asked.data() + spans[j].first, spans[j].second - spans[j].first};
  std::vector<Answer> got(asked.size());
  call_method(m, " on frames", [&] { m.classify_frames(requests.data(), requests.size(), got.data()); });
  for (std::size_t i = 0; i < asked.size(); ++i) {
    const std::string problem = answer_problem(m, asked[i], got[i]);
    if (!problem.empty()) throw std::runtime_error(problem);
    answers[at[i]] = got[i];
  }
}

}  // namespace detail

Answer checked_classify(const Method& m, const CaseFrustum& f, const Volume& v) {
  if (!m.takes(v)) return std::nullopt;
  Answer a;
  call_method(m, "", [&] { a = m.classify(f, v); });
  const std::string problem = answer_problem(m, v, a);
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
    detail::run_path(
        m, p.frames, m.stateful ? 0 : last, last, p.objects,
        [&](std::size_t f, std::size_t o, const Answer& a) {
          if (f == last && o == p.object) out = a;
        },
        /*reset=*/m.stateful);
  } catch (const detail::PathFault& e) {
    throw std::runtime_error(fmt::format("{} (camera path frame {}, object {})", e.what(), e.frame, e.object));
  }
  return out;
}

std::optional<Visibility> detail::run_method(const Method& m, const gen::GenCase& c) {
  return checked_classify(m, c.frustum, c.volume);
}

}  // namespace cullproof
