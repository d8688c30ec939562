// OFF mesh reader for the scene simulator (the real meshes of Debian's libcgal-demo data).
//
// Format (Geomview OFF, as CGAL writes it): an optional header line "OFF" (the counts may follow
// on the same line), '#' comments, then "nv nf ne", nv vertex lines (the first three numbers are
// x y z; anything after, e.g. a colour, is ignored), nf face lines "k i0 .. ik-1" (anything after
// the k indices, e.g. a colour, is ignored). Faces are fan-triangulated. Every error names the
// file and the line; nothing is repaired or dropped.
#include "cullproof/sim/scene.hpp"

#include "cullproof/io/case_io.hpp"
#include "cullproof/io/limits.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <system_error>

namespace cullproof::sim {

MeshError::MeshError(std::string file, int line, const std::string& problem)
    : std::runtime_error(printable_text(file) + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " +
                         printable_text(problem)),
      file_(std::move(file)),
      line_(line) {}

std::filesystem::path default_mesh_dir() {
  if (const char* d = std::getenv("CULLPROOF_MESH_DIR"); d && *d) return d;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return std::filesystem::path(x) / "cullproof" / "meshes";
  if (const char* h = std::getenv("HOME"); h && *h) return std::filesystem::path(h) / ".cache" / "cullproof" / "meshes";
  return std::filesystem::path(".cache") / "cullproof" / "meshes";
}

namespace {

// Splits a line into whitespace-separated tokens, dropping a '#' comment.
void tokens(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  if (const auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    std::size_t j = i;
    while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
    if (j > i) out.push_back(line.substr(i, j - i));
    i = j;
  }
}

template <class T>
bool parse_number(std::string_view s, T& v) {
  const char* b = s.data();
  const char* e = s.data() + s.size();
  if (b != e && *b == '+') ++b;
  const auto r = std::from_chars(b, e, v);
  return r.ec == std::errc() && r.ptr == e;
}

}  // namespace

Mesh read_off(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::string text;
  try {
    text = read_file_limited(file, kMaxMeshFileBytes, "a mesh file");
    check_line_lengths(text, kMaxMeshLineBytes, "a mesh file");
  } catch (const InputLimitError& e) {
    throw MeshError(name, e.line(), e.what());
  } catch (const std::system_error& e) {
    throw MeshError(name, 0, "cannot read the mesh file: " + e.code().message());
  }

  Mesh mesh;
  std::size_t pos = 0;
  int line_no = 0;
  std::vector<std::string_view> tok;
  // Next line with at least one token; false at the end of the file.
  auto next = [&]() -> bool {
    while (pos < text.size()) {
      const std::size_t end = text.find('\n', pos);
      const std::size_t stop = end == std::string::npos ? text.size() : end;
      std::string_view line(text.data() + pos, stop - pos);
      pos = end == std::string::npos ? text.size() : end + 1;
      ++line_no;
      tokens(line, tok);
      if (!tok.empty()) return true;
    }
    return false;
  };

  if (!next()) throw MeshError(name, line_no, "empty file (expected an OFF header)");
  std::size_t first = 0;
  if (tok[0].size() >= 3 && tok[0].substr(tok[0].size() - 3) == "OFF") {
    if (tok[0] != "OFF")
      throw MeshError(name, line_no, "unsupported OFF variant '" + std::string(tok[0]) + "' (only plain OFF)");
    if (tok.size() > 1) {
      first = 1;  // "OFF nv nf ne" on one line
    } else if (!next()) {
      throw MeshError(name, line_no, "missing the counts line");
    }
  }
  long long nv = -1, nf = -1;
  if (tok.size() < first + 2 || !parse_number(tok[first], nv) || !parse_number(tok[first + 1], nf) || nv < 0 ||
      nf < 0)
    throw MeshError(name, line_no, "expected the counts 'vertices faces edges'");
  if (nv > (1ll << 31) || nf > (1ll << 31)) throw MeshError(name, line_no, "counts too large");
  // A vertex line takes at least 6 bytes ("0 0 0\n"), a face line 8 ("3 0 1 2\n"): memory for more
  // than the rest of the file can hold would be set aside for a file that is then found truncated.
  mesh.vertices.reserve(std::min(static_cast<std::size_t>(nv), (text.size() - pos) / 6));
  for (long long i = 0; i < nv; ++i) {
    if (!next()) throw MeshError(name, line_no, "truncated: expected " + std::to_string(nv) + " vertices, found " + std::to_string(i));
    float c[3];
    if (tok.size() < 3) throw MeshError(name, line_no, "vertex " + std::to_string(i) + ": expected x y z");
    for (int k = 0; k < 3; ++k) {
      if (!parse_number(tok[static_cast<std::size_t>(k)], c[k]) || !std::isfinite(c[k]))
        throw MeshError(name, line_no, "vertex " + std::to_string(i) + ": coordinate '" +
                                           std::string(tok[static_cast<std::size_t>(k)]) + "' is not a finite number");
    }
    mesh.vertices.emplace_back(c[0], c[1], c[2]);
  }
  mesh.triangles.reserve(std::min(static_cast<std::size_t>(nf), (text.size() - pos) / 8));
  for (long long f = 0; f < nf; ++f) {
    if (!next()) throw MeshError(name, line_no, "truncated: expected " + std::to_string(nf) + " faces, found " + std::to_string(f));
    long long k = 0;
    if (!parse_number(tok[0], k) || k < 3)
      throw MeshError(name, line_no, "face " + std::to_string(f) + ": vertex count '" + std::string(tok[0]) + "' (need >= 3)");
    if (static_cast<long long>(tok.size()) < k + 1)
      throw MeshError(name, line_no, "face " + std::to_string(f) + ": expected " + std::to_string(k) + " indices");
    std::uint32_t idx[3] = {0, 0, 0};
    for (long long m = 0; m < k; ++m) {
      long long v = -1;
      if (!parse_number(tok[static_cast<std::size_t>(m + 1)], v) || v < 0 || v >= nv)
        throw MeshError(name, line_no, "face " + std::to_string(f) + ": vertex index '" +
                                           std::string(tok[static_cast<std::size_t>(m + 1)]) + "' out of range [0, " +
                                           std::to_string(nv) + ")");
      if (m == 0) idx[0] = static_cast<std::uint32_t>(v);
      else if (m == 1) idx[1] = static_cast<std::uint32_t>(v);
      else {
        idx[2] = static_cast<std::uint32_t>(v);
        mesh.triangles.push_back({idx[0], idx[1], idx[2]});
        idx[1] = idx[2];
      }
    }
    ++mesh.polygons;
  }
  return mesh;
}

}  // namespace cullproof::sim
