// Culling methods: how cullproof sees a culler, its own or a user's.
//
// A method is a description (MethodInfo: a stable name, its claim, the volume kinds it takes,
// where it comes from) and a culler in two phases, as real cullers run:
//  - prepare(frustum), once per frame: plane normalisation, look-up tables, certified margins,
//    SIMD broadcasts; it returns the method's state for that frustum (or says the method does not
//    apply to it, e.g. the octant test on an asymmetric frustum);
//  - classify(state, volume) per volume, and optionally classify_batch(state, volumes) for a
//    method that culls arrays.
// The frustum reaches prepare as the case gives it (CaseFrustum: the planes, and the clip matrix
// with its depth convention when the case is a matrix), so a method that extracts its own planes
// from the matrix is under test end to end.
//
// make_method() turns plain functions into a Method:
//
//   cullproof::MethodInfo info;
//   info.name = "my-culler";
//   info.claim = cullproof::Claim::conservative;
//   info.tolerance = 1e-6;
//   auto m = cullproof::make_method(info,
//       [](const cullproof::CaseFrustum& f) { return my_planes(f.planes); },       // prepare
//       [](const MyPlanes& p, const cullproof::Aabb& b) { return my_test(p, b); }); // classify
//
// classify may take `const Volume&` or any of Point, Sphere, Aabb, Obb (overloads allowed); the
// volume kinds it takes are the method's unless `info.volumes` names fewer. It returns a
// Visibility (three-way), a bool (two-way: true = visible, which counts as `intersecting`), or a
// std::optional<Visibility> (std::nullopt: the method does not apply to this volume). prepare
// returns the state by value, or a std::optional of it (std::nullopt: the method does not apply
// to this frustum).
//
// Contracts the harness relies on: prepare and classify of a method that is not stateful may run
// concurrently on different frames. A stateful method (frame coherency) is run on one thread and
// reset() before each camera path; it sees the frames of a path in order, each frame prepared
// and then classified in full before the next is prepared, and every frame of a path presents
// the same objects (those of the kinds it takes) in the same order: through classify_batch, one
// call per kind in the order points, spheres, boxes, OBBs, when the method has an array form;
// otherwise classify once per object, in path order. So the k-th volume classified in a frame is
// object k, which is how a method keys its per-object state. A case outside a camera path is a
// path of one frame and one object. A method that is not stateful also meets a camera-path frame
// prepared once with its objects classified in order, so what its PreparedFrustum keeps from one
// volume to the next is under test too. (See gen::CameraPath for the paths the campaign draws.)
#pragma once

#include "cullproof/core/frustum_build.hpp"
#include "cullproof/core/geometry.hpp"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace cullproof {

/// What a method promises (README "Semantics").
enum class Claim {
  certified_conservative,  ///< never a false reject or false inside, rounding included
  certified_exact,         ///< as above, and no other error beyond a proven band
  conservative,            ///< conservative in exact arithmetic; float errors within tolerance
  exact,                   ///< exact in exact arithmetic; float errors within tolerance
  none,                    ///< no promise (heuristic, or a published method under test)
};
/// "certified-conservative", "certified-exact", "conservative", "exact", "none".
std::string_view to_string(Claim c) noexcept;
/// Parses a name produced by to_string(Claim); throws std::invalid_argument listing the names.
Claim claim_from_string(std::string_view s);

/// Where a method comes from, which decides what a refuted claim means.
enum class Origin : std::uint8_t {
  published,  ///< a text under test: a refuted claim is a finding, reported
  own,        ///< one of cullproof's own: a refuted claim is a bug and fails the run
  user,       ///< a user's culler under verification: a refuted claim fails the run
};
/// "published", "own", "user".
std::string_view to_string(Origin o) noexcept;

/// A method's description, by named fields.
struct MethodInfo {
  std::string name;         ///< kebab-case, stable: reports, the corpus and scripts key on it
  std::string description;  ///< one line
  std::string source;       ///< text and section, e.g. "Assarsson & Möller 2000, §3.1"
  Claim claim = Claim::none;
  /// VolumeKind bits this method takes. make_method fills it from what classify takes when it
  /// is 0, and refuses a kind that classify cannot take.
  unsigned volumes = 0;
  std::string touching;     ///< how a volume touching a plane is classified
  /// For `conservative` / `exact` claims: float errors are allowed only on cases within
  /// `tolerance` times the case's scale (what the plane evaluations round, in distance units;
  /// gen::case_scale) of a case for which the verdict given is the truth (the distance is
  /// measured toward that verdict: oracle::distance_to_verdict). 0 for certified claims.
  double tolerance = 0.0;
  /// Whether the method can answer `inside`. A two-way method answers visible (`intersecting`)
  /// or `outside` only; it is never charged with under-insides, and answering `inside` is a
  /// fault. make_method sets it to false for a classify that returns bool.
  bool three_way = true;
  /// VolumeKind bits it answers two-way although it is three-way on the others (a culler whose box
  /// test tells inside from intersecting and whose sphere test only visible from outside).
  unsigned two_way_kinds = 0;
  /// Whether it answers three-way on volumes of kind `kind_bit` (then under-insides are charged and
  /// `inside` may be answered), or on `v`.
  bool three_way_on(unsigned kind_bit) const noexcept { return three_way && !(two_way_kinds & kind_bit); }
  bool three_way_on(const Volume& v) const noexcept { return three_way_on(volume_kind(v)); }
  /// A frame-coherent culler: its state carries over from frame to frame (see reset()).
  bool stateful = false;
  /// A user's method unless it says otherwise: its refuted claim fails the run.
  Origin origin = Origin::user;
  /// For a method behind a program (cullproof/protocol/external.hpp): the program's command line, which
  /// the reproduce lines of its cases name. Such a method is timed alone, one after another.
  std::string program;
  /// The options that bring this method into `cullproof verify`, where they are not `--method NAME`
  /// (a built-in's) or `--external NAME -- PROGRAM`: a shader's `--shader FILE`. The reproduce lines
  /// of its cases name them. Empty for a method defined in a user's code (its test's environment
  /// reruns a case).
  std::string reproduce;

  bool takes(const Volume& v) const noexcept { return (volumes & volume_kind(v)) != 0; }
  bool takes(unsigned kind_bit) const noexcept { return (volumes & kind_bit) != 0; }
};

/// A method's answer for one volume: a verdict, or std::nullopt when the method does not apply
/// to it (the harness leaves it out of the method's counts).
using Answer = std::optional<Visibility>;

/// What prepare() made of one frustum. Classifies volumes of the kinds the method takes; one
/// object is used by one thread at a time.
class PreparedFrustum {
 public:
  virtual ~PreparedFrustum() = default;
  virtual Answer classify(const Volume& v) = 0;
  /// answers[i] for volumes[i], i < n.
  virtual void classify_batch(const Point* volumes, std::size_t n, Answer* answers) = 0;
  virtual void classify_batch(const Sphere* volumes, std::size_t n, Answer* answers) = 0;
  virtual void classify_batch(const Aabb* volumes, std::size_t n, Answer* answers) = 0;
  virtual void classify_batch(const Obb* volumes, std::size_t n, Answer* answers) = 0;
};

/// A PreparedFrustum whose four array forms are one template, Derived::many(const K* volumes,
/// std::size_t n, Answer* answers) for each kind K (Derived befriends BatchesByKind<Derived> when
/// it keeps `many` private).
template <class Derived>
class BatchesByKind : public PreparedFrustum {
 public:
  void classify_batch(const Point* v, std::size_t n, Answer* a) override { self().many(v, n, a); }
  void classify_batch(const Sphere* v, std::size_t n, Answer* a) override { self().many(v, n, a); }
  void classify_batch(const Aabb* v, std::size_t n, Answer* a) override { self().many(v, n, a); }
  void classify_batch(const Obb* v, std::size_t n, Answer* a) override { self().many(v, n, a); }

 private:
  Derived& self() { return static_cast<Derived&>(*this); }
};

/// One frame of several asked at once (Method::classify_frames): its frustum and its volumes.
struct FrameRequest {
  const CaseFrustum* frustum = nullptr;
  const Volume* volumes = nullptr;
  std::size_t count = 0;
};

/// One method: its description and its culler.
class Method : public MethodInfo {
 public:
  using Prepare = std::function<std::unique_ptr<PreparedFrustum>(const CaseFrustum&)>;

  Method() = default;
  /// `prepare` returns nullptr when the method does not apply to the frustum. `batch`: the
  /// PreparedFrustum's classify_batch is the method's own array form (timed as such), not a loop.
  Method(MethodInfo info, Prepare prepare, bool batch = false);

  /// Per-frame set-up; nullptr when the method does not apply to this frustum.
  std::unique_ptr<PreparedFrustum> prepare(const CaseFrustum& f) const { return prepare_(f); }
  /// Whether classify_batch is the method's own array form.
  bool has_batch() const noexcept { return batch_; }
  /// Stateful methods: forget every frame seen (a new camera path starts). No-op otherwise.
  void reset() const {
    if (reset_) reset_();
  }
  /// Sets what reset() does (for a stateful method whose state lives outside its frames).
  Method& on_reset(std::function<void()> fn) {
    reset_ = std::move(fn);
    return *this;
  }
  /// A method that times itself (a program behind the process protocol reports the nanoseconds it
  /// spent on each frame's volumes): `fn` returns the nanoseconds and the volumes reported since
  /// its previous call. The campaign shows the method's own figure beside its measured cost.
  Method& on_own_timing(std::function<std::pair<double, std::uint64_t>()> fn) {
    own_timing_ = std::move(fn);
    return *this;
  }
  /// A method that answers many frames in one call: a program behind the process protocol's
  /// binary encoding asks them in one message, so that a round trip is paid per message, not per
  /// frame. `fn(frames, n, answers)` answers every frame's volumes, frame after frame, as if each
  /// frame were prepared and its volumes classified in order (of one kind at a time, as
  /// classify_batch); it throws where one of the frames would (the caller then asks frame by frame
  /// to find which). Not for a stateful method.
  using ClassifyFrames = std::function<void(const FrameRequest* frames, std::size_t n, Answer* answers)>;
  Method& on_frames(ClassifyFrames fn) {
    frames_ = std::move(fn);
    return *this;
  }
  /// Whether classify_frames asks the frames together (on_frames).
  bool has_frames() const noexcept { return bool(frames_); }
  /// Answers for every volume of `frames`, frame after frame: together where the method has a
  /// frames form, else each frame prepared and its volumes classified in order (std::nullopt
  /// for a frame the method does not apply to).
  void classify_frames(const FrameRequest* frames, std::size_t n, Answer* answers) const;
  /// Nanoseconds and volumes the method reported of itself since the previous call ({0, 0}: none).
  std::pair<double, std::uint64_t> take_own_timing() const { return own_timing_ ? own_timing_() : std::pair<double, std::uint64_t>{}; }
  /// One volume against one frustum, set-up included (a convenience: the harness prepares once
  /// per frame); a stateful method is reset() first (a camera path of one frame). std::nullopt
  /// when the method does not apply.
  Answer classify(const CaseFrustum& f, const Volume& v) const;

 private:
  Prepare prepare_;
  std::function<void()> reset_;
  std::function<std::pair<double, std::uint64_t>()> own_timing_;
  ClassifyFrames frames_;
  bool batch_ = false;
};

/// cullproof's own and published methods (39 of them), in a stable order.
const std::vector<Method>& builtin_methods();
/// The built-in method with this name, or nullptr.
const Method* find_builtin(std::string_view name);
/// The built-in methods with these names, in this order; every built-in method when `names` is
/// empty. Throws std::invalid_argument naming an unknown name and listing the known ones.
std::vector<Method> builtin_methods(const std::vector<std::string>& names);

// ---------------------------------------------------------------------------------------------
// make_method: plain functions to a Method

namespace detail {

// The state a prepare returns: S, or std::optional<S> (the method may not apply).
template <class T>
struct unwrap_optional {
  using type = T;
  static constexpr bool maybe = false;
};
template <class T>
struct unwrap_optional<std::optional<T>> {
  using type = T;
  static constexpr bool maybe = true;
};

template <class F, class S, class K>
constexpr bool classifies = std::is_invocable_v<const F&, S&, const K&>;

// Whether classify takes kind K (directly, or as a Volume).
template <class F, class S, class K>
constexpr bool takes_kind = classifies<F, S, K> || classifies<F, S, Volume>;

template <class F, class S>
constexpr unsigned kinds_taken() {
  return (takes_kind<F, S, Point> ? kPointKind : 0u) | (takes_kind<F, S, Sphere> ? kSphereKind : 0u) |
         (takes_kind<F, S, Aabb> ? kAabbKind : 0u) | (takes_kind<F, S, Obb> ? kObbKind : 0u);
}

template <class R>
constexpr bool is_bool_answer = std::is_same_v<std::decay_t<R>, bool>;

template <class R>
Answer to_answer(R&& r) {
  using T = std::decay_t<R>;
  if constexpr (std::is_same_v<T, bool>) {
    return r ? Visibility::intersecting : Visibility::outside;
  } else if constexpr (std::is_same_v<T, Visibility>) {
    return r;
  } else {
    static_assert(std::is_same_v<T, Answer>,
                  "classify must return cullproof::Visibility, bool or std::optional<cullproof::Visibility>");
    return r;
  }
}

// Whether every kind classify takes returns bool (a two-way method).
template <class F, class S>
constexpr bool answers_two_way() {
  bool any = false, all = true;
  auto one = [&](auto tag) {
    using K = typename decltype(tag)::type;
    if constexpr (classifies<F, S, K>) {
      any = true;
      all = all && is_bool_answer<std::invoke_result_t<const F&, S&, const K&>>;
    } else if constexpr (classifies<F, S, Volume>) {
      any = true;
      all = all && is_bool_answer<std::invoke_result_t<const F&, S&, const Volume&>>;
    }
  };
  one(std::common_type<Point>{});
  one(std::common_type<Sphere>{});
  one(std::common_type<Aabb>{});
  one(std::common_type<Obb>{});
  return any && all;
}

struct NoBatch {};

template <class S, class F, class B>
class Prepared final : public BatchesByKind<Prepared<S, F, B>> {
 public:
  Prepared(S state, std::shared_ptr<const F> classify, std::shared_ptr<const B> batch)
      : state_(std::move(state)), classify_(std::move(classify)), batch_(std::move(batch)) {}

  Answer classify(const Volume& v) override {
    return std::visit([this](const auto& x) { return one(x); }, v);
  }

 private:
  friend class BatchesByKind<Prepared>;
  template <class K>
  Answer one(const K& x) {
    if constexpr (classifies<F, S, K>) {
      return to_answer((*classify_)(state_, x));
    } else if constexpr (classifies<F, S, Volume>) {
      return to_answer((*classify_)(state_, Volume(x)));
    } else {
      (void)x;
      throw std::logic_error(std::string("classify does not take a ") +
                             std::string(volume_kind_name(volume_kind(Volume(K{})))));
    }
  }
  template <class K>
  void many(const K* v, std::size_t n, Answer* a) {
    if constexpr (std::is_invocable_v<const B&, S&, const K*, std::size_t, Visibility*>) {
      // The method's own array form writes verdicts; they are handed on in chunks, large enough
      // that a form which gathers what its first pass leaves across its input sees a whole frame.
      constexpr std::size_t kChunk = 4096;
      Visibility buf[kChunk];
      for (std::size_t i = 0; i < n; i += kChunk) {
        const std::size_t m = n - i < kChunk ? n - i : kChunk;
        (*batch_)(state_, v + i, m, buf);
        for (std::size_t j = 0; j < m; ++j) a[i + j] = buf[j];
      }
    } else {
      for (std::size_t i = 0; i < n; ++i) a[i] = one(v[i]);
    }
  }

  S state_;
  std::shared_ptr<const F> classify_;
  std::shared_ptr<const B> batch_;
};

template <class P>
using prepared_state_t = std::decay_t<std::invoke_result_t<const P&, const CaseFrustum&>>;

template <class P, class F, class B>
Method make_method_impl(MethodInfo info, P prepare, F classify, B batch, bool has_batch) {
  using R = prepared_state_t<P>;
  constexpr bool maybe = unwrap_optional<R>::maybe;
  using S = typename unwrap_optional<R>::type;
  constexpr unsigned taken = kinds_taken<F, S>();
  static_assert(taken != 0, "classify must take (state&, Volume) or (state&, Point/Sphere/Aabb/Obb)");
  if (info.volumes == 0) info.volumes = taken;
  if ((info.volumes & ~taken) != 0) {
    std::string missing;
    for (unsigned k : {kPointKind, kSphereKind, kAabbKind, kObbKind})
      if ((info.volumes & k) && !(taken & k)) missing += (missing.empty() ? "" : ", ") + std::string(volume_kind_name(k));
    throw std::invalid_argument("method '" + info.name + "' declares volume kind(s) " + missing +
                                " that its classify does not take");
  }
  if constexpr (answers_two_way<F, S>()) info.three_way = false;
  auto cls = std::make_shared<const F>(std::move(classify));
  auto bat = std::make_shared<const B>(std::move(batch));
  Method::Prepare prep = [prepare = std::move(prepare), cls, bat](const CaseFrustum& f) -> std::unique_ptr<PreparedFrustum> {
    if constexpr (maybe) {
      auto s = prepare(f);
      if (!s) return nullptr;
      return std::make_unique<Prepared<S, F, B>>(std::move(*s), cls, bat);
    } else {
      return std::make_unique<Prepared<S, F, B>>(prepare(f), cls, bat);
    }
  };
  return Method(std::move(info), std::move(prep), has_batch);
}

}  // namespace detail

/// A two-phase method: `prepare(const CaseFrustum&)` returns the state S (or std::optional<S>),
/// `classify(S&, const K&)` answers for one volume (see the top of this file).
template <class P, class F>
Method make_method(MethodInfo info, P prepare, F classify) {
  return detail::make_method_impl(std::move(info), std::move(prepare), std::move(classify), detail::NoBatch{}, false);
}

/// A two-phase method with an array form: `batch(S&, const K* volumes, std::size_t n,
/// Visibility* verdicts)` for the kinds it takes (other kinds go through classify one by one).
template <class P, class F, class B>
Method make_method(MethodInfo info, P prepare, F classify, B batch) {
  return detail::make_method_impl(std::move(info), std::move(prepare), std::move(classify), std::move(batch), true);
}

/// A one-phase method: `classify(const CaseFrustum&, const K&)` does everything per volume (it
/// is prepared by keeping a copy of the frustum).
template <class F>
Method make_method(MethodInfo info, F classify) {
  auto keep = [](const CaseFrustum& f) { return f; };
  auto cls = [classify = std::move(classify)](const CaseFrustum& f, const auto& v) -> decltype(classify(f, v)) {
    return classify(f, v);
  };
  return detail::make_method_impl(std::move(info), keep, std::move(cls), detail::NoBatch{}, false);
}

}  // namespace cullproof
