// The registry of case distributions: each one's name, description, membership of the lists
// ("all-generic", "all-hard", the test helper's default) and generator, in one table entry; and
// drawing a case, a frame or a camera path of one by (seed, index).
#include "blocks.hpp"

#include "cullproof/core/certified.hpp"
#include "cullproof/core/splitmix.hpp"

#include <memory>
#include <stdexcept>

namespace cullproof::gen {

using namespace detail;

namespace {

GenCase camera_path_case() {
  const CameraPath p = *camera_path();
  return path_case(p, std::size_t(pick(int(kPathFrames))), std::size_t(pick(int(kPathObjects))));
}

struct Entry {
  Distribution d;
  const char* name;  ///< stable kebab-case name
  const char* text;  ///< one line on what it generates
  bool generic;      ///< in "all-generic", the campaign's default
  int hard_rank;     ///< its place in "all-hard" (1 first), 0: not a hard family
  bool overflows;    ///< float sums overflow on it: left out of the test helper's default
  GenCase (*make)(); ///< one case (its draws: blocks.hpp)
  /// Drawn in frames of kFrameCases cases that share the frustum: a generic camera and a volume
  /// about it (generic_case), or the contact family's frame and a volume touching it.
  bool framed = false;
};

// "all" is this table's order. A case's stream is keyed on the enumerator's value, so a new
// distribution takes a new enumerator at the end of the enum and an entry here.
constexpr Entry kDistributions[] = {
    {Distribution::uniform, "uniform", "volumes of all sizes anywhere around the frustum", true, 0, false,
     [] { return generic_case(Distribution::uniform); }, true},
    {Distribution::near_boundary, "near-boundary", "within a few box sizes of a frustum face", true, 0, false,
     [] { return generic_case(Distribution::near_boundary); }, true},
    {Distribution::corner, "corner", "near frustum edges and corners, where n/p tests err (Assarsson & Moller fig. 2)",
     true, 10, false, [] { return generic_case(Distribution::corner); }, true},
    {Distribution::enclosing, "enclosing", "volumes about as large as the frustum, often containing it", true, 0, false,
     [] { return generic_case(Distribution::enclosing); }, true},
    {Distribution::tiny_huge, "tiny-huge", "sizes from 1e-7 to 10 times the frustum", true, 0, false,
     [] { return generic_case(Distribution::tiny_huge); }, true},
    {Distribution::degenerate, "degenerate", "flat, segment and point boxes, zero-radius spheres, points", true, 6, false,
     [] { return generic_case(Distribution::degenerate); }, true},
    {Distribution::touch, "touch", "exactly touching a plane at a face, an edge or a vertex (exact values)", false, 1,
     false, [] { return touch_case(false); }},
    {Distribution::ulp, "ulp", "touching, then moved 1 ulp in or out", false, 2, false, [] { return touch_case(true); }},
    {Distribution::far_offset, "far-offset", "camera and small volumes at world coordinates 1e5 to 1e7", false, 3, false,
     far_offset_case},
    {Distribution::tiny_near, "tiny-near", "near 1e-4..1e-2, far 1e3..1e7, end-to-end from the float32 matrix", false, 4,
     false, tiny_near_case},
    {Distribution::reversed_infinite, "reversed-infinite", "reversed-Z and infinite far, both depth ranges", false, 5,
     false, reversed_infinite_case},
    {Distribution::extreme_fov, "extreme-fov", "fov 0.01..179.9 degrees, aspect 1e-3..1e3", false, 7, false,
     extreme_fov_case},
    {Distribution::ill_conditioned, "ill-conditioned", "planes scaled by huge/tiny factors, skewed OBB axes", false, 8,
     false, ill_conditioned_case},
    {Distribution::rod, "rod", "long thin boxes crossing the frustum with no corner inside", false, 9, false, rod_case},
    {Distribution::contact, "contact",
     "float-exact contact: flat boxes in a face, boxes, points and spheres touching faces, edges and corners", true, 0,
     false, contact_case, true},
    {Distribution::camera_path, "camera-path",
     "a camera moving past fixed volumes (still, translating, turning, zooming), frame by frame", true, 0, false,
     camera_path_case},
    {Distribution::huge, "huge",
     "coordinates, extents, radii, plane coefficients and matrix entries up to FLT_MAX, where float sums overflow",
     false, 11, true, huge_case},
    {Distribution::subnormal, "subnormal",
     "subnormal sizes, distances to a face, plane coefficients and matrix entries, where products underflow", false, 12,
     false, subnormal_case},
};

// Every enumerator has exactly one entry, and the hard ranks are 1..n without a gap.
constexpr bool registry_complete() {
  constexpr int n = int(sizeof(kDistributions) / sizeof(kDistributions[0]));
  if (n != kDistributionCount) return false;
  int hard = 0;
  for (int v = 0; v < n; ++v) {
    int seen = 0;
    for (const Entry& e : kDistributions) seen += int(e.d) == v;
    if (seen != 1) return false;
    hard += kDistributions[v].hard_rank != 0;
  }
  for (int r = 1; r <= hard; ++r) {
    int seen = 0;
    for (const Entry& e : kDistributions) seen += e.hard_rank == r;
    if (seen != 1) return false;
  }
  return true;
}
static_assert(registry_complete(), "every Distribution needs one entry in kDistributions (and kDistributionCount)");

const Entry* find(Distribution d) noexcept {
  for (const Entry& e : kDistributions)
    if (e.d == d) return &e;
  return nullptr;
}

const Entry& entry(Distribution d) {
  if (const Entry* e = find(d)) return *e;
  throw std::invalid_argument("not a distribution: " + std::to_string(int(d)));
}

}  // namespace

std::string_view to_string(Distribution d) noexcept {
  const Entry* e = find(d);
  return e ? e->name : "invalid";
}

std::string_view describe(Distribution d) noexcept {
  const Entry* e = find(d);
  return e ? e->text : "";
}

std::vector<Distribution> generic_distributions() {
  std::vector<Distribution> out;
  for (const Entry& e : kDistributions)
    if (e.generic) out.push_back(e.d);
  return out;
}

std::vector<Distribution> hard_distributions() {
  std::vector<Distribution> out;
  for (int r = 1;; ++r) {
    const std::size_t before = out.size();
    for (const Entry& e : kDistributions)
      if (e.hard_rank == r) out.push_back(e.d);
    if (out.size() == before) return out;
  }
}

std::vector<Distribution> no_overflow_distributions() {
  std::vector<Distribution> out;
  for (const Entry& e : kDistributions)
    if (!e.overflows) out.push_back(e.d);
  return out;
}

std::vector<Distribution> parse_distributions(std::string_view name) {
  if (name == "all") {
    std::vector<Distribution> all;
    for (const Entry& e : kDistributions) all.push_back(e.d);
    return all;
  }
  if (name == "all-hard") return hard_distributions();
  if (name == "all-generic") return generic_distributions();
  for (const Entry& e : kDistributions)
    if (name == e.name) return {e.d};
  std::string known = "all, all-generic, all-hard";
  for (const Entry& e : kDistributions) known += std::string(", ") + e.name;
  throw std::invalid_argument("unknown distribution '" + std::string(name) + "' (known: " + known + ")");
}

rc::Gen<GenCase> case_of(Distribution d) {
  // Fixed size: the building blocks draw from their whole ranges whatever size RapidCheck is at
  // (its inRange narrows with size, which at size 0 would pin every draw to its lower bound).
  return rc::gen::resize(100, rc::gen::exec(entry(d).make));
}

rc::Gen<CaseFrustum> any_frustum() {
  return rc::gen::resize(100, rc::gen::exec([] { return realize(generic_camera()); }));
}

rc::Gen<GenCase> exact_touching() { return rc::gen::resize(100, rc::gen::exec(exact_touching_case)); }
rc::Gen<GenCase> exact_containment() { return rc::gen::resize(100, rc::gen::exec(exact_containment_case)); }
rc::Gen<GenCase> exact_degenerate() { return rc::gen::resize(100, rc::gen::exec(exact_degenerate_case)); }

rc::Gen<GenCase> any_case() {
  // Every distribution and every exact family equally likely; a case shrinks towards cases of
  // the first source (uniform). Fixed size, as case_of: the source is drawn from the whole range.
  const std::vector<Distribution> all = parse_distributions("all");
  const int sources = int(all.size()) + 3;
  return rc::gen::resize(100, rc::gen::mapcat(rc::gen::inRange(0, sources), [all](int k) {
    if (k < int(all.size())) return case_of(all[std::size_t(k)]);
    if (k == int(all.size())) return exact_touching();
    if (k == int(all.size()) + 1) return exact_containment();
    return exact_degenerate();
  }));
}

namespace {

// One independent stream per (seed, distribution, index): splitmix64 of the three.
std::uint64_t draw_key(std::uint64_t seed, Distribution d, std::uint64_t index) {
  return splitmix64(splitmix64(splitmix64(seed) ^ std::uint64_t(d)) ^ index);
}

// Frame cameras are drawn from a stream apart from the cases' volumes ("camera" in ASCII).
constexpr std::uint64_t kCameraStream = 0x63616d657261ull;

// A framed family's frame, drawn from the frame's key: the frustum and the placement its cases
// share (a generic family's camera), or the contact family's frame.
struct FrameCamera {
  CaseFrustum frustum;
  Placement placement;
  ContactFrame contact;
};

FrameCamera frame_camera(Distribution d, std::uint64_t seed, std::uint64_t frame, std::vector<std::int64_t>* log) {
  FastDraw scope(draw_key(seed ^ kCameraStream, d, frame), log);
  FrameCamera out;
  if (d == Distribution::contact) {
    out.contact = contact_frame();
    return out;
  }
  const Camera cam = generic_camera();
  out.placement = placement_for(cam);
  out.frustum = realize(cam);
  return out;
}

// A framed family's case `index` on its frame: the volume drawn from the case's key.
void framed_case(Distribution d, std::uint64_t seed, std::uint64_t index, const FrameCamera& fc, GenCase& out,
                 std::vector<std::int64_t>* log) {
  FastDraw scope(draw_key(seed, d, index), log);
  if (d == Distribution::contact) {
    out = contact_volume(fc.contact);
    return;
  }
  out.frustum = fc.frustum;
  out.volume = generic_volume(d, fc.placement);
  out.scene_size = fc.placement.size;
}

// The case's own draw, keyed by (seed, d, index), off RapidCheck; its values logged when asked. A
// framed family's camera comes from its frame's key, the volume from the case's: the same draws,
// in the same order, as generic_case makes.
GenCase fast_case(Distribution d, std::uint64_t seed, std::uint64_t index, std::vector<std::int64_t>* log = nullptr) {
  const Entry& e = entry(d);
  if (e.framed) {
    GenCase g;
    framed_case(d, seed, index, frame_camera(d, seed, index / kFrameCases, log), g, log);
    return g;
  }
  FastDraw scope(draw_key(seed, d, index), log);
  return e.make();
}

CameraPath fast_path(std::uint64_t seed, std::uint64_t path, std::vector<std::int64_t>* log = nullptr) {
  FastDraw scope(draw_key(seed, Distribution::camera_path, path), log);
  return make_camera_path();
}

}  // namespace

GenCase draw_case(Distribution d, std::uint64_t seed, std::uint64_t index) {
  if (d == Distribution::camera_path) {
    const PathIndex at = path_index(index);
    return path_case(draw_path(seed, at.path), at.frame, at.object);
  }
  return fast_case(d, seed, index);
}

rc::Shrinkable<GenCase> draw(Distribution d, std::uint64_t seed, std::uint64_t index) {
  // The fast draw's values, replayed inside RapidCheck: the root is draw_case's case.
  auto values = std::make_shared<std::vector<std::int64_t>>();
  if (d == Distribution::camera_path) {
    // The case's path, replayed: its shrinks are simpler paths, seen at the same frame and object.
    const PathIndex at = path_index(index);
    fast_path(seed, at.path, values.get());
    return rc::gen::exec([values, at] {
      Replay replay(*values);
      return path_case(make_camera_path(), at.frame, at.object);
    })(rc::Random(), 100);
  }
  fast_case(d, seed, index, values.get());
  const Entry& e = entry(d);
  return rc::gen::exec([values, &e] {
    Replay replay(*values);
    return e.make();
  })(rc::Random(), 100);
}

void draw_cases(Distribution d, std::uint64_t seed, std::uint64_t first, std::size_t count, GenCase* out) {
  const Entry& e = entry(d);
  if (!e.framed) {
    for (std::size_t k = 0; k < count; ++k) out[k] = draw_case(d, seed, first + k);
    return;
  }
  // The frame's camera, its frustum and placement once per frame.
  std::uint64_t frame = ~std::uint64_t(0);
  FrameCamera fc;
  for (std::size_t k = 0; k < count; ++k) {
    const std::uint64_t index = first + k;
    if (index / kFrameCases != frame) {
      frame = index / kFrameCases;
      fc = frame_camera(d, seed, frame, nullptr);
    }
    framed_case(d, seed, index, fc, out[k], nullptr);
  }
}

std::size_t cases_per_frame(Distribution d) { return entry(d).framed ? kFrameCases : 1; }

CameraPath draw_path(std::uint64_t seed, std::uint64_t path) { return fast_path(seed, path); }

Frame draw_frame(Distribution d, std::uint64_t seed, std::uint64_t index, std::size_t size, unsigned kinds) {
  // Frames are drawn from streams apart from the cases' ("frame" in ASCII mixed into the seed).
  constexpr std::uint64_t kFrameStream = 0x6672616d65ull;
  if (kinds == 0) throw std::invalid_argument("draw_frame: no volume kind asked for");
  // Up to 64 draws per volume asked for: a kind the distribution rarely makes (points) still
  // fills the frame; one it never makes leaves it short, which the caller sees.
  const std::size_t attempts = 64 * size;
  Frame out;
  if (d == Distribution::camera_path) {
    const CameraPath p = draw_path(seed ^ kFrameStream, index / kPathFrames);
    out.frustum = p.frames[index % kPathFrames];
    out.continues = index % kPathFrames != 0;
    for (const Volume& v : p.objects)
      if ((kinds & volume_kind(v)) && out.volumes.size() < size) out.volumes.push_back(v);
    return out;
  }
  if (entry(d).framed) {
    // One camera, then volumes of the distribution around its frustum: an engine's frame.
    FastDraw scope(draw_key(seed ^ kFrameStream, d, index));
    const Camera cam = generic_camera();
    const Placement p = placement_for(cam);
    out.frustum = realize(cam);
    for (std::size_t k = 0; k < attempts && out.volumes.size() < size; ++k) {
      Volume v = generic_volume(d, p);
      if (kinds & volume_kind(v)) out.volumes.push_back(std::move(v));
    }
  } else {
    // The hard families build frustum and volume together: the first case's frustum with the
    // volumes of the cases that follow it.
    for (std::uint64_t k = 0; k < attempts && out.volumes.size() < size; ++k) {
      GenCase c = draw_case(d, seed ^ kFrameStream, index * attempts + k);
      if (k == 0) out.frustum = c.frustum;
      if (kinds & volume_kind(c.volume)) out.volumes.push_back(std::move(c.volume));
    }
  }
  return out;
}

double case_scale(const CaseFrustum& f, const Volume& v) {
  // M: the largest coordinate magnitude of the volume (centre plus extent), in double.
  const double m = volume_magnitude(v);
  // Per plane, the magnitude of what its evaluation rounds, in distance units:
  // (A M + a_d + 2^-124) / |n|, with a the bound on the coefficients (|plane| for planes;
  // |r4| + |rk| for a matrix, whose float extraction rounds that much: see
  // cullproof/core/certified.hpp; halved together with the plane where the extraction halves the
  // rows). 2^-124 is the underflow: a product that underflows errs by up to 2^-150 absolutely,
  // as much as the relative rounding u = 2^-24 of a magnitude 2^-126, four products per plane.
  // In double: the bounds are finite floats (at most FLT_MAX each), so nothing here overflows.
  const CertifiedFrustum::Data c = certify(f).data();
  double s = m;
  for (int k = 0; k < kPlaneCount; ++k) {
    const Plane& p = c.planes[k];
    if (p.is_degenerate()) continue;
    const double len = glm::length(glm::dvec3(p.n));
    const double a = double(c.bound[k].x) + double(c.bound[k].y) + double(c.bound[k].z);
    s = std::max(s, (a * m + double(c.bound[k].w) + 0x1p-124) / len);
  }
  return s > 0.0 ? s : 1.0;
}

}  // namespace cullproof::gen
