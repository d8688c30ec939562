// The campaign's parts shared by its translation units (harness/*.cpp; not installed): a method
// over a camera path, shrinking, corpus records and faults, timing, and the progress line.
#pragma once

#include "cullproof/oracle/oracle.hpp"

#include "cullproof/campaign/campaign.hpp"

#include <atomic>
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

// ---- Calling a method (method_calls.cpp)

/// A fault on a camera path and where it happened.
struct PathFault : std::runtime_error {
  PathFault(const std::string& what, std::size_t f, std::size_t o) : std::runtime_error(what), frame(f), object(o) {}
  std::size_t frame, object;
};

/// Receives (frame, object, answer) for each object a method takes on a camera path.
using PathSink = std::function<void(std::size_t frame, std::size_t object, const Answer& answer)>;

/// Runs method `m` over frames[first..last] of a camera path with `objects` (see the contract in
/// cullproof/methods/methods.hpp), after reset() when `reset`; sink(frame, object, answer) for each object
/// it takes, every frame. Throws PathFault.
void run_path(const Method& m, const std::vector<CaseFrustum>& frames, std::size_t first, std::size_t last,
              const std::vector<Volume>& objects, const PathSink& sink, bool reset = true);

/// checked_classify on a generated case.
std::optional<Visibility> run_method(const Method& m, const GenCase& c);

// ---- Shrinking (shrink.cpp)

/// The simplest case of the Shrinkable tree on which `m` still makes an error of class `cls`
/// (and, for a claim violation, still violates the claim, by as many allowances as the error
/// found, up to 1,000), within `budget` steps.
GenCase shrink(const rc::Shrinkable<gen::GenCase>& start, const Method& m, ErrorClass cls, bool violation, int budget);

/// A stateful method's error on a camera path: the object alone if the error stays without the
/// others, then the fewest frames before the one judged that keep it (the case judged, and so its
/// truth and distance, does not change).
PathCase shrink_path(PathCase p, const Method& m, ErrorClass cls, Visibility truth, int budget);

// ---- The corpus and faults (campaign_corpus.cpp)

/// The command (or, for a user's method, the test environment) that reruns one case.
std::string reproduce_command(std::uint64_t seed, gen::Distribution d, std::uint64_t index, const Method& m);

/// What write_corpus_case recorded: the case's id, whether this run wrote it (false: the same
/// geometry was recorded already, by an earlier run or meanwhile by another thread), and whether
/// the record breaks the method's claim (its "violates_claim").
struct CorpusRecord {
  std::string id;
  bool written = false;
  bool violates = false;
};

/// The judgement fields of a record of method m's error: "float_exact", "verdict_distance" (error_distance; null
/// when no shift helps), "verdict_distance_kind" (oracle::to_string(VerdictShift)), "tolerance"
/// and "allowance" (the distance within which the claim forgives the error: tolerance x scale, 0
/// on a float-exact case where the claim allows only rounding; null for a claim without one).
/// Removes the older "backward_distance".
void set_judgement(nlohmann::json& record, const oracle::VerdictDistance& vd, const Method& m, double scale, bool float_exact);

/// Writes one corpus case unless the same geometry is already recorded.
/// `path`: the camera path a stateful method's error needs to reproduce, recorded with the case
/// (the other stateful methods' verdicts are taken over it too).
CorpusRecord write_corpus_case(const std::filesystem::path& dir, const GenCase& g, const Method& m, Visibility verdict,
                               gen::Distribution d, std::uint64_t seed, std::uint64_t index,
                               const std::vector<Method>& all, const PathCase* path = nullptr);

/// Saves the case that made a method fault and throws the MethodFault naming it. Faults are
/// searched from the smallest case index, so the same seed reports the same case.
[[noreturn]] void fault(const VerifyOptions& opt, const Method& m, gen::Distribution d, std::uint64_t index,
                        const GenCase& g, const std::string& problem, const PathCase* path = nullptr);

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
  void finish();

 private:
  void loop();
  void draw(bool last);
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

}  // namespace cullproof::detail
