// The campaign's parts shared by its translation units (not installed): shrinking, faults, timing,
// and the progress line.
#pragma once

#include "cullproof/oracle/oracle.hpp"

#include "cullproof/campaign/campaign.hpp"
#include "cullproof/corpus/corpus.hpp"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace cullproof::detail {

using Clock = std::chrono::steady_clock;
using gen::GenCase;

// ---- Shrinking (shrink.cpp)

/// The simplest case of the Shrinkable tree of case `index` of distribution d (gen::draw) on which
/// `m` still makes an error of class `cls` (and, for a claim violation, still violates the claim,
/// by as many allowances as the error found, up to 1,000), within `budget` steps. Safe to call
/// from several threads (for different methods, or methods that may run concurrently).
GenCase shrink(gen::Distribution d, std::uint64_t seed, std::uint64_t index, const Method& m, ErrorClass cls, bool violation,
               int budget);

/// A stateful method's error on a camera path: the object alone if the error stays without the
/// others, then the fewest frames before the one judged that keep it (the case judged, and so its
/// truth and distance, does not change).
PathCase shrink_path(PathCase p, const Method& m, ErrorClass cls, Visibility truth, int budget);

// ---- Faults (faults.cpp)

/// The fault of method `m` on case `index` of distribution `d` (`g`, or on a camera path `path`),
/// the case saved under VerifyOptions::faults (or the corpus folder's faults/).
MethodFault make_fault(const VerifyOptions& opt, const Method& m, gen::Distribution d, std::uint64_t index, const GenCase& g,
                       const std::string& problem, const PathCase* path = nullptr);
/// A fault while the method was timed (no case of the distribution to save).
MethodFault timing_fault(const Method& m, const std::string& problem);

// ---- The corpus's choice (campaign.cpp records it, shards.cpp merges it)

/// Claim violations a run records per (method, distribution, class).
inline constexpr std::size_t kViolationsPerClass = 4;
/// Keeps, of `v` (in case order), the kViolationsPerClass farthest beyond their allowance
/// (`rank(x)` larger first: the float-exact ones, with none, first), the clearest evidence that
/// rounding does not explain them; the earlier case first among equals.
template <class T, class Rank>
void keep_farthest(std::vector<T>& v, Rank rank) {
  std::stable_sort(v.begin(), v.end(), [&](const T& a, const T& b) { return rank(a) > rank(b); });
  if (v.size() > kViolationsPerClass) v.erase(v.begin() + std::ptrdiff_t(kViolationsPerClass), v.end());
}

// ---- Timing (timing.cpp)

/// A frame's volumes split by kind, for classify_batch.
struct KindedFrame {
  CaseFrustum frustum;
  std::vector<Point> points;
  std::vector<Sphere> spheres;
  std::vector<Aabb> aabbs;
  std::vector<Obb> obbs;
  bool continues = false;  // gen::Frame::continues
  std::size_t size() const noexcept { return points.size() + spheres.size() + aabbs.size() + obbs.size(); }
};

KindedFrame split(gen::Frame f);

struct Timing {
  double ns_per_test = std::numeric_limits<double>::quiet_NaN();
  double ns_setup_per_frame = std::numeric_limits<double>::quiet_NaN();
  double ns_per_test_own = std::numeric_limits<double>::quiet_NaN();
};

/// Both phases timed as the method runs (stateful ones frame after frame), and what the method
/// reports of its own time over the same frames.
Timing time_method(const Method& m, const std::vector<KindedFrame>& frames);

// ---- The progress line (progress.cpp)

/// Progress bar on stderr: a redrawn line on a terminal, a line per 10% otherwise.
class Progress {
 public:
  Progress(bool on, std::uint64_t total);
  ~Progress() { finish(); }
  void add(std::uint64_t n) { done_.fetch_add(n, std::memory_order_relaxed); }
  void label(std::string s);
  /// Runs `f` (which writes to stdout) with the progress line cleared, then draws it again.
  void print(const std::function<void()>& f);
  void finish();

 private:
  void loop();
  void draw(bool last);
  void draw_locked(bool last);
  bool on_;
  std::uint64_t total_;
  bool tty_;
  std::atomic<std::uint64_t> done_{0};
  std::mutex m_;
  std::mutex out_;  // draw() and print() write one at a time
  bool finished_ = false;
  std::condition_variable cv_;
  bool stop_ = false;
  std::string label_;
  int last_decile_ = -1;
  Clock::time_point start_ = Clock::now();
  std::thread thread_;
};

}  // namespace cullproof::detail
