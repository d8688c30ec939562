// The verification run (see cullproof/campaign/campaign.hpp): per distribution, the cases drawn, every
// method's verdicts and the oracle's truth, the errors' distances, and per method the counts, the
// corpus records and the cost.
#include "campaign_internal.hpp"

#include "cullproof/oracle/oracle.hpp"

#include <fmt/format.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <map>
#include <set>

namespace cullproof {

namespace {

using namespace detail;

// A method's verdict on a case: a Visibility, or one of these.
constexpr std::int8_t kNotApplying = -1;  // the method does not take the volume or does not apply
constexpr std::int8_t kNotAsked = -2;     // not asked (after its fault, or the run was stopped)

// What the run keeps of every case (the case itself is drawn again from its index when needed).
struct CaseOutcome {
  Visibility truth{};
  bool judged = false;       // the oracle decided the truth
  bool float_exact = false;  // gen::float_exact
  std::uint8_t kind = 0;     // volume_kind of the volume
};

// What is measured of a case some method got wrong.
struct ErrorMeasure {
  double distance = std::numeric_limits<double>::quiet_NaN();  // the oracle's distance (false intersects)
  double scale = 0.0;                                          // gen::case_scale
  double scene_size = 1.0;                                     // GenCase::scene_size
  // error_distance per verdict (indexed by Visibility), where some method's claim needs it.
  static constexpr double kUnmeasured = -1.0;
  std::array<double, 3> verdict_distance{kUnmeasured, kUnmeasured, kUnmeasured};
};

std::int8_t verdict_code(const Answer& a) { return a ? std::int8_t(*a) : kNotApplying; }

constexpr std::uint64_t kNoFault = std::numeric_limits<std::uint64_t>::max();

// The run's cases of distribution d: (first, count).
std::pair<std::uint64_t, std::uint64_t> range_of(const VerifyOptions& opt, gen::Distribution d) {
  if (opt.only_index) return {*opt.only_index, 1};
  if (opt.shard) {
    const auto [a, b] = shard_cases(d, opt.cases, *opt.shard);
    return {a, b - a};
  }
  return {0, opt.cases};
}

// One distribution of a run, step by step: the cases drawn frame by frame and judged, the methods
// run on them (case by case, or on camera paths frame by frame as an engine does, stateful
// methods on one thread), a method that faults no longer asked past its fault; the errors'
// distances measured; then each method's errors counted, recorded in the corpus, and the method
// timed. Of each case the run keeps its truth and the verdicts; a case is drawn again from its
// index where a later step needs it. A stop request (VerifyOptions::stop) ends the judging and
// asking: what was judged is counted.
class DistributionRun {
 public:
  DistributionRun(const VerifyOptions& opt, const std::vector<Method>& ms, gen::Distribution d, Progress& progress)
      : opt_(opt), ms_(ms), d_(d), progress_(progress), per_(range_of(opt, d).second),
        first_(range_of(opt, d).first), on_paths_(d == gen::Distribution::camera_path),
        per_frame_(gen::cases_per_frame(d)), out_(per_), verdicts_(per_ * ms.size(), kNotAsked),
        fault_at_(ms.size()), fault_problem_(ms.size()) {
    for (auto& f : fault_at_) f.store(kNoFault, std::memory_order_relaxed);
  }

  DistributionResult run() {
    const auto st0 = oracle::stats();
    draw_paths();
    run_case_by_case();
    if (on_paths_) run_path_frames();
    run_stateful();
    const bool interrupted = stopped();
    std::vector<std::optional<MethodFault>> faults = collect_faults();
    measure_errors();
    const auto st1 = oracle::stats();

    DistributionResult dr;
    dr.distribution = d_;
    dr.first_case = first_;
    dr.cases_asked = per_;
    dr.interrupted = interrupted;
    dr.oracle_calls = st1.calls - st0.calls;
    dr.oracle_fallbacks = st1.fallbacks - st0.fallbacks;
    for (const CaseOutcome& o : out_) {
      dr.cases += o.judged;
      dr.float_exact_cases += o.judged && o.float_exact;
    }
    const bool timing = opt_.timing && !interrupted;
    const auto frames = timing ? timing_frames() : std::map<unsigned, std::vector<KindedFrame>>{};
    // Counting a method's errors and shrinking them ask that method alone: methods in parallel,
    // each on one thread (as a stateful method's contract asks). Writing a record asks every method
    // for its verdict: one record at a time, in method order, so the corpus is the same on any
    // number of threads.
    std::vector<MethodStats> stats(ms_.size());
    std::vector<std::vector<Pending>> pending(ms_.size());
    std::vector<std::vector<Shrunk>> shrunk(ms_.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, ms_.size(), 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t k = r.begin(); k != r.end(); ++k) {
                          stats[k] = tally(k, pending[k]);
                          shrunk[k] = shrink_errors(k, pending[k], stats[k]);
                        }
                      },
                      tbb::simple_partitioner());
    for (std::size_t k = 0; k < ms_.size(); ++k) {
      MethodStats& s = stats[k];
      for (std::size_t j = 0; j < pending[k].size(); ++j) write_record(k, pending[k][j], shrunk[k][j], s);
      if (faults[k]) s.fault = std::move(faults[k]);
      dr.methods.push_back(std::move(s));
    }
    if (timing) {
      auto time_one = [&](std::size_t k) {
        MethodStats& s = dr.methods[k];
        if (s.fault) return;
        try {
          const Timing t = time_method(ms_[k], frames.at(ms_[k].volumes));
          s.ns_per_test = t.ns_per_test;
          s.ns_setup_per_frame = t.ns_setup_per_frame;
          s.timed_batch = ms_[k].has_batch();
          s.ns_per_test_own = t.ns_per_test_own;
        } catch (const std::exception& e) {
          s.fault = timing_fault(ms_[k], fmt::format("{} (while timed: frames of {} volumes drawn from seed {})", e.what(),
                                                     opt_.frame_size, opt_.seed));
        }
      };
      // In-process methods are timed one per thread at a time; a program's one after another (its
      // process would make two of them wait on each other).
      std::vector<std::size_t> in_process;
      for (std::size_t k = 0; k < ms_.size(); ++k)
        if (ms_[k].program.empty()) in_process.push_back(k);
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, in_process.size(), 1),
                        [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t u = r.begin(); u != r.end(); ++u) time_one(in_process[u]);
                        },
                        tbb::simple_partitioner());
      for (std::size_t k = 0; k < ms_.size(); ++k)
        if (!ms_[k].program.empty()) time_one(k);
    }
    return dr;
  }

 private:
  // Camera paths are drawn first, each once (and kept: the stateful methods run over them); every
  // other case is drawn where it is judged (run_case_by_case).
  void draw_paths() {
    drawn_ = per_;
    if (!on_paths_) return;
    for (std::uint64_t i = 0; i < per_; ++i) {
      if (i % 4096 == 0 && stopped()) {
        drawn_ = i;
        return;
      }
      const gen::PathIndex at = gen::path_index(first_ + i);
      if (!paths_.count(at.path)) paths_.emplace(at.path, gen::draw_path(opt_.seed, at.path));
    }
  }

  // The run's cases [a, b) (relative indices) into out[0, b - a): as the campaign draws them, a
  // framed family's camera once per frame.
  void frame_cases(std::uint64_t a, std::uint64_t b, std::vector<GenCase>& out) const {
    out.resize(b - a);
    if (!on_paths_) return gen::draw_cases(d_, opt_.seed, first_ + a, b - a, out.data());
    for (std::uint64_t i = a; i < b; ++i) {
      const gen::PathIndex at = gen::path_index(first_ + i);
      out[i - a] = gen::path_case(paths_.at(at.path), at.frame, at.object);
    }
  }

  // Case i of the run (a relative index), drawn again.
  GenCase case_at(std::uint64_t i) const {
    std::vector<GenCase> one;
    frame_cases(i, i + 1, one);
    return one[0];
  }

  // The path case of a stateful method at case index `index` of this run's paths: the frames up to
  // its own, every object.
  PathCase path_case_at(std::uint64_t index) const {
    const gen::PathIndex at = gen::path_index(index);
    const gen::CameraPath& cp = paths_.at(at.path);
    PathCase pc;
    pc.frames.assign(cp.frames.begin(), cp.frames.begin() + std::ptrdiff_t(at.frame + 1));
    pc.objects = cp.objects;
    pc.object = at.object;
    pc.motion = cp.motion;
    return pc;
  }

  bool stopped() const { return opt_.stop && opt_.stop->load(std::memory_order_relaxed); }

  std::int8_t& verdict(std::uint64_t i, std::size_t k) { return verdicts_[i * ms_.size() + k]; }
  std::int8_t verdict(std::uint64_t i, std::size_t k) const { return verdicts_[i * ms_.size() + k]; }

  // Whether method k is still asked about case `index` (of the distribution): only below the
  // smallest index it faulted on so far, so that every case before its first fault is asked and
  // the same seed reports the same fault whatever the threads do.
  bool asks(std::size_t k, std::uint64_t index) const { return index < fault_at_[k].load(std::memory_order_relaxed); }

  // A fault of method k is kept for the smallest case index it happens on. Indices are the
  // distribution's (a stateful method on a camera path may fault on a frame before the first case
  // asked for).
  void note_fault(std::uint64_t index, std::size_t k, const std::string& problem) {
    std::lock_guard<std::mutex> g(fault_mutex_);
    if (index < fault_at_[k].load(std::memory_order_relaxed)) {
      fault_at_[k].store(index, std::memory_order_relaxed);
      fault_problem_[k] = problem;
    }
  }

  void run_one(std::uint64_t i, std::size_t k, const GenCase& c) {
    if (!asks(k, first_ + i)) return;
    try {
      verdict(i, k) = verdict_code(run_method(ms_[k], c));
    } catch (const std::exception& e) {
      note_fault(first_ + i, k, e.what());
    }
  }

  // A verdict on a camera path, kept when the case is one of the run's.
  auto keep_verdicts(std::uint64_t path, std::size_t k) {
    return [this, path, k](std::size_t frame, std::size_t object, const Answer& a) {
      const std::uint64_t index = gen::path_case_index({path, frame, object});
      if (index >= first_ && index < first_ + drawn_ && out_[index - first_].judged && asks(k, index))
        verdict(index - first_, k) = verdict_code(a);
    };
  }

  // The run's cases [a, b) of the frame of case a (relative indices): a family's frame
  // (gen::cases_per_frame), clipped to the run.
  std::uint64_t frame_end(std::uint64_t a) const {
    return std::min(drawn_, a + (per_frame_ - (first_ + a) % per_frame_));
  }
  // The first of the run's cases in the frame of case i (a relative index).
  std::uint64_t frame_start(std::uint64_t i) const { return i - std::min(i, (first_ + i) % per_frame_); }

  // The truth of every case, in parallel, and the verdicts of the methods that are not stateful
  // (off camera paths): frame by frame, as an engine culls, each method preparing the frame once
  // and classifying its volumes in order (a batch method in one call).
  void run_case_by_case() {
    std::vector<std::uint64_t> starts;  // of the frames
    for (std::uint64_t a = 0; a < drawn_; a = frame_end(a)) starts.push_back(a);
    // A method that answers many frames in one call (a program's binary messages) is asked about
    // a chunk's frames together: chunks of about kFramesChunk cases then.
    std::vector<std::size_t> together;
    for (std::size_t k = 0; k < ms_.size(); ++k)
      if (!ms_[k].stateful && ms_[k].has_frames()) together.push_back(k);
    constexpr std::uint64_t kChunk = 64, kFramesChunk = 1024;
    const std::size_t grain = std::max<std::uint64_t>(1, (together.empty() ? kChunk : kFramesChunk) / per_frame_);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, starts.size(), grain),
                      [&](const tbb::blocked_range<std::size_t>& r) {
      if (stopped()) return;
      std::uint64_t judged = 0;
      std::vector<GenCase> cases;
      std::vector<CaseFrustum> frame(1);
      std::vector<Volume> volumes;
      thread_local ChunkFrames chunk;  // kept: its arrays are reused chunk after chunk
      chunk.clear();
      for (std::size_t u = r.begin(); u != r.end(); ++u) {
        const std::uint64_t a = starts[u], b = frame_end(a);
        frame_cases(a, b, cases);
        for (std::uint64_t i = a; i < b; ++i) {
          const GenCase& c = cases[i - a];
          validate(c.volume);
          out_[i].truth = oracle::truth(c.frustum, c.volume);
          out_[i].float_exact = gen::float_exact(c.frustum, c.volume);
          out_[i].kind = std::uint8_t(volume_kind(c.volume));
          out_[i].judged = true;
        }
        judged += b - a;
        if (on_paths_) continue;
        frame[0] = cases[0].frustum;
        volumes.clear();
        for (const GenCase& c : cases) volumes.push_back(c.volume);
        for (std::size_t k = 0; k < ms_.size(); ++k)
          if (!ms_[k].stateful && !ms_[k].has_frames()) run_frame(a, b, k, cases, frame, volumes);
        if (!together.empty()) chunk.add(a, b, cases);
      }
      for (std::size_t k : together) run_chunk(k, chunk);
      progress_.add(judged);
    });
  }

  // The frames of a chunk of cases, kept for the methods asked about them together: each frame's
  // frustum and the chunk's volumes, frame after frame.
  struct ChunkFrames {
    std::vector<std::pair<std::uint64_t, std::uint64_t>> bounds;  // [a, b) of each frame
    std::vector<CaseFrustum> frusta;
    std::vector<Volume> volumes;
    void clear() {
      bounds.clear();
      frusta.clear();
      volumes.clear();
    }
    void add(std::uint64_t a, std::uint64_t b, const std::vector<GenCase>& c) {
      bounds.emplace_back(a, b);
      frusta.push_back(c[0].frustum);
      for (const GenCase& g : c) volumes.push_back(g.volume);
    }
  };

  // Method k on a chunk's frames in one call (Method::classify_frames). Where it faults, the
  // frames are asked one by one (run_frame, each frame's cases drawn again), so that the fault is
  // charged to the case that makes it, as ever.
  void run_chunk(std::size_t k, const ChunkFrames& chunk) {
    if (chunk.bounds.empty() || !asks(k, first_ + chunk.bounds.front().first)) return;
    std::vector<FrameRequest> frames(chunk.bounds.size());
    for (std::size_t j = 0, at = 0; j < frames.size(); ++j) {
      const std::size_t n = chunk.bounds[j].second - chunk.bounds[j].first;
      frames[j] = FrameRequest{&chunk.frusta[j], chunk.volumes.data() + at, n};
      at += n;
    }
    std::vector<Answer> answers;
    try {
      detail::run_frames(ms_[k], frames, answers);
    } catch (const std::exception&) {
      std::vector<GenCase> cases;
      std::vector<CaseFrustum> frame(1);
      for (std::size_t j = 0; j < frames.size(); ++j) {
        const auto [a, b] = chunk.bounds[j];
        frame_cases(a, b, cases);
        frame[0] = cases[0].frustum;
        const std::vector<Volume> volumes(frames[j].volumes, frames[j].volumes + frames[j].count);
        run_frame(a, b, k, cases, frame, volumes);
      }
      return;
    }
    std::size_t at = 0;
    for (const auto& [a, b] : chunk.bounds)
      for (std::uint64_t i = a; i < b; ++i, ++at)
        if (asks(k, first_ + i)) verdict(i, k) = verdict_code(answers[at]);
  }

  // Method k on the frame of cases [a, b) (`cases`; `frame` their frustum, `volumes` theirs): one
  // case alone as ever; several as one frame. A fault on the frame (a batch call names no single
  // volume) is looked for case by case, so that the fault is charged to the case that makes it;
  // one the cases alone do not make is the frame's.
  void run_frame(std::uint64_t a, std::uint64_t b, std::size_t k, const std::vector<GenCase>& cases,
                 const std::vector<CaseFrustum>& frame, const std::vector<Volume>& volumes) {
    if (b - a == 1) return run_one(a, k, cases[0]);
    if (!asks(k, first_ + a)) return;
    try {
      run_path(ms_[k], frame, 0, 0, volumes, [&](std::size_t, std::size_t o, const Answer& v) {
        if (asks(k, first_ + a + o)) verdict(a + o, k) = verdict_code(v);
      }, /*reset=*/false);
    } catch (const PathFault& e) {
      for (std::uint64_t i = a; i < b && asks(k, first_ + i); ++i) run_one(i, k, cases[i - a]);
      if (asks(k, first_ + b - 1))
        note_fault(first_ + a + e.object, k,
                   fmt::format("{} (on the frame of cases {} to {}, classified in order; no case alone makes it)", e.what(),
                               first_ + a, first_ + b - 1));
    }
  }

  // On camera paths every method meets each frame as an engine does: prepared once, then the
  // frame's objects classified in order (so a state leaking from one volume to the next within a
  // frame is exercised); the methods that are not stateful frame by frame in parallel.
  void run_path_frames() {
    std::vector<std::pair<std::uint64_t, std::size_t>> frames;  // (path, frame) of the run's cases
    for (std::uint64_t i = 0; i < drawn_; ++i) {
      const gen::PathIndex at = gen::path_index(first_ + i);
      if (frames.empty() || frames.back() != std::make_pair(at.path, at.frame)) frames.emplace_back(at.path, at.frame);
    }
    tbb::parallel_for(std::size_t(0), frames.size(), [&](std::size_t u) {
      if (stopped()) return;
      const auto [number, f] = frames[u];
      const gen::CameraPath& cp = paths_.at(number);
      for (std::size_t k = 0; k < ms_.size(); ++k) {
        if (ms_[k].stateful || !asks(k, gen::path_case_index({number, f, 0}))) continue;
        try {
          run_path(ms_[k], cp.frames, f, f, cp.objects, keep_verdicts(number, k), /*reset=*/false);
        } catch (const PathFault& e) {
          note_fault(gen::path_case_index({number, e.frame, e.object}), k,
                     fmt::format("{} (camera path frame {}, object {}; the frame's objects classified in order)",
                                 e.what(), e.frame, e.object));
        }
      }
    });
  }

  // Each stateful method on one thread (different ones at once): over each camera path from its
  // first frame to the last frame a case of the run is on; elsewhere case by case, each a path of
  // one frame.
  void run_stateful() {
    std::vector<std::size_t> stateful;
    for (std::size_t k = 0; k < ms_.size(); ++k)
      if (ms_[k].stateful) stateful.push_back(k);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, stateful.size(), 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t u = r.begin(); u != r.end(); ++u) run_stateful(stateful[u]);
                      },
                      tbb::simple_partitioner());
  }

  void run_stateful(std::size_t k) {
    if (!on_paths_) {
      std::vector<GenCase> cases;
      for (std::uint64_t a = 0; a < drawn_ && asks(k, first_ + a) && !stopped(); a = frame_end(a)) {
        const std::uint64_t b = frame_end(a);
        frame_cases(a, b, cases);
        for (std::uint64_t i = a; i < b; ++i)
          if (out_[i].judged) run_one(i, k, cases[i - a]);
      }
      return;
    }
    for (const auto& [number, cp] : paths_) {
      const std::uint64_t base = gen::path_case_index({number, 0, 0});
      if (!asks(k, base) || stopped()) break;
      const std::uint64_t last = std::min(base + gen::kPathFrames * gen::kPathObjects, first_ + drawn_) - 1;
      try {
        run_path(ms_[k], cp.frames, 0, gen::path_index(last).frame, cp.objects, keep_verdicts(number, k));
      } catch (const PathFault& e) {
        note_fault(gen::path_case_index({number, e.frame, e.object}), k,
                   fmt::format("{} (camera path frame {}, object {})", e.what(), e.frame, e.object));
      }
    }
  }

  // Each method's fault, if it had one, with its case saved.
  std::vector<std::optional<MethodFault>> collect_faults() const {
    std::vector<std::optional<MethodFault>> faults(ms_.size());
    for (std::size_t k = 0; k < ms_.size(); ++k) {
      const std::uint64_t at = fault_at_[k].load();
      if (at == kNoFault) continue;
      const Method& m = ms_[k];
      if (on_paths_) {
        PathCase pc = path_case_at(at);
        if (!m.stateful) pc.frames = {pc.frames.back()};
        const GenCase g = gen::path_case(paths_.at(gen::path_index(at).path), gen::path_index(at).frame, pc.object);
        faults[k] = make_fault(opt_, m, d_, at, g, fault_problem_[k], &pc);
      } else {
        faults[k] = make_fault(opt_, m, d_, at, case_at(at - first_), fault_problem_[k]);
      }
    }
    return faults;
  }

  // Whether some method's verdict on case i is an error.
  bool erred(std::uint64_t i) const {
    const CaseOutcome& o = out_[i];
    if (!o.judged) return false;
    for (std::size_t k = 0; k < ms_.size(); ++k) {
      const std::int8_t v = verdict(i, k);
      if (v >= 0 && error_class(Visibility(v), o.truth, ms_[k].three_way_on(o.kind)) != ErrorClass::correct) return true;
    }
    return false;
  }

  // The oracle's distance (an exact QP for outside volumes), the case scale and size, once per case
  // that some method got wrong, and the distance of each wrong verdict from the truth where a claim
  // is judged on it, in parallel: they depend on the case and the verdict, not on the method.
  void measure_errors() {
    erring_.clear();
    for (std::uint64_t i = 0; i < drawn_; ++i)
      if (erred(i)) erring_.push_back(i);
    measures_.assign(erring_.size(), ErrorMeasure{});
    // The erring cases frame by frame: each frame's run from its first erring case to its last
    // drawn once (its camera once).
    std::vector<std::size_t> runs;  // where each frame's erring cases start in erring_
    for (std::size_t e = 0; e < erring_.size(); ++e)
      if (e == 0 || frame_start(erring_[e]) != frame_start(erring_[e - 1])) runs.push_back(e);
    runs.push_back(erring_.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, runs.size() - 1, 4), [&](const tbb::blocked_range<std::size_t>& r) {
      std::vector<GenCase> cases;
      for (std::size_t u = r.begin(); u != r.end(); ++u) {
        const std::uint64_t a = erring_[runs[u]];
        frame_cases(a, erring_[runs[u + 1] - 1] + 1, cases);
        for (std::size_t e = runs[u]; e < runs[u + 1]; ++e) measure(erring_[e], cases[erring_[e] - a], measures_[e]);
      }
    });
  }

  // What the table and the claims need of erring case i (c).
  void measure(std::uint64_t i, const GenCase& c, ErrorMeasure& m) const {
    const CaseOutcome& o = out_[i];
    // The distance is reported for false intersects only (the table's FI distance).
    bool false_intersect = false;
    for (std::size_t k = 0; k < ms_.size() && o.truth == Visibility::outside && !false_intersect; ++k)
      false_intersect = verdict(i, k) == std::int8_t(Visibility::intersecting);
    if (false_intersect) m.distance = oracle::distance(c.frustum, c.volume, o.truth);
    m.scale = gen::case_scale(c.frustum, c.volume);
    m.scene_size = c.scene_size;
    for (std::size_t k = 0; k < ms_.size(); ++k) {
      const std::int8_t v = verdict(i, k);
      if (v < 0 || m.verdict_distance[std::size_t(v)] != ErrorMeasure::kUnmeasured) continue;
      if (needs_distance(ms_[k].claim, error_class(Visibility(v), o.truth, ms_[k].three_way_on(o.kind)), o.float_exact))
        m.verdict_distance[std::size_t(v)] = error_distance(c.frustum, c.volume, Visibility(v));
    }
  }

  // The measures at position e of the erring cases (erring_ is in case order), which must be case
  // i's.
  const ErrorMeasure& measure_at(std::size_t e, std::uint64_t i) const {
    if (e >= erring_.size() || erring_[e] != i) throw std::logic_error(fmt::format("case {} was not measured as an error", first_ + i));
    return measures_[e];
  }

  // Timing frames, drawn once per set of volume kinds (methods that take the same kinds are timed
  // on the same volumes).
  std::map<unsigned, std::vector<KindedFrame>> timing_frames() const {
    std::map<unsigned, std::vector<KindedFrame>> frames;
    if (opt_.timing)
      for (const Method& m : ms_)
        if (!frames.count(m.volumes)) {
          std::vector<KindedFrame>& fs = frames[m.volumes];
          for (int j = 0; j < opt_.timing_frames; ++j)
            fs.push_back(split(gen::draw_frame(d_, opt_.seed, std::uint64_t(j), opt_.frame_size, m.volumes)));
        }
    return frames;
  }

  // The distance a method's error is judged on (error_distance), measured where its claim needs it.
  double judged_distance(std::size_t k, std::uint64_t i, ErrorClass cls, const ErrorMeasure& me) const {
    if (!needs_distance(ms_[k].claim, cls, out_[i].float_exact)) return std::numeric_limits<double>::infinity();
    return me.verdict_distance[std::size_t(verdict(i, k))];
  }

  // One of method k's errors to record in the corpus: case i, its class, whether it breaks the
  // claim.
  struct Pending {
    std::uint64_t i;
    ErrorClass cls;
    bool violation;
    double rank = 0.0;  // of a violation: how far beyond its allowance (CorpusCandidate::rank)
  };
  // What recording it takes: the corpus's record of it already (held), or the case shrunk from it
  // (with the camera path or frame it needs) and the method's verdict there (nullopt: none, or a
  // fault, which is the method's MethodStats::fault).
  struct Shrunk {
    std::optional<CorpusRecord> held;
    GenCase small;
    std::optional<PathCase> path;
    Answer verdict;
  };

  // Method k's counts over the cases, and the errors of it to record in the corpus (`pending`).
  MethodStats tally(std::size_t k, std::vector<Pending>& pending) {
    const Method& m = ms_[k];
    MethodStats s;
    s.method = m.name;
    s.program = m.program;
    s.claim = m.claim;
    s.origin = m.origin;
    s.three_way = m.three_way;
    s.two_way_kinds = m.three_way ? m.two_way_kinds & m.volumes : 0;
    s.volumes = m.volumes;
    std::map<ErrorClass, int> written;
    // Claim violations per class: (allowances beyond which the error lies, case).
    constexpr double kUnbounded = std::numeric_limits<double>::infinity();
    std::map<ErrorClass, std::vector<std::pair<double, std::uint64_t>>> violating;
    const std::uint64_t fault_at = fault_at_[k].load();
    std::size_t next_erring = 0;  // the cases go up: the erring ones are met in order
    for (std::uint64_t i = 0; i < drawn_ && first_ + i < fault_at; ++i) {
      if (!out_[i].judged || verdict(i, k) < 0) continue;
      const Visibility t = out_[i].truth;
      ++s.cases;
      (t == Visibility::outside ? s.truth_outside : t == Visibility::inside ? s.truth_inside : s.truth_intersecting)++;
      const bool three_way = m.three_way_on(out_[i].kind);
      if (t == Visibility::inside && three_way) ++s.truth_inside_three_way;
      const ErrorClass cls = error_class(Visibility(verdict(i, k)), t, three_way);
      switch (cls) {
        case ErrorClass::correct: continue;
        case ErrorClass::false_reject: ++s.false_reject; break;
        case ErrorClass::false_inside: ++s.false_inside; break;
        case ErrorClass::false_intersect: ++s.false_intersect; break;
        case ErrorClass::under_inside: ++s.under_inside; break;
      }
      while (next_erring < erring_.size() && erring_[next_erring] < i) ++next_erring;
      const ErrorMeasure& me = measure_at(next_erring, i);
      const double judged = judged_distance(k, i, cls, me);
      const bool violation = violates_claim(m.claim, cls, judged, m.tolerance, me.scale, out_[i].float_exact);
      if (violation && out_[i].float_exact) ++s.float_exact_violations;
      if (violation) ++s.claim_violations;
      if (violation && !s.first_violation) {
        s.first_violation = first_ + i;
        s.first_violation_reproduce = reproduce_command(opt_.seed, d_, first_ + i, m);
      }
      if (cls == ErrorClass::false_intersect) s.fi_distance.push_back(me.distance / me.scene_size);
      // Corpus: corpus_per_class of the errors a claim allows (the expected false intersects and
      // under-insides of conservative methods), the first ones; the claim violations are chosen
      // below.
      if (violation) {
        const double allowance = m.tolerance * me.scale;
        violating[cls].push_back({std::isfinite(judged) && allowance > 0.0 ? judged / allowance : kUnbounded, i});
      } else if (opt_.corpus && written[cls] < opt_.corpus_per_class) {
        ++written[cls];
        pending.push_back({i, cls, false});
      }
    }
    // The claim violations of each class farthest beyond their allowance (keep_farthest).
    if (opt_.corpus)
      for (auto& [cls, v] : violating) {
        keep_farthest(v, [](const auto& x) { return x.first; });
        for (const auto& [rank, i] : v) pending.push_back({i, cls, true, rank});
      }
    return s;
  }

  // Case i with its frame's volumes (a framed family's frame, clipped to the run), as a path of one
  // frame.
  PathCase frame_case_at(std::uint64_t i) const {
    const std::uint64_t a = frame_start(i), b = frame_end(a);
    std::vector<GenCase> cases;
    frame_cases(a, b, cases);
    PathCase pc;
    pc.frames = {cases[0].frustum};
    for (const GenCase& c : cases) pc.objects.push_back(c.volume);
    pc.object = std::size_t(i - a);
    pc.motion = "still";
    return pc;
  }

  // Method k's errors to record, each shrunk unless the corpus holds its record already
  // (CorpusSources: the same seed, case and class, still reproducing). On a camera path, an error
  // that needs what came before (earlier frames for a stateful method, the frame's earlier objects
  // for any) is kept with its path; so is an error on a framed family's case that needs the frame's
  // earlier volumes.
  std::vector<Shrunk> shrink_errors(std::size_t k, const std::vector<Pending>& pending, MethodStats& s) const {
    std::vector<Shrunk> out(pending.size());
    if (pending.empty()) return out;
    const Method& m = ms_[k];
    const CorpusSources sources(*opt_.corpus, m.name, d_);
    for (std::size_t j = 0; j < pending.size(); ++j) {
      const auto [i, cls, violation, rank] = pending[j];
      Shrunk& r = out[j];
      r.held = sources.held(m, opt_.seed, first_ + i, cls, /*judge=*/violation);
      if (r.held) continue;
      const Visibility t = out_[i].truth;
      const GenCase c = case_at(i);
      auto alone_shows_it = [&] {
        try {
          const Answer a = run_method(m, c);
          return a && error_class(*a, t, m.three_way_on(c.volume)) == cls;
        } catch (const std::exception&) {
          return false;
        }
      };
      const bool framed = !on_paths_ && per_frame_ > 1 && !m.stateful;
      if ((on_paths_ && (m.stateful || !alone_shows_it())) || (framed && !alone_shows_it())) {
        PathCase pc = on_paths_ ? path_case_at(first_ + i) : frame_case_at(i);
        if (!m.stateful) pc.frames = {pc.frames.back()};
        r.path = shrink_path(std::move(pc), m, cls, t, opt_.shrink_budget);
        r.small = c;
      } else {
        r.small = shrink(d_, opt_.seed, first_ + i, m, cls, violation, opt_.shrink_budget);
      }
      try {
        r.verdict = r.path ? checked_classify_path(m, *r.path) : run_method(m, r.small);
      } catch (const std::exception& e) {
        // The case shrunk from case i makes the method fault: that case is the fault's.
        r.verdict.reset();
        if (!s.fault)
          s.fault = make_fault(opt_, m, d_, first_ + i, r.small,
                               fmt::format("{} (on the case shrunk from case {})", e.what(), first_ + i),
                               r.path ? &*r.path : nullptr);
      }
    }
    return out;
  }

  // Writes method k's shrunk error to the corpus (unless held there already) and counts it.
  void write_record(std::size_t k, const Pending& p, const Shrunk& r, MethodStats& s) const {
    CorpusRecord rec;
    if (r.held) {
      rec = *r.held;
    } else {
      if (!r.verdict) {  // the shrunk case faulted: no record, in its place too when merged
        if (opt_.shard) s.corpus_candidates.push_back({first_ + p.i, p.cls, p.violation, p.rank, {}, {}, false, {}});
        return;
      }
      rec = write_corpus_case(*opt_.corpus, r.small, ms_[k], *r.verdict, d_, opt_.seed, first_ + p.i, ms_,
                              r.path ? &*r.path : nullptr);
    }
    if (rec.written) s.corpus_written.push_back(rec.id);
    if (opt_.shard) s.corpus_candidates.push_back({first_ + p.i, p.cls, p.violation, p.rank, rec.id, rec.file, rec.violates, rec.text});
    // Evidence of a counted violation that the shrunk case still shows (shrinking keeps it).
    if (p.violation && rec.violates &&
        std::find(s.violation_ids.begin(), s.violation_ids.end(), rec.id) == s.violation_ids.end())
      s.violation_ids.push_back(rec.id);
  }

  const VerifyOptions& opt_;
  const std::vector<Method>& ms_;
  const gen::Distribution d_;
  Progress& progress_;
  const std::uint64_t per_, first_;
  const bool on_paths_;
  const std::uint64_t per_frame_;  // gen::cases_per_frame
  std::vector<CaseOutcome> out_;
  std::vector<std::int8_t> verdicts_;  // per case, per method: Visibility, kNotApplying or kNotAsked
  std::vector<std::uint64_t> erring_;  // the cases some method got wrong, in order
  std::vector<ErrorMeasure> measures_;  // theirs
  std::uint64_t drawn_ = 0;  // cases of the run (all of per_ unless stopped while paths were drawn)
  std::map<std::uint64_t, gen::CameraPath> paths_;
  std::mutex fault_mutex_;
  std::vector<std::atomic<std::uint64_t>> fault_at_;  // per method: the smallest index it faulted on
  std::vector<std::string> fault_problem_;            // under fault_mutex_
};

}  // namespace

std::pair<std::uint64_t, std::uint64_t> shard_cases(gen::Distribution d, std::uint64_t cases, const Shard& shard) {
  if (shard.count == 0 || shard.index >= shard.count)
    throw std::invalid_argument(fmt::format("shard {}/{}: the index must be below the count", shard.index, shard.count));
  const std::uint64_t unit =
      d == gen::Distribution::camera_path ? std::uint64_t(gen::kPathFrames * gen::kPathObjects) : gen::cases_per_frame(d);
  const std::uint64_t frames = cases / unit + (cases % unit != 0);
  // frames * index / count without overflow: frames and count are below 2^64, their product may not be.
  const auto cut = [&](std::uint64_t k) {
    return std::uint64_t((static_cast<unsigned __int128>(frames) * k) / shard.count);
  };
  return {std::min(cases, cut(shard.index) * unit), std::min(cases, cut(shard.index + 1) * unit)};
}

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
  result.options.on_distribution = nullptr;
  if (opt.shard && opt.only_index) throw std::invalid_argument("a shard and a single case (--index) together");
  std::uint64_t total = 0;
  for (gen::Distribution d : opt.distributions) total += range_of(opt, d).second;
  Progress progress(opt.progress, total);
  for (gen::Distribution d : opt.distributions) {
    if (opt.stop && opt.stop->load()) {
      result.interrupted = true;
      break;
    }
    progress.label(std::string(gen::to_string(d)));
    result.distributions.push_back(DistributionRun(opt, ms, d, progress).run());
    if (opt.on_distribution) progress.print([&] { opt.on_distribution(result.distributions.back()); });
    if (result.distributions.back().interrupted) {
      result.interrupted = true;
      break;
    }
  }
  progress.finish();
  result.wall_seconds = std::chrono::duration<double>(Clock::now() - t_start).count();
  return result;
}

}  // namespace cullproof
