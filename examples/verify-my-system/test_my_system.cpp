// Verifying my culling system: described once in its three phases, then one line per claim.
#include "my_system.hpp"

#include <cullproof/gtest/gtest.hpp>

#include <iostream>

namespace {

// My engine culls by boxes: a volume's enclosing box, in my types.
my::Box box_of(const cullproof::Volume& v) {
  const cullproof::Aabb b = cullproof::enclosing_box(v);
  return {{b.min.x, b.min.y, b.min.z}, {b.max.x, b.max.y, b.max.z}};
}

cullproof::Visibility to_verdict(my::Result r) {
  return r == my::Result::inside ? cullproof::Visibility::inside : cullproof::Visibility::intersecting;
}

cullproof::System my_system(bool bug) {
  cullproof::SystemInfo info;
  info.name = bug ? "my-grid-with-a-bug" : "my-grid";
  info.description = "loose grid of 16-unit cells, plane masks from cells to their objects";
  info.claim = cullproof::Claim::conservative;
  info.tolerance = 1e-6;  // my plane tests round: errors allowed within 1e-6 of the scale
  return cullproof::make_system(
      info,
      [bug](const cullproof::Scene& scene) {  // build
        std::vector<std::pair<std::uint32_t, my::Box>> objects;
        for (const cullproof::SceneObject& o : scene.objects) objects.emplace_back(o.id, box_of(o.world));
        return my::Grid(objects, 16.0f, !bug);
      },
      [](my::Grid& grid, const std::vector<cullproof::SceneObject>& moved) {  // objects that moved
        for (const cullproof::SceneObject& o : moved) grid.move(o.id, box_of(o.world));
      },
      [](my::Grid& grid, const cullproof::CullView& view, cullproof::VisibleSet& out) {  // a frame
        std::array<my::Plane, 6> planes;
        for (int i = 0; i < 6; ++i) {
          const cullproof::Plane& p = view.frustum.planes[i];
          planes[i] = {p.n.x, p.n.y, p.n.z, p.d};
        }
        std::vector<std::pair<std::uint32_t, my::Result>> visible;
        grid.cull(planes, visible);
        for (const auto& [id, r] : visible) out.indices.push_back(id), out.verdicts.push_back(to_verdict(r));
      });
}

TEST(MySystem, HoldsItsClaim) { EXPECT_TRUE(cullproof::testing::system_holds(my_system(false))); }

// What a failure looks like: the planted bug (a cell not refitted when an object moves into it)
// is refuted, and the message shows the run, the frame and the object. Asserted here so that the
// example's own test suite passes; in your tests, EXPECT_TRUE(system_holds(...)) prints this and
// fails.
TEST(MySystemWithABug, IsCaught) {
  const ::testing::AssertionResult r = cullproof::testing::system_holds(my_system(true));
  EXPECT_FALSE(r);
  std::cout << r.message() << "\n";
}

}  // namespace
