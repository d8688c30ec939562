// The judge: what a claim forbids and how far an error lies from being right (error classes, the
// claim rule, the distance it is judged on), and calling a method as the campaign does, every
// answer checked (one case, or a camera path frame after frame). Definitions: docs/semantics.md
// "Errors" and "Claims".
#pragma once

#include "cullproof/gen/generators.hpp"
#include "cullproof/methods/methods.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace cullproof {

/// Error class of a verdict against the truth (docs/semantics.md "Errors").
enum class ErrorClass : std::uint8_t { correct, false_reject, false_inside, false_intersect, under_inside };
/// "correct", "false-reject", "false-inside", "false-intersect", "under-inside".
std::string_view to_string(ErrorClass e) noexcept;
/// The class of `verdict` when the truth is `truth`. A two-way method (three_way == false)
/// answers `intersecting` for "visible": it is never charged with an under-inside.
ErrorClass error_class(Visibility verdict, Visibility truth, bool three_way = true) noexcept;
/// Whether an error of class `e` at distance `distance` from being right (error_distance) breaks `claim`, for a
/// method with rounding tolerance `tolerance` (relative to `scale`, see Method::tolerance). On a
/// float-exact case (gen::float_exact) nothing rounds, so `conservative` and `exact` claims get no
/// allowance: every error they forbid breaks them, however close to the boundary. A tolerance of
/// 0 forgives nothing, not even an error at distance 0.
bool violates_claim(Claim claim, ErrorClass e, double distance, double tolerance, double scale, bool float_exact) noexcept;

/// The distance a claim's rounding allowance is compared with: how far `verdict` lies from being
/// the truth, the smallest shift of the planes (or of the volume, which never needs less) that
/// makes it the truth, measured toward the verdict given (oracle::distance_to_verdict, a proven
/// lower bound). `inside` for a volume that straddles the frustum is as far as the volume
/// protrudes; `outside` for one that lies inside, as deep as it reaches in. +infinity when no
/// shift helps (a plane that contains nothing, or none that limits space).
double error_distance(const CaseFrustum& f, const Volume& v, Visibility verdict);
/// Whether violates_claim's answer for an error of class `e` depends on its distance (a claim
/// that forgives it within a tolerance or a band), so that the distance must be measured.
bool needs_distance(Claim claim, ErrorClass e, bool float_exact) noexcept;

/// Runs method `m` on one case as the campaign does (prepare, then classify; a stateful method is
/// reset() first: the case is a camera path of one frame), checking what it answers:
/// std::nullopt when it does not take the volume or does not apply. Throws
/// std::runtime_error naming the method and the problem when it throws or answers a value that
/// is not a verdict (or `inside`, being two-way).
Answer checked_classify(const Method& m, const CaseFrustum& f, const Volume& v);

/// A case on a camera path: the frames up to the one it is judged on (the last), the objects the
/// path shows every frame, and the one judged. A stateful method needs the frames before; any
/// method may need the objects classified before it in the frame (a state it keeps from one volume
/// to the next).
struct PathCase {
  std::vector<CaseFrustum> frames;
  std::vector<Volume> objects;
  std::size_t object = 0;
  std::string motion;  ///< gen::CameraPath::motion, for the record
  /// The case judged: the last frame and the object.
  CaseFrustum frustum() const { return frames.back(); }
  const Volume& volume() const { return objects.at(object); }
};

/// Runs method `m` over the path as the campaign does and returns its answer for the object judged
/// on the last frame (std::nullopt when it does not take the volume or does not apply): a stateful
/// method from reset() through every frame in order, each prepared and then classified in full
/// (see cullproof/methods/methods.hpp); any other on the last frame alone, prepared once with its objects
/// classified in order. Checks every answer as checked_classify does and throws
/// std::runtime_error naming the method, the frame and the object on a fault.
Answer checked_classify_path(const Method& m, const PathCase& p);
/// A path case as the corpus records it (field "path" of a case: motion, object, frames, objects
/// in the case format's frustum and volume forms).
nlohmann::json to_json(const PathCase& p);
/// Reads a recorded path; throws std::runtime_error naming `where` and the field that is wrong.
PathCase path_from_json(const nlohmann::json& j, const std::string& where);

/// Wilson score interval (95%) for k successes in n trials: {low, high}; {0, 0} when n == 0.
std::pair<double, double> wilson95(std::uint64_t k, std::uint64_t n) noexcept;
/// k of n in percent with that interval, two decimals: "3.35 [2.01, 5.54]"; "-" when n == 0.
std::string percent_ci95(std::uint64_t k, std::uint64_t n);

namespace detail {

/// A fault on a camera path and where it happened.
struct PathFault : std::runtime_error {
  PathFault(const std::string& what, std::size_t f, std::size_t o) : std::runtime_error(what), frame(f), object(o) {}
  std::size_t frame, object;
};

/// Receives (frame, object, answer) for each object a method takes on a camera path. It refers to
/// a callable (nothing copied, nothing allocated), which must outlive the call it is passed to.
class PathSink {
 public:
  template <class F, class = std::enable_if_t<!std::is_same_v<std::decay_t<F>, PathSink>>>
  PathSink(F&& f) noexcept  // implicit: a lambda is passed where a sink is asked for
      : callable_(static_cast<const void*>(std::addressof(f))),
        call_([](const void* c, std::size_t frame, std::size_t object, const Answer& answer) {
          (*static_cast<std::remove_reference_t<F>*>(const_cast<void*>(c)))(frame, object, answer);
        }) {}
  void operator()(std::size_t frame, std::size_t object, const Answer& answer) const {
    call_(callable_, frame, object, answer);
  }

 private:
  const void* callable_;
  void (*call_)(const void*, std::size_t, std::size_t, const Answer&);
};

/// Runs method `m` over frames[first..last] of a camera path with `objects` (see the contract in
/// cullproof/methods/methods.hpp), after reset() when `reset`; sink(frame, object, answer) for each
/// object it takes, every frame. Throws PathFault.
void run_path(const Method& m, const std::vector<CaseFrustum>& frames, std::size_t first, std::size_t last,
              const std::vector<Volume>& objects, const PathSink& sink, bool reset = true);

/// checked_classify on a generated case.
std::optional<Visibility> run_method(const Method& m, const gen::GenCase& c);

/// Method m (not stateful) on several frames at once (Method::classify_frames): answers[j] for
/// the j-th volume over all frames, frame after frame; std::nullopt for a volume it does not take.
/// Each frame's volumes are asked by kind, in the order points, spheres, boxes, OBBs, as run_path
/// asks a batch method. Throws std::runtime_error naming the method for what it throws or an
/// answer it may not give; which frame is at fault, the caller finds by asking frame by frame.
void run_frames(const Method& m, const std::vector<FrameRequest>& frames, std::vector<Answer>& answers);

}  // namespace detail

}  // namespace cullproof
