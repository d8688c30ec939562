// My engine's culling system: objects bucketed into a loose grid by their centres, each cell's box
// the union of its objects' boxes; a frame tests the cells, handing each cell's plane mask to its
// objects (a plane the cell lies inside is not tested again). Moving an object moves it between
// cells and refits both cells' boxes. Written against my engine's own types, not cullproof's.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <tuple>
#include <unordered_map>
#include <vector>

namespace my {

struct Vec3 {
  float x, y, z;
};
struct Box {
  Vec3 min, max;
};
/// a x + b y + c z + d >= 0 inside
struct Plane {
  float a, b, c, d;
};
enum class Result { outside, intersecting, inside };

class Grid {
 public:
  /// `refit_on_move` false is the planted bug: a moved object joins its new cell, whose box is
  /// not grown to hold it.
  Grid(const std::vector<std::pair<std::uint32_t, Box>>& objects, float cell_size, bool refit_on_move = true)
      : cell_(cell_size), refit_(refit_on_move) {
    for (const auto& [id, box] : objects) {
      boxes_[id] = box;
      const Key k = key(box);
      cell_of_[id] = k;
      cells_[k].members.push_back(id);
    }
    for (auto& [k, c] : cells_) refit(c);
  }

  void move(std::uint32_t id, const Box& box) {
    boxes_.at(id) = box;
    const Key from = cell_of_.at(id), to = key(box);
    Cell& old_cell = cells_.at(from);
    if (!(from == to)) {
      old_cell.members.erase(std::find(old_cell.members.begin(), old_cell.members.end(), id));
      cells_[to].members.push_back(id);
      cell_of_[id] = to;
    }
    refit(old_cell);
    if (refit_) refit(cells_[to]);
  }

  /// The visible objects with their results, cell by cell.
  void cull(const std::array<Plane, 6>& planes, std::vector<std::pair<std::uint32_t, Result>>& visible) const {
    visible.clear();
    for (const auto& [k, c] : cells_) {
      if (c.members.empty()) continue;
      unsigned mask = 0x3f;
      if (!test(planes, c.box, mask)) continue;
      for (std::uint32_t id : c.members) {
        unsigned m = mask;
        if (!test(planes, boxes_.at(id), m)) continue;
        visible.emplace_back(id, m == 0 ? Result::inside : Result::intersecting);
      }
    }
  }

 private:
  using Key = std::tuple<long long, long long, long long>;
  struct Cell {
    Box box{};
    std::vector<std::uint32_t> members;
  };

  Key key(const Box& b) const {
    auto c = [&](float lo, float hi) { return static_cast<long long>(std::floor((0.5 * lo + 0.5 * hi) / cell_)); };
    return {c(b.min.x, b.max.x), c(b.min.y, b.max.y), c(b.min.z, b.max.z)};
  }

  void refit(Cell& c) const {
    if (c.members.empty()) return;
    c.box = boxes_.at(c.members.front());
    for (std::uint32_t id : c.members) {
      const Box& b = boxes_.at(id);
      c.box.min = {std::min(c.box.min.x, b.min.x), std::min(c.box.min.y, b.min.y), std::min(c.box.min.z, b.min.z)};
      c.box.max = {std::max(c.box.max.x, b.max.x), std::max(c.box.max.y, b.max.y), std::max(c.box.max.z, b.max.z)};
    }
  }

  // The n/p-vertex test against the planes whose bit is set in `mask`: false when one rejects
  // the box; clears the bits of the planes it lies inside.
  static bool test(const std::array<Plane, 6>& planes, const Box& b, unsigned& mask) {
    for (int i = 0; i < 6; ++i) {
      if (!(mask >> i & 1u)) continue;
      const Plane& p = planes[i];
      const float px = p.a > 0 ? b.max.x : b.min.x, py = p.b > 0 ? b.max.y : b.min.y, pz = p.c > 0 ? b.max.z : b.min.z;
      if (p.a * px + p.b * py + p.c * pz + p.d < 0) return false;
      const float nx = p.a > 0 ? b.min.x : b.max.x, ny = p.b > 0 ? b.min.y : b.max.y, nz = p.c > 0 ? b.min.z : b.max.z;
      if (!(p.a * nx + p.b * ny + p.c * nz + p.d < 0)) mask &= ~(1u << i);
    }
    return true;
  }

  float cell_;
  bool refit_;
  std::map<Key, Cell> cells_;
  std::unordered_map<std::uint32_t, Box> boxes_;
  std::unordered_map<std::uint32_t, Key> cell_of_;
};

}  // namespace my
