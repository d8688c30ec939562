// Shrinking a mismatch to the simplest case that still shows it (see campaign_internal.hpp).
#include "campaign_internal.hpp"

#include "cullproof/oracle/oracle.hpp"

#include <algorithm>
#include <limits>
#include <mutex>

namespace cullproof::detail {

namespace {

// An error of class `cls` judged as the run judges it: whether it breaks m's claim, and how many
// allowances it lies from the verdict it was given (+infinity where the claim forgives nothing at
// any distance: no tolerance, or a float-exact case). The distance is measured once.
struct Judged {
  bool violates = false;
  double allowances = std::numeric_limits<double>::infinity();
};

Judged judge(const GenCase& c, const Method& m, ErrorClass cls, Visibility verdict) {
  const bool exact_case = gen::float_exact(c.frustum, c.volume);
  const double scale = gen::case_scale(c.frustum, c.volume);
  const bool measured = needs_distance(m.claim, cls, exact_case);
  const double dist = measured ? error_distance(c.frustum, c.volume, verdict) : std::numeric_limits<double>::infinity();
  Judged j;
  j.violates = violates_claim(m.claim, cls, dist, m.tolerance, scale, exact_case);
  const double allowance = m.tolerance * scale;
  if (measured && allowance > 0.0) j.allowances = dist / allowance;
  return j;
}

}  // namespace

GenCase shrink(gen::Distribution d, std::uint64_t seed, std::uint64_t index, const Method& m, ErrorClass cls, bool violation,
               int budget) {
  // RapidCheck keeps its generation state process-wide, not per thread: its shrinkable trees are
  // made, walked and destroyed under this lock (declared first, so released last), and only the
  // candidates, plain values, are judged outside it, where threads shrinking different methods'
  // errors overlap.
  static std::mutex rapidcheck;
  std::unique_lock<std::mutex> lock(rapidcheck);
  rc::Shrinkable<gen::GenCase> cur = gen::draw(d, seed, index);
  // A claim violation shrinks only to claim violations that stay as far beyond the allowance as the
  // error found was, up to kKeptAllowances of it: simpler numbers, not a smaller error, so that a
  // shrunk case of a gross bug never reads as rounding noise.
  constexpr double kKeptAllowances = 1000.0;
  double keep = 0.0;
  if (violation) {
    const GenCase c = cur.value();
    lock.unlock();
    if (const auto v = run_method(m, c)) keep = std::min(judge(c, m, cls, *v).allowances, kKeptAllowances);
    lock.lock();
  }
  // Whether the candidate c keeps the error (judged as the run judges it: beyond the allowance,
  // its distance from the verdict given, and by as many allowances as `keep`).
  auto keeps_error = [&](const GenCase& c) {
    try {
      validate(c.volume);
      const auto v = run_method(m, c);
      if (!v) return false;
      if (error_class(*v, oracle::truth(c.frustum, c.volume), m.three_way_on(c.volume)) != cls) return false;
      if (violation) {
        const Judged j = judge(c, m, cls, *v);
        if (!j.violates || j.allowances < keep) return false;
      }
      return true;
    } catch (const std::exception&) {
      return false;  // an invalid shrink (e.g. a degenerate axis): not a candidate
    }
  };
  bool progress = true;
  while (progress && budget > 0) {
    progress = false;
    auto seq = cur.shrinks();
    while (auto next = seq.next()) {
      if (--budget <= 0) break;
      const GenCase c = next->value();
      lock.unlock();
      const bool keeps = keeps_error(c);
      lock.lock();
      if (keeps) {
        cur = *next;
        progress = true;
        break;
      }
    }
  }
  return cur.value();
}

PathCase shrink_path(PathCase p, const Method& m, ErrorClass cls, Visibility truth, int budget) {
  auto still = [&](const PathCase& c) {
    try {
      const Answer a = checked_classify_path(m, c);
      return a && error_class(*a, truth, m.three_way_on(c.volume())) == cls;
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

}  // namespace cullproof::detail
