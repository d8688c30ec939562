// The method registry: every named culling method cullproof runs side by side.
//
// A method is a stable kebab-case name (reports, the corpus and scripts key on it), a one-line
// description, its source (text and section), the claim it makes (shared/CONVENTIONS.md
// "Claims"), the volume kinds it takes, how it treats a volume touching a plane, and a
// classification function. `cullproof methods` prints this table; `cullproof classify` and the
// verification run call `classify`.
#pragma once

#include "cullproof/frustum_build.hpp"
#include "cullproof/geometry.hpp"

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace cullproof {

/// What a method promises (CONVENTIONS "Claims").
enum class Claim {
  certified_conservative,  ///< never a false reject or false inside, rounding included
  certified_exact,         ///< as above, and no other error beyond a proven band
  conservative,            ///< conservative in exact arithmetic; float errors within tolerance
  exact,                   ///< exact in exact arithmetic; float errors within tolerance
  none,                    ///< no promise (heuristic, or a published method under test)
};
/// "certified-conservative", "certified-exact", "conservative", "exact", "none".
std::string_view to_string(Claim c) noexcept;

/// One named method.
struct Method {
  std::string name;         ///< kebab-case, stable (e.g. "pn-vertex")
  std::string description;  ///< one line
  std::string source;       ///< text and section, e.g. "Assarsson & Möller 2000, §3.1"
  Claim claim = Claim::none;
  unsigned volumes = 0;     ///< VolumeKind bits this method takes
  std::string touching;     ///< how a volume touching a plane is classified
  /// For `conservative` / `exact` claims: float errors are allowed only on cases whose exact
  /// distance to the frustum boundary is at most `tolerance` times the case's scale (what the
  /// plane evaluations round, in distance units; gen::case_scale). 0 for certified claims.
  double tolerance = 0.0;
  bool stateful = false;    ///< a frame-coherent culler; classify runs it with a fresh state
  /// A published method under test (its text's claim is checked and may be refuted: reported,
  /// not an error) rather than one of cullproof's own, whose broken claim fails the run.
  bool published = true;
  /// Classifies one volume. Returns std::nullopt when the method does not apply to this frustum
  /// (e.g. the octant test on an asymmetric frustum); the caller leaves it out of its verdicts.
  /// Called only with volume kinds listed in `volumes`.
  std::function<std::optional<Visibility>(const CaseFrustum&, const Volume&)> classify;

  bool takes(const Volume& v) const noexcept { return (volumes & volume_kind(v)) != 0; }
};

/// Every registered method, in a stable order.
const std::vector<Method>& methods();
/// The method with this name, or nullptr.
const Method* find_method(std::string_view name);

namespace detail {
// Each family of methods registers itself from its own file (see src/methods.cpp).
void register_cull_methods(std::vector<Method>& out);   // src/cull/
void register_exact_methods(std::vector<Method>& out);  // src/exact/
void register_certified_methods(std::vector<Method>& out);  // src/certified/
}  // namespace detail

}  // namespace cullproof
