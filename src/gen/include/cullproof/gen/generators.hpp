// Case generators shared by the property tests and the verification run (`cullproof verify`).
//
// Every family is built from valid constructions, aimed at the cases it names instead of
// filtering, and draws each of its choices as one integer in a range. A property test takes it as
// a RapidCheck rc::Gen (shrinking for free). The campaign draws case i of a distribution directly
// from a counter-based stream keyed by (seed, distribution, i) (draw_case: no RapidCheck, no
// allocation per value, any index on any thread), so the same seed gives the same cases; to
// shrink a mismatch it replays that case's values inside RapidCheck (draw), whose root is the
// same case.
#pragma once

#include "cullproof/core/frustum_build.hpp"
#include "cullproof/core/geometry.hpp"

#include <rapidcheck.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace cullproof::gen {

/// Named case distributions; what each generates, its name and the lists it belongs to are its
/// entry in the registry (src/gen/distributions.cpp): describe(), to_string(),
/// generic_distributions(), hard_distributions(). A case's stream is keyed on the enumerator's
/// value, so a new distribution is added at the end (and kDistributionCount raised): the cases of
/// the others stay the same.
enum class Distribution {
  uniform,
  near_boundary,
  corner,
  enclosing,
  tiny_huge,
  degenerate,
  touch,
  ulp,
  far_offset,
  tiny_near,
  reversed_infinite,
  extreme_fov,
  ill_conditioned,
  rod,
  camera_path,
  contact,
  huge,
  subnormal,
};
/// How many distributions there are (the registry is checked against it when it compiles).
inline constexpr int kDistributionCount = 18;

/// Stable kebab-case name ("near-boundary", "far-offset", ...).
std::string_view to_string(Distribution d) noexcept;
/// One line on what the distribution generates.
std::string_view describe(Distribution d) noexcept;
/// Parses a name; "all" and "all-hard" expand to several. Throws std::invalid_argument listing
/// the known names.
std::vector<Distribution> parse_distributions(std::string_view name);
/// The generic distributions (the campaign's default).
std::vector<Distribution> generic_distributions();
/// The hard-case families.
std::vector<Distribution> hard_distributions();
/// Every distribution but `huge`, in "all" order: those on which the float evaluations of a plane
/// test do not overflow. The test helper's default (cullproof/gtest/gtest.hpp): a float culler that
/// makes no provision for overflow, such as a plain n/p-vertex test, breaks a conservative claim
/// on `huge`, which is therefore asked for by name.
std::vector<Distribution> no_overflow_distributions();

/// A generated case: the frustum as a culler sees it (and the matrix, for end-to-end cases), a
/// volume, and the frustum's size for relative distances.
struct GenCase {
  CaseFrustum frustum;
  Volume volume;
  double scene_size = 1.0;  ///< diameter of the frustum's bounded part (placement frustum)
};

/// A random case of the distribution.
rc::Gen<GenCase> case_of(Distribution d);
/// A random frustum of the generic kinds (perspective, off-axis, orthographic, reversed-Z,
/// infinite far; as planes or as a matrix).
rc::Gen<CaseFrustum> any_frustum();

/// The exact families: cases on truncated pyramids with integer corners (perspective, off-axis,
/// sheared, orthographic; moved to the world by a signed axis permutation and, half the time, an
/// integer shift), given as planes with small integer coefficients, some scaled by a power of
/// two, so that points built from the corners with dyadic weights lie exactly on the boundary.
/// Aimed at methods that claim exactness (the oracle and its independent method). Not
/// distributions: `cullproof verify` does not draw them.
///  - exact_touching: at a corner, an edge point or a face point, a box with a corner there, an
///    OBB with a vertex there (rotated, by any rotation or by whole-degree angles that leave its
///    axes a rounding off the coordinate axes; or with small integer axes, neither orthonormal
///    nor independent), a sphere with an extreme point there, or the point; then each
///    coordinate moved by 0 to 2 ulps.
///  - exact_containment: the frustum's bounding box (grown, shrunk or as is, then nudged by ulps),
///    small boxes, balls from radius 0 to containing the frustum and rotated boxes about its
///    centroid, and a corner as a point box.
///  - exact_degenerate: in four cases in ten one plane is special: the far plane infinite
///    (0, 0, 0, 1), a plane that holds nowhere (0, 0, 0, -1), a plane flipped (often an empty or
///    unbounded frustum) or the zero plane (0 >= 0 holds everywhere); the volume is a flat,
///    segment or point box or a zero-radius sphere on the boundary (nudged by ulps), or an
///    exact_touching volume.
rc::Gen<GenCase> exact_touching();
rc::Gen<GenCase> exact_containment();
rc::Gen<GenCase> exact_degenerate();
/// Any case: a case of any distribution (parse_distributions("all"), `huge` included) or of an
/// exact family, each source equally likely. rc::Arbitrary<GenCase> (cullproof/gen/arbitrary.hpp).
rc::Gen<GenCase> any_case();

/// The generic-camera families (uniform, near-boundary, corner, enclosing, tiny-huge, degenerate)
/// and contact come in frames, as an engine culls: cases [kFrameCases f, kFrameCases (f + 1))
/// share frame f's frustum, and each draws its own volume against it. A case is drawn exactly as
/// one alone would be (a generic camera, then a volume of the family about it; a contact frame,
/// then a volume touching it); only cases of one frame share the frustum. Every other family has
/// one case per frustum.
constexpr std::size_t kFrameCases = 16;
/// kFrameCases for a framed family, 1 for the others (cases_per_frame(camera_path) is 1: its
/// frames are its paths', path_index).
std::size_t cases_per_frame(Distribution d);

/// The campaign's deterministic draw: case `index` of distribution `d` for `seed`. Thread-safe;
/// the same arguments give the same case on every run and thread.
GenCase draw_case(Distribution d, std::uint64_t seed, std::uint64_t index);
/// Cases first .. first + count - 1, as draw_case draws them (a frame's camera drawn once).
void draw_cases(Distribution d, std::uint64_t seed, std::uint64_t first, std::size_t count, GenCase* out);
/// The same case as a Shrinkable for shrinking (value() is draw_case's case; shrinks() its
/// simpler versions, RapidCheck's shrinks of the values it was drawn from). On the thread that
/// uses it only (RapidCheck's generation context is the process's).
rc::Shrinkable<GenCase> draw(Distribution d, std::uint64_t seed, std::uint64_t index);

/// A frame for timing: one frustum and volumes of the distribution against it.
struct Frame {
  CaseFrustum frustum;
  std::vector<Volume> volumes;
  /// The next camera position of the previous frame's path: the same volumes in the same order
  /// (camera-path frames after the first); a frame-coherent method keeps its state into it.
  bool continues = false;
};
/// Frame `index` of distribution `d` for `seed`: up to `size` volumes whose kind is in `kinds`
/// (VolumeKind bits), fewer when the distribution rarely makes that kind. The generic-camera
/// families place every volume around one camera's frustum, as in an engine's frame; the others
/// (the hard families and `contact`), which build frustum and volume together, give the first
/// case's frustum and the volumes of the cases that follow; camera-path frames are the frames of one path in order (index % kPathFrames
/// of path index / kPathFrames), its objects of the kinds asked for. Deterministic; a stream
/// apart from draw()'s cases.
Frame draw_frame(Distribution d, std::uint64_t seed, std::uint64_t index, std::size_t size, unsigned kinds);

/// A camera path: kPathFrames frames of one moving camera (standing still, translating,
/// turning about one of its axes, both at once, or zooming; every frustum kind of any_frustum)
/// and kPathObjects fixed volumes placed about its frusta, so that they cross the boundary as it
/// moves. Case `index` of the camera-path distribution is object `object` of frame `frame` of path
/// `path` (path_index); a frame-coherent method sees the frames of a path in order, the same
/// objects every frame (see cullproof/methods/methods.hpp).
constexpr std::size_t kPathFrames = 8;
constexpr std::size_t kPathObjects = 32;
struct CameraPath {
  std::vector<CaseFrustum> frames;
  std::vector<double> scene_size;  ///< per frame, as GenCase::scene_size
  std::vector<Volume> objects;
  std::string motion;              ///< "still", "translation", "rotation-x" (about the camera's right
                                   ///< axis), "rotation-y" (up), "rotation-z" (view), "general", "zoom"
};
struct PathIndex {
  std::uint64_t path = 0;
  std::size_t frame = 0, object = 0;
};
/// Where case `index` of the camera-path distribution lies (cases run path by path, frame by
/// frame, object by object).
PathIndex path_index(std::uint64_t index) noexcept;
/// The case index of a position on a path.
std::uint64_t path_case_index(const PathIndex& p) noexcept;
/// A random camera path.
rc::Gen<CameraPath> camera_path();
/// Path `path` of the camera-path distribution for `seed` (draw(camera_path, seed, index) is
/// object i.object of frame i.frame of draw_path(seed, i.path), i = path_index(index)).
CameraPath draw_path(std::uint64_t seed, std::uint64_t path);
/// One case of a path.
GenCase path_case(const CameraPath& p, std::size_t frame, std::size_t object);

/// Whether the case is float-exact (docs/semantics.md "Claims": where nothing rounds, nothing is
/// forgiven): nothing a plane test computes on it rounds in float. Decided exactly, in rational
/// arithmetic on the float values:
///  - every plane of the case (for a matrix case, the Gribb-Hartmann row sums the extraction takes
///    are floats, so the planes a culler gets are the exact planes), at every vertex of the volume
///    (the point; the eight corners of an AABB): each product n_i x_i is a float, and so is every
///    sum of two or more of n_0 x_0, n_1 x_1, n_2 x_2, d (every partial sum of any evaluation order);
///  - a sphere: every plane with a nonzero normal has n.n == 1 exactly, and the sums of
///    n_i c_i, d and the radius are floats;
///  - an OBB: its corners c + sum_i (+-h_i u_i) compute exactly (each h_i u_ik and every partial
///    sum is a float) and the plane sums at them are floats; and its projected form does too:
///    n.c + d, each n.u_i, h_i |n.u_i|, their sums, and the centre value minus and plus the
///    projected half-width.
/// On a float-exact case a `conservative` or `exact` claim has no rounding allowance.
bool float_exact(const CaseFrustum& f, const Volume& v);

/// The scale against which rounding tolerances are measured (see Method::tolerance): the largest,
/// over the planes, of what evaluating the plane at the volume rounds, in distance units,
/// (sum_i a_i M + a_d) / |n|, with M the volume's largest coordinate magnitude and a the bound
/// on the plane's coefficients: |plane| for planes given as planes; |r4| + |rk| for a matrix,
/// whose float extraction rounds in proportion to that (so an end-to-end case whose extraction
/// cancels badly, e.g. a tiny near plane, has a large scale). At least M.
double case_scale(const CaseFrustum& f, const Volume& v);

}  // namespace cullproof::gen
